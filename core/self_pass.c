/* One pass of the self-collision stage over its candidate pairs (self_pass.h). */
#include "self_pass.h"
#include <math.h>
#include "geom.h"
#include "par.h"
#include "self_broad.h"
#include "self_near.h"
#include "union_find.h"
#include "vec3.h"

#define WC_SELF_SCAN_CHUNK 256 /* queries a thread takes at a time in the parallel scans */

typedef struct pass_ctx {
    wc_self* sc;
    const wc_model* m;
    double* x;          /* end positions, corrected in place (not in WC_SELF_PASS_DETECT) */
    int mode;
    int query;          /* the vertex or edge being queried */
    int count;          /* CCD pairs acted on / found */
    int prox;           /* proximity impulses (WC_SELF_PASS_PROXIMITY) */
    int dry;            /* 1: the read-only scan: nothing moved or merged, a pair that needs action
                           makes the visit return 1 (the query is marked, its visit stops) */
    const unsigned char* dirty; /* NULL: every pair; else (dry scan) only pairs with a particle i
                                   dirty[i] */
    unsigned char* touched;     /* NULL, or (serial visit) 1 for the particles of every pair acted
                                   on or counted: the next pass's dirty set */
    int grids;                  /* bits 1, 2: sc's triangle, edge grid holds this pass's dirty
                                   elements (mark_dirty) */
    int no_impact;              /* 1: a CCD hit is counted, no impulse applied (wc_self_pass_pair) */
} pass_ctx;

/* The 4 particles of a pair that needed action go into the next pass's dirty set. */
static void touch(pass_ctx* c, const int* ids) {
    if (c->touched)
        for (int k = 0; k < 4; ++k) c->touched[ids[k]] = 1;
}

/* Move the 4 particles ids by w_i inv_m_i D / sum_j w_j^2 inv_m_j along n: the relative normal
 * displacement sum_i w_i (x_i - x_start_i) . n grows by D. */
static int apply(pass_ctx* c, const int* ids, const double* w, const double* n, double D) {
    const double* im = c->sc->inv_mass;
    touch(c, ids);
    double den = 0.0;
    for (int k = 0; k < 4; ++k) den += w[k] * w[k] * im[ids[k]];
    if (!(den > 0)) return 0;
    double J = D / den;
    for (int k = 0; k < 4; ++k) v3_axpy(c->x + 3 * ids[k], w[k] * im[ids[k]] * J, n);
    return 1;
}

/* Relative displacement sum_i w_i (x_i - x_start_i) along n. */
static double rel_normal(const pass_ctx* c, const int* ids, const double* w, const double* n) {
    double r = 0.0;
    for (int k = 0; k < 4; ++k) {
        double d[3];
        v3_sub(d, c->x + 3 * ids[k], c->sc->x_start + 3 * ids[k]);
        r += w[k] * v3_dot(d, n);
    }
    return r;
}

/* The union-find root of i without path halving (read-only: the parallel scan). */
static int find_ro(const int* parent, int i) {
    while (parent[i] != i) i = parent[i];
    return i;
}

/* Detect mode: pairs whose 4 particles are in one zone without a pin move by one affine map. */
static int same_zone(const pass_ctx* c, const int* ids) {
    wc_self* sc = c->sc;
    int r = -1;
    for (int k = 0; k < 4; ++k) {
        int i = ids[k];
        if (!sc->in_zone[i] || sc->inv_mass[i] == 0.0) return 0;
        int ri = c->dry ? find_ro(sc->parent, i) : wc_uf_find(sc->parent, i);
        if (r >= 0 && ri != r) return 0;
        r = ri;
    }
    return 1;
}

static void merge(pass_ctx* c, const int* ids) {
    wc_self* sc = c->sc;
    for (int k = 0; k < 4; ++k) {
        sc->in_zone[ids[k]] = 1;
        if (k > 0) wc_uf_union(sc->parent, ids[0], ids[k]);
    }
}

/* 1 when the pair cannot come within eta during the substep. With linear motion a point of the
 * first feature (fixed weights a_i over its vertices) and one of the second (weights b_j) are
 * p(t) - q(t) = (p0 - q0) + t sum_ij a_i b_j (d_i - d_j), d = x - x_start: their distance stays
 * at least d0 - max_ij |d_i - d_j| (first feature ids[0, split), second ids[split, 4)). Only the
 * relative motion counts, so a cloth region that falls or swings as a whole skips the CCD's
 * cubic for its neighbours however far it moves in a substep (the previous bound, the sum of
 * the two features' largest displacements, is never tighter: |d_i - d_j| <= |d_i| + |d_j|). */
