/* Finding the self-contact pairs (self_pairs.h) at a substep's start.
 *
 * Detection (wc_self_pairs_find, at the substep's start, before the assembly), on the
 * self-collision trees refitted over the boxes of x_n and x_n + 1.5 h v_n inflated by the
 * thickness (so the broad phase covers the contact distance below): vertex i against triangle t
 * (i not in t) and edge e against edge f > e (no shared particle), pairs with a particle sewn to
 * the other side or made only of particles tangled at rest skipped (self_collide.h's rules). The
 * closest points at the start must be interior to both features (barycentric weights and edge
 * parameters above 1e-6: a vertex nearest an edge or a vertex is left to the stage) and closer
 * than th + thickness + 1.5 h a (a: the approach speed along the pair's direction at v_n, when
 * positive), with th = min(thickness, the pair's distance at rest) as in the stage. Frozen for
 * the substep: the weights w (vertex-triangle: 1, -b1, -b2, -b3; edge-edge: 1-s, s, -(1-t), -t),
 * the unit normal n from the second feature to the first at the start, off = WC_SELF_PAIR_MARGIN
 * th, and k by penalty_pairs.h's rule.
 * Deterministic on any thread count: the detection runs its queries (every vertex, then every
 * edge) on sp->threads threads in fixed ranges, each thread into its own stage, and appends the
 * stages in range order (the serial list, in query order). */
#include "self_pairs.h"
#include <math.h>
#include <string.h>
#include "filter.h"
#include "geom.h"
#include "model.h"
#include "par.h"
#include "self_collide.h"
#include "self_near.h"
#include "vec3.h"

#define INTERIOR 1e-6    /* a feature parameter within this of its ends is the end's */

wc_self_pairs* wc_self_pairs_create(int cap, int n_particles, int n_edges, int threads, int stage_cap,
                                    const wc_allocator* a) {
    if (n_particles < 0) n_particles = 0;
    (void)n_edges;
    if (threads < 1) threads = 1;
    wc_self_pairs* sp = WC_NEW(a, wc_self_pairs, 1);
    if (!sp) return NULL;
    memset(sp, 0, sizeof *sp);
    sp->x_pred = WC_NEW(a, double, 3 * (size_t)n_particles + 1);
    if (!wc_penalty_pairs_init(&sp->list, cap, 0, a) || !sp->x_pred) {
        wc_self_pairs_destroy(sp, a);
        return NULL;
    }
    if (threads > 1 && !wc_penalty_stages_init(&sp->stage, &sp->resume, threads,
                                               stage_cap > 0 ? stage_cap : sp->list.cap / threads + 64, 0, a)) {
        wc_self_pairs_destroy(sp, a);
        return NULL;
    }
    sp->threads = threads;
    sp->n_particles = n_particles;
    sp->coupling.t = sp->list.term;
    return sp;
}

void wc_self_pairs_destroy(wc_self_pairs* sp, const wc_allocator* a) {
    if (!sp) return;
    wc_penalty_stages_free(&sp->stage, &sp->resume, sp->threads, a);
    wc_free(a, sp->x_pred);
    wc_penalty_pairs_free(&sp->list, a);
    wc_free(a, sp);
}

typedef struct find_ctx {
    wc_self_pairs* sp;
    const wc_self* sc;
    const wc_model* m;
    const wc_filter* f;
    const double *x, *v;
    double h, he;
    int query;
    wc_penalty_pairs* out; /* the list, or a thread's stage */
    int pos;        /* where the next kept pair goes in out (past its capacity: counted only) */
} find_ctx;

/* Keep the pair ids (w, at distance d along n at the start; th its rest gap) when it is close
 * enough for its approach speed and has an unpinned particle. */
static void keep(find_ctx* c, const int* ids, const double* w, const double* n, double d, double th) {
    double vrel = 0.0;
    for (int a = 0; a < 4; ++a) vrel += w[a] * v3_dot(n, c->v + 3 * ids[a]);
    double inv = wc_penalty_inv_mass(c->m, c->f, NULL, 4, ids, w);
    double approach = vrel < 0.0 ? -vrel : 0.0;
    if (!(d < th + c->sc->thickness + 1.5 * c->h * approach) || !(inv > 0.0)) return;
    int at = c->pos++;
    if (at >= c->out->cap) return;   /* counted as overflow by the caller */
    wc_penalty_pairs_set(c->out, at, 4, ids, w, n, WC_SELF_PAIR_MARGIN * th, wc_penalty_stiffness(inv, c->he));
}

static int tangled_all(const wc_self* sc, const int* ids) {
    return sc->tangled[ids[0]] && sc->tangled[ids[1]] && sc->tangled[ids[2]] && sc->tangled[ids[3]];
}

