/* The self-collision queries' kept candidates (self_near.h). */
#include "self_near.h"
#include <float.h>
#include <math.h>
#include <string.h>
#include "par.h"
#include "self_broad.h"

wc_status wc_self_near_alloc(wc_self* sc) {
    size_t nq = (size_t)sc->n + (size_t)sc->n_edges;
    sc->near_gap = (1.0 + WC_SELF_NEAR_SLACK) * sc->thickness;
    sc->near_kept = sc->near_use = sc->near_full_use = sc->near_later = 0;
    sc->near_anchor = WC_NEW(&sc->alloc, double, 6 * (size_t)sc->n + 6);
    sc->near_cand = WC_NEW(&sc->alloc, int, nq * WC_SELF_NEAR_CAP + 1);
    sc->near_count = WC_NEW(&sc->alloc, int, nq + 1);
    sc->near_ahead = WC_NEW(&sc->alloc, double, 3 * (size_t)sc->n + 3);
    return sc->near_anchor && sc->near_cand && sc->near_count && sc->near_ahead ? WC_OK : WC_ERROR_OUT_OF_MEMORY;
}

void wc_self_near_free(wc_self* sc) {
    wc_free(&sc->alloc, sc->near_anchor);
    wc_free(&sc->alloc, sc->near_cand);
    wc_free(&sc->alloc, sc->near_count);
    wc_free(&sc->alloc, sc->near_ahead);
    sc->near_anchor = sc->near_ahead = NULL;
    sc->near_cand = sc->near_count = NULL;
}

int wc_self_near_covers(const wc_self* sc, const double* x0, const double* x1, double r) {
    if (!sc->near_kept || sc->near_off) return 0;
    double A[3] = {-INFINITY, -INFINITY, -INFINITY}, B[3] = {INFINITY, INFINITY, INFINITY}, scale = 0.0;
    const double* an = sc->near_anchor;
    for (int i = 0; i < sc->n; ++i)
        for (int k = 0; k < 3; ++k) {
            double lo = an[6 * i + k], hi = an[6 * i + 3 + k], v0 = x0[3 * i + k], v1 = x1[3 * i + k];
            double a = (v0 > v1 ? v0 : v1) - hi, b = (v0 < v1 ? v0 : v1) - lo;
            A[k] = a > A[k] ? a : A[k];
            B[k] = b < B[k] ? b : B[k];
            double s = fabs(v0) > fabs(v1) ? fabs(v0) : fabs(v1);
            s = fabs(lo) > s ? fabs(lo) : s;
            s = fabs(hi) > s ? fabs(hi) : s;
            scale = s > scale ? s : scale;
        }
    double T = 0.0;
    for (int k = 0; k < 3; ++k)
        if (0.5 * (A[k] - B[k]) > T) T = 0.5 * (A[k] - B[k]);
    if (!(T < INFINITY)) return 0;   /* non-finite positions: the trees decide */
    double round = 64.0 * DBL_EPSILON * (scale + sc->near_gap);
    return 2.0 * T + r + round <= sc->near_gap;
}

/* Gathering: each query's candidates less those the adjacency rules exclude. */
typedef struct gather_ctx {
    const wc_self* sc;
    const wc_model* m;
    int query;      /* vertex queries: the vertex */
    int a, b;       /* edge queries: the edge's particles */
    int* out;       /* the query's WC_SELF_NEAR_CAP slots */
    int count;
} gather_ctx;

static int keep(gather_ctx* c, int element) {
    if (c->count == WC_SELF_NEAR_CAP) {
        c->count = -1;   /* too many: this query walks the tree */
        return 1;
    }
    c->out[c->count++] = element;
    return 0;
}

static int gather_tri(void* user, int t) {
    gather_ctx* c = (gather_ctx*)user;
    const wc_self* sc = c->sc;
    const int* tv = c->m->tris + 3 * t;
    int i = c->query;
    if (wc_self_linked(sc, i, tv[0]) || wc_self_linked(sc, i, tv[1]) || wc_self_linked(sc, i, tv[2])) return 0;
    const unsigned char* tg = sc->tangled;
    if (tg[i] && tg[tv[0]] && tg[tv[1]] && tg[tv[2]]) return 0;
    return keep(c, t);
}

static int gather_edge(void* user, int f) {
    gather_ctx* c = (gather_ctx*)user;
    const wc_self* sc = c->sc;
    int a0 = c->a, a1 = c->b, b0 = sc->edges[2 * f], b1 = sc->edges[2 * f + 1];
    if (wc_self_linked(sc, a0, b0) || wc_self_linked(sc, a0, b1) || wc_self_linked(sc, a1, b0) ||
        wc_self_linked(sc, a1, b1))
        return 0;
    const unsigned char* tg = sc->tangled;
    if (tg[a0] && tg[a1] && tg[b0] && tg[b1]) return 0;
    return keep(c, f);
}