static double max_rel(const pass_ctx* c, const int* ids, int split) {
    double d[4][3], m2 = 0.0;
    for (int k = 0; k < 4; ++k) v3_sub(d[k], c->x + 3 * ids[k], c->sc->x_start + 3 * ids[k]);
    for (int i = 0; i < split; ++i)
        for (int j = split; j < 4; ++j) {
            double r[3];
            v3_sub(r, d[i], d[j]);
            double l2 = v3_dot(r, r);
            if (l2 > m2) m2 = l2;
        }
    return sqrt(m2);
}

static int too_far(const pass_ctx* c, const int* ids, int split, double d0) {
    return d0 - max_rel(c, ids, split) > c->sc->eta;
}

/* 1 when the pair needs no closest-point computation: the distance between the two features'
 * boxes at the start (a lower bound of their distance d0) is at least the thickness (or any
 * distance outside the proximity pass), so no proximity impulse, and too_far holds with it. */
static int far_apart(const pass_ctx* c, const int* ids, int split) {
    const double* xs = c->sc->x_start;
    double g2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        double alo = xs[3 * ids[0] + k], ahi = alo, blo = xs[3 * ids[3] + k], bhi = blo;
        for (int j = 1; j < split; ++j) {
            double v = xs[3 * ids[j] + k];
            alo = v < alo ? v : alo;
            ahi = v > ahi ? v : ahi;
        }
        for (int j = split; j < 3; ++j) {
            double v = xs[3 * ids[j] + k];
            blo = v < blo ? v : blo;
            bhi = v > bhi ? v : bhi;
        }
        double g = alo - bhi > blo - ahi ? alo - bhi : blo - ahi;
        if (g > 0) g2 += g * g;
    }
    double lb = sqrt(g2);
    if (c->mode == WC_SELF_PASS_PROXIMITY && lb < c->sc->thickness) return 0;
    return lb - max_rel(c, ids, split) > c->sc->eta;
}

static void lerp3(double* o, const double* a, const double* b, double t) {
    for (int k = 0; k < 3; ++k) o[k] = a[k] + t * (b[k] - a[k]);
}

/* The collision normal at time t (unit; from the second feature towards the first, oriented by
 * their separation at the start, sep0 = first - second then). tri: 1 for vertex-triangle (ids
 * 1..3 the triangle), else edge-edge (ids 0-1 and 2-3). Returns 0 when there is none. */
static int impact_normal(const pass_ctx* c, const int* ids, int tri, double t, const double* sep0, double* n) {
    const double* xs = c->sc->x_start;
    double p[4][3];
    for (int k = 0; k < 4; ++k) lerp3(p[k], xs + 3 * ids[k], c->x + 3 * ids[k], t);
    double u[3], v[3];
    if (tri) {
        v3_sub(u, p[2], p[1]);
        v3_sub(v, p[3], p[1]);
    } else {
        v3_sub(u, p[1], p[0]);
        v3_sub(v, p[3], p[2]);
    }
    v3_cross(n, u, v);
    double nn = v3_norm(n);
    if (!(nn > 1e-12 * v3_dot(u, u) + 1e-300)) {
        /* parallel edges: the start separation */
        nn = v3_norm(sep0);
        if (!(nn > 0)) return 0;
        v3_scale(n, sep0, 1.0 / nn);
        return 1;
    }
    v3_scale(n, n, 1.0 / nn);
    if (v3_dot(n, sep0) < 0) v3_scale(n, n, -1.0);
    return 1;
}