static int visit_tri(void* user, int t) {
    find_ctx* c = (find_ctx*)user;
    const wc_model* m = c->m;
    const int* tv = m->tris + 3 * t;
    int i = c->query;
    for (int k = 0; k < 3; ++k)
        if (wc_self_linked(c->sc, i, tv[k])) return 0;
    int ids[4] = {i, tv[0], tv[1], tv[2]};
    if (tangled_all(c->sc, ids)) return 0;
    const double* x = c->x;
    double bw[3], q[3];
    double d2 = wc_closest_on_triangle(x + 3 * i, x + 3 * tv[0], x + 3 * tv[1], x + 3 * tv[2], bw, q);
    if (!(bw[0] > INTERIOR && bw[1] > INTERIOR && bw[2] > INTERIOR)) return 0;
    double d = sqrt(d2), th = c->sc->thickness;
    if (!(d > 1e-9 * th)) return 0;   /* no direction: the stage's */
    if (d > 2.0 * th + 1.5 * c->h * (v3_norm(c->v + 3 * i) + v3_norm(c->v + 3 * tv[0]) + v3_norm(c->v + 3 * tv[1]) +
                                     v3_norm(c->v + 3 * tv[2])))
        return 0;   /* cheap reject before the rest distance */
    const double* r = m->rest_pos;
    double dr = sqrt(wc_closest_on_triangle(r + 3 * i, r + 3 * tv[0], r + 3 * tv[1], r + 3 * tv[2], NULL, NULL));
    if (dr < th) th = dr;
    double n[3], w[4] = {1.0, -bw[0], -bw[1], -bw[2]};
    v3_sub(n, x + 3 * i, q);
    v3_scale(n, n, 1.0 / d);
    keep(c, ids, w, n, d, th);
    return 0;
}

static int visit_edge(void* user, int f) {
    find_ctx* c = (find_ctx*)user;
    const int* E = c->sc->edges;
    int e = c->query;
    int a0 = E[2 * e], a1 = E[2 * e + 1], b0 = E[2 * f], b1 = E[2 * f + 1];
    if (wc_self_linked(c->sc, a0, b0) || wc_self_linked(c->sc, a0, b1) || wc_self_linked(c->sc, a1, b0) ||
        wc_self_linked(c->sc, a1, b1))
        return 0;
    int ids[4] = {a0, a1, b0, b1};
    if (tangled_all(c->sc, ids)) return 0;
    const double* x = c->x;
    double s, t;
    double d2 = wc_closest_on_segments(x + 3 * a0, x + 3 * a1, x + 3 * b0, x + 3 * b1, &s, &t);
    if (!(s > INTERIOR && s < 1.0 - INTERIOR && t > INTERIOR && t < 1.0 - INTERIOR)) return 0;
    double d = sqrt(d2), th = c->sc->thickness;
    if (!(d > 1e-9 * th)) return 0;
    double vmax = v3_norm(c->v + 3 * a0) + v3_norm(c->v + 3 * a1) + v3_norm(c->v + 3 * b0) + v3_norm(c->v + 3 * b1);
    if (d > 2.0 * th + 1.5 * c->h * vmax) return 0;
    const double* r = c->m->rest_pos;
    double ss, tt;
    double dr = sqrt(wc_closest_on_segments(r + 3 * a0, r + 3 * a1, r + 3 * b0, r + 3 * b1, &ss, &tt));
    if (dr < th) th = dr;
    double n[3], w[4] = {1.0 - s, s, -(1.0 - t), -t};
    for (int k = 0; k < 3; ++k)
        n[k] = ((1 - s) * x[3 * a0 + k] + s * x[3 * a1 + k] - (1 - t) * x[3 * b0 + k] - t * x[3 * b1 + k]) / d;
    keep(c, ids, w, n, d, th);
    return 0;
}

/* Query q (vertex q < n, else edge q - n) against the trees. */
static void find_query(find_ctx* c, int q) {
    const wc_self* sc = c->sc;
    int n = c->m->n_particles;
    double b[6];
    if (q < n) {
        wc_self_swept_box(b, &q, 1, c->x, c->sp->x_pred, 0.0);
        c->query = q;
        wc_self_near_tris(sc, q, b, NULL, visit_tri, c);
    } else {
        int e = q - n;
        wc_self_swept_box(b, sc->edges + 2 * e, 2, c->x, c->sp->x_pred, 0.0);
        c->query = e;
        wc_self_near_edges(sc, e, b, NULL, visit_edge, c);
    }
}

