/* The self-collision queries' kept candidates (self_near.h). */
#include "self_near.h"
#include <float.h>
#include <limits.h>
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
    sc->near_qbox = WC_NEW(&sc->alloc, double, 6 * nq + 6);
    sc->near_vstart = WC_NEW(&sc->alloc, int, (size_t)sc->n_tris + 2);
    sc->near_vlist = WC_NEW(&sc->alloc, int, (size_t)sc->n + 1);
    sc->near_vready = 0;
    return sc->near_anchor && sc->near_cand && sc->near_count && sc->near_ahead && sc->near_qbox &&
                   sc->near_vstart && sc->near_vlist
               ? WC_OK
               : WC_ERROR_OUT_OF_MEMORY;
}

void wc_self_near_free(wc_self* sc) {
    wc_free(&sc->alloc, sc->near_anchor);
    wc_free(&sc->alloc, sc->near_cand);
    wc_free(&sc->alloc, sc->near_count);
    wc_free(&sc->alloc, sc->near_ahead);
    wc_free(&sc->alloc, sc->near_qbox);
    wc_free(&sc->alloc, sc->near_vstart);
    wc_free(&sc->alloc, sc->near_vlist);
    sc->near_anchor = sc->near_ahead = sc->near_qbox = NULL;
    sc->near_cand = sc->near_count = sc->near_vstart = sc->near_vlist = NULL;
    sc->near_vready = 0;
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

/* Gathering: each query's candidates less those the adjacency rules exclude, in the leaf order
 * of its tree; more than WC_SELF_NEAR_CAP: count -1 (the query walks the tree). That is the list
 * the query's own walk from the root (wc_bvh_query, wc_self_edges_above) with its box gives, its
 * visitor keeping each candidate until one more than the cap arrives: a walk enters the nodes in
 * preorder, left child first, so it visits the leaves in leaf order, and it visits a leaf when
 * the leaf's box meets the query's (and, edges above, the edge's index is above the query's):
 * every node above holds the leaf's box (a refit's unions; the lists are used only when every
 * anchor is finite, wc_self_near_covers, so every box then is) and the leaf's index, so the
 * tests there pass too. So a walk with a box that holds the query's (edges: from an index at or
 * below the query's) visits those leaves among others, in the same order: the queries are
 * gathered in batches, the queries of a subtree of their tree (a triangle's: the vertices it
 * carries) walked once with the union of their boxes, each query's list then the collected
 * elements that pass its own walk's leaf test, in the order collected (gather_batch). */
typedef struct gather_ctx {
    const wc_self* sc;
    const wc_model* m;
    int query;      /* the vertex, or the edge */
    int* out;       /* its WC_SELF_NEAR_CAP slots */
    int count;
} gather_ctx;

static int tri_excluded(const wc_self* sc, const wc_model* m, int i, int t) {
    const int* tv = m->tris + 3 * t;
    if (wc_self_linked(sc, i, tv[0]) || wc_self_linked(sc, i, tv[1]) || wc_self_linked(sc, i, tv[2])) return 1;
    const unsigned char* tg = sc->tangled;
    return tg[i] && tg[tv[0]] && tg[tv[1]] && tg[tv[2]];
}

static int edge_excluded(const wc_self* sc, int e, int f) {
    int a0 = sc->edges[2 * e], a1 = sc->edges[2 * e + 1], b0 = sc->edges[2 * f], b1 = sc->edges[2 * f + 1];
    if (wc_self_linked(sc, a0, b0) || wc_self_linked(sc, a0, b1) || wc_self_linked(sc, a1, b0) ||
        wc_self_linked(sc, a1, b1))
        return 1;
    const unsigned char* tg = sc->tangled;
    return tg[a0] && tg[a1] && tg[b0] && tg[b1];
}

/* A query's own walk of its tree (leaf order), for a vertex in no triangle or a batch whose walk
 * collected too many: each candidate kept, and the walk stopped one past the cap */
static int gather_keep(gather_ctx* c, int element) {
    if (c->count == WC_SELF_NEAR_CAP) {
        c->count = -1;
        return 1;
    }
    c->out[c->count++] = element;
    return 0;
}

static int gather_tri(void* user, int t) {
    gather_ctx* c = (gather_ctx*)user;
    return tri_excluded(c->sc, c->m, c->query, t) ? 0 : gather_keep(c, t);
}

static int gather_edge(void* user, int f) {
    gather_ctx* c = (gather_ctx*)user;
    return edge_excluded(c->sc, c->query, f) ? 0 : gather_keep(c, f);
}

/* The vertex queries each triangle carries, for the batches: a vertex by the first triangle it is
 * in (so a batch's vertices are near each other), those in none after the last triangle's.
 * Once: the model's topology. */
static void vertex_owners(wc_self* sc, const wc_model* m) {
    int n = sc->n, nt = m->n_tris, *start = sc->near_vstart, *list = sc->near_vlist;
    int* owner = sc->near_cand; /* scratch: the lists are gathered after this */
    for (int i = 0; i < n; ++i) owner[i] = nt;
    for (int k = 3 * nt - 1; k >= 0; --k) owner[m->tris[k]] = k / 3;
    memset(start, 0, ((size_t)nt + 2) * sizeof(int));
    for (int i = 0; i < n; ++i) ++start[owner[i] + 1];
    for (int t = 0; t <= nt; ++t) start[t + 1] += start[t];
    for (int i = 0; i < n; ++i) list[start[owner[i]]++] = i; /* start[t] ends at t + 1's start */
    for (int t = nt; t > 0; --t) start[t] = start[t - 1];
    start[0] = 0;
    sc->near_vready = 1;
}

#define GATHER_GROUP 8   /* a batch: the queries of a subtree of at most this many leaves */
#define GATHER_ROOM 256  /* the elements a batch's walk may collect (more: each query walks alone) */

typedef struct batch {
    int n;                  /* elements collected, in leaf order; GATHER_ROOM + 1: too many */
    int elem[GATHER_ROOM];
} batch;

static int collect(void* user, int p) {
    batch* b = (batch*)user;
    if (b->n == GATHER_ROOM) {
        b->n = GATHER_ROOM + 1;
        return 1;
    }
    b->elem[b->n++] = p;
    return 0;
}

/* The batch of queries qs[0 .. nq) (tri: vertices against the triangle tree; else edges against
 * the edges above them): the tree walked once with the union of their boxes (edges: above the
 * lowest of them), then each query's list the collected elements that pass its own walk's test
 * (its box meets the element's; edges: the element above it), in the order collected. */
static void gather_batch(wc_self* sc, const wc_model* m, int tri, const int* qs, int nq) {
    const double* qb = sc->near_qbox;
    const wc_bvh* tree = tri ? &sc->tri_bvh : &sc->edge_bvh;
    double u[6];
    int lowest = INT_MAX;
    wc_box_empty(u);
    for (int j = 0; j < nq; ++j) {
        const double* q = qb + 6 * (size_t)qs[j];
        for (int k = 0; k < 3; ++k) {
            if (q[k] < u[k]) u[k] = q[k];
            if (q[3 + k] > u[3 + k]) u[3 + k] = q[3 + k];
        }
        if (qs[j] < lowest) lowest = qs[j];
    }
    batch bt;
    bt.n = 0;
    if (tri)
        wc_bvh_query(tree, u, collect, &bt);
    else
        wc_self_edges_above(sc, lowest - sc->n, u, collect, &bt);
    for (int j = 0; j < nq; ++j) {
        int q = qs[j], count = 0;
        int* out = sc->near_cand + (size_t)q * WC_SELF_NEAR_CAP;
        const double* qbox = qb + 6 * (size_t)q;
        if (bt.n > GATHER_ROOM) { /* too many for the batch: the query's own walk */
            gather_ctx c = {sc, m, tri ? q : q - sc->n, out, 0};
            if (tri)
                wc_bvh_query(tree, qbox, gather_tri, &c);
            else
                wc_self_edges_above(sc, q - sc->n, qbox, gather_edge, &c);
            sc->near_count[q] = c.count;
            continue;
        }
        for (int k = 0; k < bt.n; ++k) {
            int p = bt.elem[k];
            if (!tri && p <= q - sc->n) continue;
            if (!wc_box_overlap(tree->box + 6 * (size_t)tree->leaf_of[p], qbox)) continue;
            if (tri ? tri_excluded(sc, m, q, p) : edge_excluded(sc, q - sc->n, p)) continue;
            if (count == WC_SELF_NEAR_CAP) {
                count = -1;
                break;
            }
            out[count++] = p;
        }
        sc->near_count[q] = count;
    }
}

/* The batches under node root of a tree (the nodes [root, end) in preorder; tri: the triangle
 * tree, whose batches are the vertices its triangles carry), each the subtree of at most
 * GATHER_GROUP leaves under a larger one */
static void gather_under(wc_self* sc, const wc_model* m, int tri, int root, int end) {
    const wc_bvh* tree = tri ? &sc->tri_bvh : &sc->edge_bvh;
    int stack[2 * (WC_BVH_MAX_DEPTH + 2)], top = 0;
    int qs[3 * GATHER_GROUP];
    stack[top++] = root;
    stack[top++] = end;
    while (top > 0) {
        int e = stack[--top], node = stack[--top];
        const int* ch = tree->child + 2 * node;
        if (ch[0] >= 0 && (e - node + 1) / 2 > GATHER_GROUP) { /* (nodes + 1) / 2 leaves */
            stack[top++] = ch[1];
            stack[top++] = e;
            stack[top++] = ch[0];
            stack[top++] = ch[1];
            continue;
        }
        int nq = 0;
        for (int k = node; k < e; ++k) {
            const int* c = tree->child + 2 * k;
            if (c[0] >= 0) continue;
            if (!tri) {
                qs[nq++] = sc->n + c[1];
                continue;
            }
            for (int j = sc->near_vstart[c[1]]; j < sc->near_vstart[c[1] + 1]; ++j) qs[nq++] = sc->near_vlist[j];
        }
        if (nq > 0) gather_batch(sc, m, tri, qs, nq);
    }
}

/* Gather at x0, x1 for boxes inflated by r: each particle's anchor is its box from x0 to x1 moved
 * on by WC_SELF_NEAR_AHEAD times its motion x1 - x0 (x1 lies inside it, up to rounding, which
 * the bound measures like any motion), so that steady motion (a cloth falling, or turning with
 * its body) stays inside the anchors for a few substeps. The trees are refitted over the anchors
 * for the gathering, then over x0, x1 again for the phase. The queries' boxes: a vertex's anchor,
 * an edge's box of x0 and the reach, each grown by the margin (gap - r). */
static void gather(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r) {
    int n = sc->n, nq = n + sc->n_edges;
    double* xa = sc->near_ahead;
    for (int k = 0; k < 3 * n; ++k) xa[k] = x1[k] + WC_SELF_NEAR_AHEAD * (x1[k] - x0[k]);
    for (int i = 0; i < n; ++i) wc_self_swept_box(sc->near_anchor + 6 * i, &i, 1, x0, xa, 0.0);
    wc_self_refit(sc, m, x0, xa, r);
    if (!sc->near_vready) vertex_owners(sc, m);
    double grow = sc->near_gap - r;
    int ns_tri = sc->tri_split.n_sub, ns = ns_tri + sc->edge_split.n_sub;
    int lone = sc->near_vstart[m->n_tris]; /* the vertices in no triangle: near_vlist[lone, n) */
    WC_PAR_REGION(sc) {
        int lo, hi;
        wc_par_range(nq, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int q = lo; q < hi; ++q) {
            double* b = sc->near_qbox + 6 * (size_t)q;
            if (q < n) {
                memcpy(b, sc->near_anchor + 6 * q, 6 * sizeof(double));
                wc_box_inflate(b, grow);
            } else {
                wc_self_swept_box(b, sc->edges + 2 * (q - n), 2, x0, xa, grow);
            }
        }
        WC_PAR_BARRIER(); /* every query's box before the batches */
        /* each subtree's queries theirs alone: any thread may gather any */
        WC_PAR_FOR_DYNAMIC(1)
        for (int k = 0; k < ns; ++k) {
            int tri = k < ns_tri;
            const int* sub = tri ? sc->tri_split.sub + 2 * k : sc->edge_split.sub + 2 * (k - ns_tri);
            gather_under(sc, m, tri, sub[0], sub[1]);
        }
        gather_ctx c = {sc, m, 0, NULL, 0};
        WC_PAR_FOR_DYNAMIC(16)
        for (int j = lone; j < n; ++j) {
            int v = sc->near_vlist[j];
            c.out = sc->near_cand + (size_t)v * WC_SELF_NEAR_CAP;
            c.count = 0;
            c.query = v;
            wc_bvh_query(&sc->tri_bvh, sc->near_qbox + 6 * (size_t)v, gather_tri, &c);
            sc->near_count[v] = c.count;
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