/* Returns 1 in a dry scan when the pair needs action (else 0). */
static int vertex_tri(pass_ctx* c, int i, int t) {
    const wc_model* m = c->m;
    const int* tv = m->tris + 3 * t;
    const int *ls = c->sc->seam_start, *ln = c->sc->seam_nbr;
    if (wc_self_seam_linked(ls, ln, i, tv[0]) || wc_self_seam_linked(ls, ln, i, tv[1]) ||
        wc_self_seam_linked(ls, ln, i, tv[2]))
        return 0;
    const unsigned char* tg = c->sc->tangled;
    if (tg[i] && tg[tv[0]] && tg[tv[1]] && tg[tv[2]]) return 0;
    int ids[4] = {i, tv[0], tv[1], tv[2]};
    const double* xs = c->sc->x_start;
    const double* x = c->x;
    double bw[3], q[3], w[4], n[3];
    if (c->mode == WC_SELF_PASS_DETECT && same_zone(c, ids)) return 0;
    if (far_apart(c, ids, 1)) return 0;
    double d2 = wc_closest_on_triangle(xs + 3 * i, xs + 3 * tv[0], xs + 3 * tv[1], xs + 3 * tv[2], bw, q);
    if (c->mode == WC_SELF_PASS_PROXIMITY) {
        double th = c->sc->thickness;
        if (d2 < th * th) {
            const double* r = m->rest_pos;
            double dr = sqrt(wc_closest_on_triangle(r + 3 * i, r + 3 * tv[0], r + 3 * tv[1], r + 3 * tv[2], NULL, NULL));
            if (dr < th) th = dr;
            double d = sqrt(d2);
            if (d < th && d > 0) {
                v3_sub(n, xs + 3 * i, q);
                v3_scale(n, n, 1.0 / d);
                w[0] = 1.0; w[1] = -bw[0]; w[2] = -bw[1]; w[3] = -bw[2];
                double dn = rel_normal(c, ids, w, n), target = 0.1 * (th - d);
                if (dn < target && c->dry) return 1;
                if (dn < target) c->prox += apply(c, ids, w, n, target - dn);
            }
        }
    }
    if (too_far(c, ids, 1, sqrt(d2))) return 0;
    double t_hit;
    if (!wc_ccd_point_triangle(xs + 3 * i, xs + 3 * tv[0], xs + 3 * tv[1], xs + 3 * tv[2], x + 3 * i, x + 3 * tv[0],
                               x + 3 * tv[1], x + 3 * tv[2], c->sc->eta, &t_hit, bw))
        return 0;
    if (c->dry) return 1;
    if (c->mode == WC_SELF_PASS_DETECT) {
        merge(c, ids);
        ++c->count;
        return 0;
    }
    /* counted whether or not an impulse can be applied (pinned, no normal, already separating
       along it): the pass is then not clean, and what impulses cannot fix the zones will */
    ++c->count;
    touch(c, ids);
    if (c->sc->passes == 0 || c->no_impact) return 0;
    double sep0[3];
    for (int k = 0; k < 3; ++k) sep0[k] = xs[3 * i + k] - bw[0] * xs[3 * tv[0] + k] - bw[1] * xs[3 * tv[1] + k] - bw[2] * xs[3 * tv[2] + k];
    if (!impact_normal(c, ids, 1, t_hit, sep0, n)) return 0;
    w[0] = 1.0; w[1] = -bw[0]; w[2] = -bw[1]; w[3] = -bw[2];
    double dn = rel_normal(c, ids, w, n), target = c->sc->eta;
    if (dn < target) apply(c, ids, w, n, target - dn);
    return 0;
}

/* Returns 1 in a dry scan when the pair needs action (else 0). */
static int edge_edge(pass_ctx* c, int e, int f) {
    const int* E = c->sc->edges;
    int a0 = E[2 * e], a1 = E[2 * e + 1], b0 = E[2 * f], b1 = E[2 * f + 1];
    const int *ls = c->sc->seam_start, *ln = c->sc->seam_nbr;
    if (wc_self_seam_linked(ls, ln, a0, b0) || wc_self_seam_linked(ls, ln, a0, b1) ||
        wc_self_seam_linked(ls, ln, a1, b0) || wc_self_seam_linked(ls, ln, a1, b1))
        return 0;
    const unsigned char* tg = c->sc->tangled;
    if (tg[a0] && tg[a1] && tg[b0] && tg[b1]) return 0;
    int ids[4] = {a0, a1, b0, b1};
    const double* xs = c->sc->x_start;
    const double* x = c->x;
    double s, t, w[4], n[3];
    if (c->mode == WC_SELF_PASS_DETECT && same_zone(c, ids)) return 0;
    if (far_apart(c, ids, 2)) return 0;
    double d2 = wc_closest_on_segments(xs + 3 * a0, xs + 3 * a1, xs + 3 * b0, xs + 3 * b1, &s, &t);
    if (c->mode == WC_SELF_PASS_PROXIMITY) {
        double th = c->sc->thickness;
        if (d2 < th * th) {
            const double* r = c->m->rest_pos;
            double ss, tt;
            double dr = sqrt(wc_closest_on_segments(r + 3 * a0, r + 3 * a1, r + 3 * b0, r + 3 * b1, &ss, &tt));
            if (dr < th) th = dr;
            double d = sqrt(d2);
            if (d < th && d > 0) {
                for (int k = 0; k < 3; ++k)
                    n[k] = ((1 - s) * xs[3 * a0 + k] + s * xs[3 * a1 + k] - (1 - t) * xs[3 * b0 + k] - t * xs[3 * b1 + k]) / d;
                w[0] = 1 - s; w[1] = s; w[2] = -(1 - t); w[3] = -t;
                double dn = rel_normal(c, ids, w, n), target = 0.1 * (th - d);
                if (dn < target && c->dry) return 1;
                if (dn < target) c->prox += apply(c, ids, w, n, target - dn);
            }
        }
    }
    if (too_far(c, ids, 2, sqrt(d2))) return 0;
    double t_hit;
    if (!wc_ccd_edge_edge(xs + 3 * a0, xs + 3 * a1, xs + 3 * b0, xs + 3 * b1, x + 3 * a0, x + 3 * a1, x + 3 * b0,
                          x + 3 * b1, c->sc->eta, &t_hit, &s, &t))
        return 0;
    if (c->dry) return 1;
    if (c->mode == WC_SELF_PASS_DETECT) {
        merge(c, ids);
        ++c->count;
        return 0;
    }
    ++c->count; /* as for vertex-triangle pairs */
    touch(c, ids);
    if (c->sc->passes == 0 || c->no_impact) return 0;
    double sep0[3];
    for (int k = 0; k < 3; ++k)
        sep0[k] = (1 - s) * xs[3 * a0 + k] + s * xs[3 * a1 + k] - (1 - t) * xs[3 * b0 + k] - t * xs[3 * b1 + k];
    if (!impact_normal(c, ids, 0, t_hit, sep0, n)) return 0;
    w[0] = 1 - s; w[1] = s; w[2] = -(1 - t); w[3] = -t;
    double dn = rel_normal(c, ids, w, n), target = c->sc->eta;
    if (dn < target) apply(c, ids, w, n, target - dn);
    return 0;
}