int wc_self_pairs_find(wc_self_pairs* sp, wc_self* sc, const wc_model* m, const wc_filter* f, const double* x,
                       const double* v, double h, double he) {
    wc_penalty_pairs_clear(&sp->list);
    sp->coupling.n = 0;
    if (sc->n_tris == 0) return 0;
    int n = m->n_particles, nq = n + sc->n_edges;
    double* xp = sp->x_pred;
    /* WC_PAR_REGION reads sc->threads (par.h's fixed contiguous ranges) */
    WC_PAR_REGION(sc) {
        int lo, hi;
        wc_par_range(3 * n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int k = lo; k < hi; ++k) xp[k] = x[k] + 1.5 * h * v[k];
    }
    wc_self_refit(sc, m, x, xp, sc->thickness);
    wc_self_near_prepare(sc, m, x, xp, sc->thickness, 1);
    find_ctx c = {sp, sc, m, f, x, v, h, he, 0, &sp->list, 0};
    if (sp->threads <= 1 || !sp->stage) {
        for (int q = 0; q < nq; ++q) find_query(&c, q);
    } else {
        /* each thread stages its fixed range; then, in range order, its staged pairs and the rest
           of its range (where its stage filled up) are appended: the serial list */
        int nt = 1;
        WC_PAR_REGION(sp) {
            int t = wc_par_tid(), lo, hi, q;
            if (t == 0) nt = wc_par_nt();
            wc_par_range(nq, t, wc_par_nt(), &lo, &hi);
            wc_penalty_pairs* st = &sp->stage[t];
            find_ctx ct = {sp, sc, m, f, x, v, h, he, 0, st, 0};
            for (q = lo; q < hi; ++q) {
                int pos0 = ct.pos;
                find_query(&ct, q);
                if (ct.pos > st->cap) { /* undo this query: the serial pass finds it again */
                    ct.pos = pos0;
                    break;
                }
            }
            st->n = ct.pos;
            st->overflow = st->skipped = 0;
            sp->resume[2 * t] = q;
            sp->resume[2 * t + 1] = hi;
        }
        for (int t = 0; t < nt; ++t) {
            wc_penalty_pairs_append(&sp->list, &sp->stage[t]);
            c.pos = sp->list.n + sp->list.overflow;
            for (int q = sp->resume[2 * t]; q < sp->resume[2 * t + 1]; ++q) find_query(&c, q);
            sp->list.n = c.pos < sp->list.cap ? c.pos : sp->list.cap;
            sp->list.overflow = c.pos - sp->list.n;
        }
    }
    int total = sp->threads <= 1 || !sp->stage ? c.pos : sp->list.n + sp->list.overflow;
    sp->list.n = total < sp->list.cap ? total : sp->list.cap;
    sp->list.overflow = total - sp->list.n;
    sp->coupling.n = sp->list.n;
    return sp->list.n;
}

int wc_self_pairs_from(wc_self_pairs* sp, const wc_self* sc, const wc_model* m, const wc_filter* f, const double* x,
                       const double* v, double h, double he, const int* cand, int n_cand) {
    wc_penalty_pairs_clear(&sp->list);
    sp->coupling.n = 0;
    if (sc->n_tris == 0) return 0;
    int n = m->n_particles;
    double* xp = sp->x_pred;
    for (int k = 0; k < 3 * n; ++k) xp[k] = x[k] + 1.5 * h * v[k];   /* wc_self_pairs_find's */
    find_ctx c = {sp, sc, m, f, x, v, h, he, 0, &sp->list, 0};
    double qb[6], eb[6];
    for (int j = 0; j < n_cand; ++j) {
        int q = cand[2 * j], el = cand[2 * j + 1];
        /* the walk's leaf test: the query's box (x, xp) meets the element's (x, xp, grown by the
           thickness: wc_self_refit's), and an edge is above the query's */
        if (q < n) {
            wc_self_swept_box(qb, &q, 1, x, xp, 0.0);
            wc_self_swept_box(eb, m->tris + 3 * el, 3, x, xp, sc->thickness);
        } else {
            if (el <= q - n) continue;
            wc_self_swept_box(qb, sc->edges + 2 * (q - n), 2, x, xp, 0.0);
            wc_self_swept_box(eb, sc->edges + 2 * el, 2, x, xp, sc->thickness);
        }
        if (!wc_box_overlap(qb, eb)) continue;
        c.query = q < n ? q : q - n;
        if (q < n)
            visit_tri(&c, el);
        else
            visit_edge(&c, el);
    }
    sp->list.n = c.pos < sp->list.cap ? c.pos : sp->list.cap;
    sp->list.overflow = c.pos - sp->list.n;
    sp->coupling.n = sp->list.n;
    return sp->list.n;
}