/* Gather at x0, x1 for boxes inflated by r: each particle's anchor is its box from x0 to x1 moved
 * on by WC_SELF_NEAR_AHEAD times its motion x1 - x0 (x1 lies inside it, up to rounding, which
 * the bound measures like any motion), so that steady motion (a cloth falling, or turning with
 * its body) stays inside the anchors for a few substeps. The trees are refitted over the anchors
 * for the gathering, then over x0, x1 again for the phase. */
static void gather(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r) {
    int n = sc->n, nq = n + sc->n_edges;
    double* xa = sc->near_ahead;
    for (int k = 0; k < 3 * n; ++k) xa[k] = x1[k] + WC_SELF_NEAR_AHEAD * (x1[k] - x0[k]);
    for (int i = 0; i < n; ++i) wc_self_swept_box(sc->near_anchor + 6 * i, &i, 1, x0, xa, 0.0);
    wc_self_refit(sc, m, x0, xa, r);
    double grow = sc->near_gap - r;
    WC_PAR_REGION(sc) { /* each query's list its own: chunks to whichever thread is free */
        gather_ctx c = {sc, m, 0, 0, 0, NULL, 0};
        WC_PAR_FOR_DYNAMIC(256)
        for (int q = 0; q < nq; ++q) {
            double b[6];
            c.out = sc->near_cand + (size_t)q * WC_SELF_NEAR_CAP;
            c.count = 0;
            if (q < n) {
                memcpy(b, sc->near_anchor + 6 * q, sizeof b);
                wc_box_inflate(b, grow);
                c.query = q;
                wc_bvh_query(&sc->tri_bvh, b, gather_tri, &c);
            } else {
                const int* ev = sc->edges + 2 * (q - n);
                wc_self_swept_box(b, ev, 2, x0, xa, grow);
                c.a = ev[0];
                c.b = ev[1];
                wc_self_edges_above(sc, q - n, b, gather_edge, &c);
            }
            sc->near_count[q] = c.count;
        }
    }
    sc->near_kept = 1;
    ++sc->near_gathers;
    wc_self_refit(sc, m, x0, x1, r);   /* the phase's boxes again */
}

void wc_self_near_prepare(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r,
                          int full) {
    sc->near_use = 0;
    if (sc->near_off) return;
    if (!full) { /* a later pass: the lists as they are when they cover it, never a gathering; not
                    even checked (a serial sweep of the particles) when the last full phase walked */
        sc->near_use = sc->near_full_use && wc_self_near_covers(sc, x0, x1, r);
        if (sc->near_use) ++sc->near_later;
        return;
    }
    sc->near_full_use = 0;
    if (wc_self_near_covers(sc, x0, x1, r)) {
        sc->near_use = sc->near_full_use = 1;
        ++sc->near_served;
        return;
    }
    if (sc->near_wait > 0) {
        --sc->near_wait;
        return;
    }
    if (sc->near_kept && sc->near_served <= 2 && !sc->near_waited) {
        /* the last lists served at most one full phase after the one that gathered them, less
           than a gathering costs (its walks use boxes grown by the margin): wait (2, 4, ... 32
           full phases) before gathering again */
        sc->near_backoff = sc->near_backoff ? (sc->near_backoff < 32 ? 2 * sc->near_backoff : 32) : 2;
        sc->near_wait = sc->near_backoff - 1;
        sc->near_waited = 1;
        return;
    }
    if (sc->near_served > 2) sc->near_backoff = 0;
    gather(sc, m, x0, x1, r);
    sc->near_served = 0;
    sc->near_waited = 0;
    if (!wc_self_near_covers(sc, x0, x1, r)) return;   /* non-finite positions */
    sc->near_use = sc->near_full_use = 1;
    sc->near_served = 1;
}

/* The kept list of query q in the trees' leaf order: the leaf test of wc_bvh_query_masked (mask,
 * then box) on each. */
static int visit_list(const wc_self* sc, const wc_bvh* tree, const double* boxes, int q, const double* box,
                      const unsigned char* mask, wc_bvh_visit_fn visit, void* user) {
    const int* cand = sc->near_cand + (size_t)q * WC_SELF_NEAR_CAP;
    int nc = sc->near_count[q];
    for (int k = 0; k < nc; ++k) {
        int p = cand[k];
        if ((mask && !mask[tree->leaf_of[p]]) || !wc_box_overlap(boxes + 6 * p, box)) continue;
        int r = visit(user, p);
        if (r) return r;
    }
    return 0;
}

int wc_self_near_tris(const wc_self* sc, int i, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                      void* user) {
    if (!sc->near_use || sc->near_count[i] < 0) return wc_bvh_query_masked(&sc->tri_bvh, box, mask, visit, user);
    return visit_list(sc, &sc->tri_bvh, sc->tri_box, i, box, mask, visit, user);
}

int wc_self_near_edges(const wc_self* sc, int e, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                       void* user) {
    int q = sc->n + e;
    if (!sc->near_use || sc->near_count[q] < 0) return wc_self_edges_above_masked(sc, e, box, mask, visit, user);
    return visit_list(sc, &sc->edge_bvh, sc->edge_box, q, box, mask, visit, user);
}