static int visit_tri(void* user, int t) {
    pass_ctx* c = (pass_ctx*)user;
    return vertex_tri(c, c->query, t);
}

static int visit_edge_above(void* user, int f) {
    pass_ctx* c = (pass_ctx*)user;
    return edge_edge(c, c->query, f);
}

/* Visit the candidates of query q (vertex q < n, else edge q - n) at c's positions; returns 1
 * when a dry scan found a pair that needs action. With c->dirty (the dry scan only), a clean query
 * (its particles not dirty) visits only the elements under the trees' dirty nodes (mark_dirty). */
static int query(pass_ctx* c, int q) {
    wc_self* sc = c->sc;
    const unsigned char* dirty = c->dirty;
    double b[6];
    if (q < sc->n) {
        wc_self_swept_box(b, &q, 1, sc->x_start, c->x, 0.0);
        c->query = q;
        const unsigned char* mask = dirty && !dirty[q] ? sc->tri_mask : NULL;
        if (mask && (c->grids & 1) && !wc_self_grid_hits(&sc->tri_grid, b)) return 0; /* no dirty triangle near */
        return wc_self_near_tris(sc, q, b, mask, visit_tri, c) != 0;
    }
    /* the edge's own box (not inflated twice: the tree's boxes carry r) */
    const int* ev = sc->edges + 2 * (q - sc->n);
    wc_self_swept_box(b, ev, 2, sc->x_start, c->x, 0.0);
    c->query = q - sc->n;
    const unsigned char* mask = dirty && !dirty[ev[0]] && !dirty[ev[1]] ? sc->edge_mask : NULL;
    if (mask && (c->grids & 2) && !wc_self_grid_hits(&sc->edge_grid, b)) return 0; /* no dirty edge near */
    return wc_self_near_edges(sc, q - sc->n, b, mask, visit_edge_above, c) != 0;
}

/* The trees' masks: a leaf is dirty when one of its element's particles is (dirty[]), a node when
 * a leaf under it is. With refit, the dirty elements' boxes are recomputed and the trees refitted
 * under the dirty nodes only (the clean elements' particles have not moved since the last refit,
 * at the same r: wc_self.refit_dirty). Then the dirty elements' boxes go into the grids
 * (self_grid.h). Returns the grids on for the pass (bit 1: the triangles', 2: the edges'). */
static int mark_dirty(wc_self* sc, const wc_model* m, const double* x, double r, const unsigned char* dirty,
                      int refit) {
    WC_PAR_REGION(sc) { /* each element's leaf and box its own; then each subtree's nodes */
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
        wc_par_range(sc->n_tris, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) {
            const int* tv = m->tris + 3 * k;
            unsigned char d = dirty[tv[0]] | dirty[tv[1]] | dirty[tv[2]];
            sc->tri_mask[sc->tri_bvh.leaf_of[k]] = d;
            if (d && refit) wc_self_swept_box(sc->tri_box + 6 * k, tv, 3, sc->x_start, x, r);
        }
        wc_par_range(sc->n_edges, t, nt, &lo, &hi);
        for (int e = lo; e < hi; ++e) {
            const int* ev = sc->edges + 2 * e;
            unsigned char d = dirty[ev[0]] | dirty[ev[1]];
            sc->edge_mask[sc->edge_bvh.leaf_of[e]] = d;
            if (d && refit) wc_self_swept_box(sc->edge_box + 6 * e, ev, 2, sc->x_start, x, r);
        }
        WC_PAR_BARRIER(); /* every leaf before the subtrees */
        wc_self_trees_sweep(sc, 1, refit);
    }
    wc_self_trees_top(sc, 1, refit);
    if (sc->grid_off || sc->tri_bvh.n_nodes == 0 || sc->edge_bvh.n_nodes == 0) return 0;
    WC_PAR_REGION(sc) { /* the two grids are independent: the first thread's and the last's */
        int t = wc_par_tid(), nt = wc_par_nt();
        if (t == 0) {
            wc_self_grid_reset(&sc->tri_grid, sc->tri_bvh.box);
            for (int k = 0; k < sc->n_tris && sc->tri_grid.on; ++k)
                if (sc->tri_mask[sc->tri_bvh.leaf_of[k]]) wc_self_grid_mark(&sc->tri_grid, sc->tri_box + 6 * k);
        }
        if (t == nt - 1) {
            wc_self_grid_reset(&sc->edge_grid, sc->edge_bvh.box);
            for (int e = 0; e < sc->n_edges && sc->edge_grid.on; ++e)
                if (sc->edge_mask[sc->edge_bvh.leaf_of[e]]) wc_self_grid_mark(&sc->edge_grid, sc->edge_box + 6 * e);
        }
    }
    return (sc->tri_grid.on ? 1 : 0) | (sc->edge_grid.on ? 2 : 0);
}

/* The parallel read-only scan marks the queries with work, then the marked ones are visited
 * serially in index order (self_pass.h). */
int wc_self_pass(wc_self* sc, const wc_model* m, double* x, int mode, int* prox, const unsigned char* dirty,
                 unsigned char* touched) {
    double r = mode == WC_SELF_PASS_PROXIMITY ? sc->thickness : sc->eta;
    int nq = sc->n + sc->n_edges;
    /* WC_PAR_REGION reads sc->threads */
    int partial = dirty && sc->refit_dirty && sc->refit_r == r;
    sc->refit_dirty = 0;
    if (!partial) wc_self_refit(sc, m, sc->x_start, x, r);
    wc_self_near_prepare(sc, m, sc->x_start, x, r, dirty == NULL); /* the lists serve full scans */
    int grids = dirty ? mark_dirty(sc, m, x, r, dirty, partial) : 0;
    sc->refit_r = r;
    /* each query's mark is its own: chunks go to whichever thread is free (the queries' costs
       differ by orders of magnitude: fixed ranges left one thread waiting) */
    WC_PAR_REGION(sc) {
        pass_ctx d = {sc, m, x, mode, 0, 0, 0, 1, dirty, NULL, grids, 0};
        WC_PAR_FOR_DYNAMIC(WC_SELF_SCAN_CHUNK)
        for (int q = 0; q < nq; ++q) sc->active[q] = (unsigned char)query(&d, q);
    }
    /* the serial visits are those of the unfiltered pass: the scan marked the same queries (a pair
       with no dirty particle needs nothing), and a marked query visits all its candidates, so an
       impulse earlier in this pass that moved a clean pair is seen as it would be unfiltered */
    pass_ctx c = {sc, m, x, mode, 0, 0, 0, 0, NULL, touched, 0, 0};
    for (int q = 0; q < nq; ++q)
        if (sc->active[q]) query(&c, q);
    if (prox) *prox = c.prox;
    return c.count;
}

int wc_self_pass_pair(wc_self* sc, const wc_model* m, double* x, int mode, int q, int elem, int* prox,
                      unsigned char* touched) {
    pass_ctx c = {sc, m, x, mode & ~WC_SELF_PAIR_DRY, 0, 0, 0, (mode & WC_SELF_PAIR_DRY) != 0, NULL, touched, 0, 1};
    if (c.dry) return q < sc->n ? vertex_tri(&c, q, elem) : edge_edge(&c, q - sc->n, elem);
    if (q < sc->n) vertex_tri(&c, q, elem);
    else edge_edge(&c, q - sc->n, elem);
    if (prox) *prox += c.prox;
    return c.count;
}
