/* Self-collision: proximity impulses, CCD impulses, rigid impact zones (self_collide.h). */
#include "self_collide.h"

#include <math.h>
#include <string.h>

#include "geom.h"
#include "par.h"
#include "union_find.h"
#include "vec3.h"

static int count_unique_edges(const wc_winged_edge* we) {
    int k = 0;
    for (int e = 0; e < we->n_edges; ++e)
        if (!wc_we_repeats_previous(we, e)) ++k;
    return k;
}

static void fill_edges(const wc_winged_edge* we, int* edges) {
    int k = 0;
    for (int e = 0; e < we->n_edges; ++e)
        if (!wc_we_repeats_previous(we, e)) {
            edges[2 * k] = we->edges[e].v[0];
            edges[2 * k + 1] = we->edges[e].v[1];
            ++k;
        }
}

/* Seam links (sew.h): particles joined by a sewing spring count as one for the adjacency rules
 * (a vertex is never tested against a triangle or edge it is sewn to): sewn panels are not welded,
 * so their elements overlap along the seam by construction, and pushing them apart would fight
 * the seam. CSR of each particle's seam partners; NULL arrays when the model has no seams. */
static wc_status seam_links_build(const wc_model* m, const wc_allocator* A, int** start_out, int** nbr_out) {
    *start_out = NULL;
    *nbr_out = NULL;
    int s0 = m->spring_type_start[WC_SPRING_SEAM], s1 = m->spring_type_start[WC_SPRING_SEAM + 1];
    if (s1 <= s0) return WC_OK;
    int n = m->n_particles;
    int* start = WC_NEW(A, int, (size_t)n + 1);
    int* nbr = WC_NEW(A, int, 2 * (size_t)(s1 - s0));
    if (!start || !nbr) {
        wc_free(A, start);
        wc_free(A, nbr);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    for (int k = s0; k < s1; ++k) {
        ++start[m->springs[k].a + 1];
        ++start[m->springs[k].b + 1];
    }
    for (int i = 0; i < n; ++i) start[i + 1] += start[i];
    int* fill = WC_NEW(A, int, (size_t)n);
    if (!fill) {
        wc_free(A, start);
        wc_free(A, nbr);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    for (int k = s0; k < s1; ++k) {
        int a = m->springs[k].a, b = m->springs[k].b;
        nbr[start[a] + fill[a]++] = b;
        nbr[start[b] + fill[b]++] = a;
    }
    wc_free(A, fill);
    *start_out = start;
    *nbr_out = nbr;
    return WC_OK;
}

/* 1 when particles a and b are one particle or sewn together. */
static int linked(const int* start, const int* nbr, int a, int b) {
    if (a == b) return 1;
    if (!start) return 0;
    for (int k = start[a]; k < start[a + 1]; ++k)
        if (nbr[k] == b) return 1;
    return 0;
}

int wc_self_linked(const wc_self* sc, int a, int b) { return linked(sc->seam_start, sc->seam_nbr, a, b); }

static int edge_tri_cross(const wc_model* m, const int* ls, const int* ln, const double* x, int a, int b, int t);

typedef struct tangle_ctx {
    const wc_model* m;
    const wc_self* sc;
    unsigned char* tangled;
    int a, b, pairs;
} tangle_ctx;

static int visit_tangle(void* user, int t) {
    tangle_ctx* c = (tangle_ctx*)user;
    if (!edge_tri_cross(c->m, c->sc->seam_start, c->sc->seam_nbr, c->m->rest_pos, c->a, c->b, t)) return 0;
    const int* tv = c->m->tris + 3 * t;
    c->tangled[c->a] = c->tangled[c->b] = 1;
    c->tangled[tv[0]] = c->tangled[tv[1]] = c->tangled[tv[2]] = 1;
    ++c->pairs;
    return 0;
}

/* Particles of the edge-triangle pairs that already cross in the rest shape (creation): a mesh
 * that starts tangled (overlapping panels along a seam, layers through each other) cannot be
 * untangled by a method that only prevents new crossings; pairs made only of such particles are
 * left alone, so the stage does not lock them in impact zones. Returns the crossing pairs. */
static int mark_tangled(wc_self* sc, const wc_model* m) {
    tangle_ctx c = {m, sc, sc->tangled, 0, 0, 0};
    for (int e = 0; e < sc->n_edges; ++e) {
        c.a = sc->edges[2 * e];
        c.b = sc->edges[2 * e + 1];
        double b[6];
        wc_box_empty(b);
        wc_box_add(b, m->rest_pos + 3 * c.a);
        wc_box_add(b, m->rest_pos + 3 * c.b);
        wc_bvh_query(&sc->tri_bvh, b, visit_tangle, &c);
    }
    return c.pairs;
}

/* Boxes of the triangles and edges over x_start U x (x_start may be NULL), inflated by r. */
void wc_self_swept_box(double* b, const int* v, int nv, const double* x_start, const double* x, double r) {
    wc_box_empty(b);
    for (int k = 0; k < nv; ++k) {
        wc_box_add(b, x + 3 * v[k]);
        if (x_start) wc_box_add(b, x_start + 3 * v[k]);
    }
    wc_box_inflate(b, r);
}

static void boxes(const wc_model* m, const int* edges, int n_edges, const double* x_start, const double* x, double r,
                  double* tri_box, double* edge_box) {
    for (int t = 0; t < m->n_tris; ++t) wc_self_swept_box(tri_box + 6 * t, m->tris + 3 * t, 3, x_start, x, r);
    if (!edge_box) return;
    for (int e = 0; e < n_edges; ++e) wc_self_swept_box(edge_box + 6 * e, edges + 2 * e, 2, x_start, x, r);
}

void wc_self_refit(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r) {
    WC_PAR_REGION(sc) {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
        wc_par_range(m->n_tris, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) wc_self_swept_box(sc->tri_box + 6 * k, m->tris + 3 * k, 3, x0, x1, r);
        wc_par_range(sc->n_edges, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) wc_self_swept_box(sc->edge_box + 6 * k, sc->edges + 2 * k, 2, x0, x1, r);
    }
    wc_bvh_refit(&sc->tri_bvh, sc->tri_box);
    wc_bvh_refit(&sc->edge_bvh, sc->edge_box);
}

void wc_self_destroy(wc_self* sc) {
    if (!sc) return;
    wc_allocator a = sc->alloc;
    wc_bvh_free(&sc->tri_bvh);
    wc_bvh_free(&sc->edge_bvh);
    wc_free(&a, sc->edges);
    wc_free(&a, sc->tri_box);
    wc_free(&a, sc->edge_box);
    wc_free(&a, sc->x_start);
    wc_free(&a, sc->x_old);
    wc_free(&a, sc->inv_mass);
    wc_free(&a, sc->parent);
    wc_free(&a, sc->in_zone);
    wc_free(&a, sc->active);
    wc_free(&a, sc->edge_max);
    wc_free(&a, sc->tri_mask);
    wc_free(&a, sc->edge_mask);
    wc_free(&a, sc->dirty);
    wc_free(&a, sc->dirty_next);
    wc_free(&a, sc->zone);
    wc_free(&a, sc->tangled);
    wc_free(&a, sc->seam_start);
    wc_free(&a, sc->seam_nbr);
    wc_free(&a, sc);
}

wc_status wc_self_create(wc_self** out, const wc_model* m, double thickness, const wc_allocator* alloc,
                           wc_diag* diag) {
    if (out) *out = NULL;
    if (!out || !m) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "self-collision: NULL argument");
    if (!(thickness > 0) || !isfinite(thickness))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "self-collision: thickness %g m must be finite and > 0",
                       thickness);
    wc_allocator A = alloc ? *alloc : (wc_allocator){0};
    wc_self* sc = WC_NEW(&A, wc_self, 1);
    if (!sc) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory");
    sc->alloc = A;
    sc->thickness = thickness;
    sc->eta = thickness / 100.0;
    sc->passes = WC_SELF_PASSES;
    sc->zone_strain = WC_SELF_ZONE_STRAIN;
    int n = m->n_particles;
    sc->n = n;
    sc->n_tris = m->n_tris;
    sc->n_edges = count_unique_edges(&m->we);
    sc->edges = WC_NEW(&A, int, 2 * (size_t)sc->n_edges + 2);
    sc->tri_box = WC_NEW(&A, double, 6 * (size_t)sc->n_tris + 6);
    sc->edge_box = WC_NEW(&A, double, 6 * (size_t)sc->n_edges + 6);
    sc->x_start = WC_NEW(&A, double, 3 * (size_t)n);
    sc->x_old = WC_NEW(&A, double, 3 * (size_t)n);
    sc->inv_mass = WC_NEW(&A, double, (size_t)n);
    sc->parent = WC_NEW(&A, int, (size_t)n);
    sc->in_zone = WC_NEW(&A, unsigned char, (size_t)n);
    sc->zone = WC_NEW(&A, double, WC_SELF_ZONE_STRIDE * (size_t)n);
    sc->tangled = WC_NEW(&A, unsigned char, (size_t)n);
    sc->active = WC_NEW(&A, unsigned char, (size_t)n + (size_t)sc->n_edges + 1);
    sc->dirty = WC_NEW(&A, unsigned char, (size_t)n + 1);
    sc->dirty_next = WC_NEW(&A, unsigned char, (size_t)n + 1);
    sc->threads = 1;
    if (!sc->edges || !sc->tri_box || !sc->edge_box || !sc->x_start || !sc->x_old || !sc->inv_mass || !sc->parent ||
        !sc->in_zone || !sc->zone || !sc->active || !sc->tangled || !sc->dirty ||
        !sc->dirty_next) {
        wc_self_destroy(sc);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory (%d particles)", n);
    }
    if (seam_links_build(m, &A, &sc->seam_start, &sc->seam_nbr) != WC_OK) {
        wc_self_destroy(sc);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory (%d particles)", n);
    }
    fill_edges(&m->we, sc->edges);
    boxes(m, sc->edges, sc->n_edges, NULL, m->rest_pos, thickness, sc->tri_box, sc->edge_box);
    wc_status st = wc_bvh_build(&sc->tri_bvh, sc->tri_box, sc->n_tris, &A, diag);
    if (st == WC_OK) st = wc_bvh_build(&sc->edge_bvh, sc->edge_box, sc->n_edges, &A, diag);
    if (st == WC_OK) {
        sc->edge_max = WC_NEW(&A, int, (size_t)sc->edge_bvh.n_nodes + 1);
        sc->tri_mask = WC_NEW(&A, unsigned char, (size_t)sc->tri_bvh.n_nodes + 1);
        sc->edge_mask = WC_NEW(&A, unsigned char, (size_t)sc->edge_bvh.n_nodes + 1);
        if (!sc->edge_max || !sc->tri_mask || !sc->edge_mask)
            st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self-collision: out of memory");
    }
    if (st != WC_OK) {
        wc_self_destroy(sc);
        return st;
    }
    /* children follow their parent (preorder): one backward sweep gives every subtree's maximum */
    for (int k = sc->edge_bvh.n_nodes - 1; k >= 0; --k) {
        const int* ch = sc->edge_bvh.child + 2 * k;
        sc->edge_max[k] = ch[0] < 0 ? ch[1] : (sc->edge_max[ch[0]] > sc->edge_max[ch[1]] ? sc->edge_max[ch[0]] : sc->edge_max[ch[1]]);
    }
    sc->tangled_pairs = mark_tangled(sc, m);
    memcpy(sc->x_start, m->rest_pos, 3 * (size_t)n * sizeof(double));
    *out = sc;
    return WC_OK;
}

void wc_self_begin(wc_self* sc, const double* x) { memcpy(sc->x_start, x, 3 * (size_t)sc->n * sizeof(double)); }

/* ---- pairs ------------------------------------------------------------------------------------ */

/* MODE_PROXIMITY: proximity impulses, then CCD impulses, on each pair (the first pass);
 * MODE_IMPULSE: CCD impulses; MODE_DETECT: CCD collisions merged into zones, nothing moved. */
enum { MODE_PROXIMITY = 0, MODE_IMPULSE = 1, MODE_DETECT = 2 };

typedef struct pass_ctx {
    wc_self* sc;
    const wc_model* m;
    double* x;          /* end positions, corrected in place (not in MODE_DETECT) */
    int mode;
    int query;          /* the vertex or edge being queried */
    int count;          /* CCD pairs acted on / found */
    int prox;           /* proximity impulses (MODE_PROXIMITY) */
    int dry;            /* 1: the read-only scan: nothing moved or merged, a pair that needs action
                           makes the visit return 1 (the query is marked, its visit stops) */
    const unsigned char* dirty; /* NULL: every pair; else (dry scan) only pairs with a particle i
                                   dirty[i] */
    unsigned char* touched;     /* NULL, or (serial visit) 1 for the particles of every pair acted
                                   on or counted: the next pass's dirty set */
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
    if (c->mode == MODE_PROXIMITY && lb < c->sc->thickness) return 0;
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
    if (linked(ls, ln, i, tv[0]) || linked(ls, ln, i, tv[1]) || linked(ls, ln, i, tv[2])) return 0;
    const unsigned char* tg = c->sc->tangled;
    if (tg[i] && tg[tv[0]] && tg[tv[1]] && tg[tv[2]]) return 0;
    int ids[4] = {i, tv[0], tv[1], tv[2]};
    const double* xs = c->sc->x_start;
    const double* x = c->x;
    double bw[3], q[3], w[4], n[3];
    if (c->mode == MODE_DETECT && same_zone(c, ids)) return 0;
    if (far_apart(c, ids, 1)) return 0;
    double d2 = wc_closest_on_triangle(xs + 3 * i, xs + 3 * tv[0], xs + 3 * tv[1], xs + 3 * tv[2], bw, q);
    if (c->mode == MODE_PROXIMITY) {
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
    if (c->mode == MODE_DETECT) {
        merge(c, ids);
        ++c->count;
        return 0;
    }
    /* counted whether or not an impulse can be applied (pinned, no normal, already separating
       along it): the pass is then not clean, and what impulses cannot fix the zones will */
    ++c->count;
    touch(c, ids);
    if (c->sc->passes == 0) return 0;
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
    if (linked(ls, ln, a0, b0) || linked(ls, ln, a0, b1) || linked(ls, ln, a1, b0) || linked(ls, ln, a1, b1)) return 0;
    const unsigned char* tg = c->sc->tangled;
    if (tg[a0] && tg[a1] && tg[b0] && tg[b1]) return 0;
    int ids[4] = {a0, a1, b0, b1};
    const double* xs = c->sc->x_start;
    const double* x = c->x;
    double s, t, w[4], n[3];
    if (c->mode == MODE_DETECT && same_zone(c, ids)) return 0;
    if (far_apart(c, ids, 2)) return 0;
    double d2 = wc_closest_on_segments(xs + 3 * a0, xs + 3 * a1, xs + 3 * b0, xs + 3 * b1, &s, &t);
    if (c->mode == MODE_PROXIMITY) {
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
    if (c->mode == MODE_DETECT) {
        merge(c, ids);
        ++c->count;
        return 0;
    }
    ++c->count; /* as for vertex-triangle pairs */
    touch(c, ids);
    if (c->sc->passes == 0) return 0;
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

/* Edge e against the edges f > e whose tree boxes overlap box (self_collide.h), in the nodes of
 * the edge tree whose mask is set (mask NULL: all). */
static int edges_above(const wc_self* sc, int e, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                       void* user) {
    const wc_bvh* b = &sc->edge_bvh;
    const int* mx = sc->edge_max;
    if (b->n_nodes == 0) return 0;
    int stack[WC_BVH_MAX_DEPTH + 2];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (mx[node] <= e || (mask && !mask[node]) || !wc_box_overlap(b->box + 6 * node, box)) continue;
        const int* ch = b->child + 2 * node;
        if (ch[0] < 0) {
            int r = visit(user, ch[1]);
            if (r) return r;
        } else {
            stack[top++] = ch[1];
            stack[top++] = ch[0];
        }
    }
    return 0;
}

int wc_self_edges_above(const wc_self* sc, int e, const double* box, wc_bvh_visit_fn visit, void* user) {
    return edges_above(sc, e, box, NULL, visit, user);
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
        return wc_bvh_query_masked(&sc->tri_bvh, b, mask, visit_tri, c) != 0;
    }
    /* the edge's own box (not inflated twice: the tree's boxes carry r) */
    const int* ev = sc->edges + 2 * (q - sc->n);
    wc_self_swept_box(b, ev, 2, sc->x_start, c->x, 0.0);
    c->query = q - sc->n;
    const unsigned char* mask = dirty && !dirty[ev[0]] && !dirty[ev[1]] ? sc->edge_mask : NULL;
    return edges_above(sc, q - sc->n, b, mask, visit_edge_above, c) != 0;
}

/* The trees' masks: a leaf is dirty when one of its element's particles is (dirty[]), a node when
 * a leaf under it is. */
static void mark_dirty(wc_self* sc, const wc_model* m, const unsigned char* dirty) {
    for (int t = 0; t < sc->n_tris; ++t) {
        const int* tv = m->tris + 3 * t;
        sc->tri_mask[sc->tri_bvh.leaf_of[t]] = dirty[tv[0]] | dirty[tv[1]] | dirty[tv[2]];
    }
    wc_bvh_mask_up(&sc->tri_bvh, sc->tri_mask);
    for (int e = 0; e < sc->n_edges; ++e) {
        const int* ev = sc->edges + 2 * e;
        sc->edge_mask[sc->edge_bvh.leaf_of[e]] = dirty[ev[0]] | dirty[ev[1]];
    }
    wc_bvh_mask_up(&sc->edge_bvh, sc->edge_mask);
}

/* One pass over every vertex-triangle and edge-edge candidate (dirty non-NULL: only those with a
 * particle i dirty[i]); returns the CCD collisions found (given an impulse where one applies);
 * *prox (may be NULL) the proximity impulses. The parallel read-only scan marks the queries with
 * work (self_collide.h), then the marked ones are visited serially in index order. */
static int pass(wc_self* sc, const wc_model* m, double* x, int mode, int* prox, const unsigned char* dirty,
                unsigned char* touched) {
    double r = mode == MODE_PROXIMITY ? sc->thickness : sc->eta;
    int nq = sc->n + sc->n_edges;
    /* WC_PAR_REGION reads sc->threads (par.h's fixed contiguous ranges per thread) */
    wc_self_refit(sc, m, sc->x_start, x, r);
    if (dirty) mark_dirty(sc, m, dirty);
    WC_PAR_REGION(sc) {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
        wc_par_range(nq, t, nt, &lo, &hi);
        pass_ctx d = {sc, m, x, mode, 0, 0, 0, 1, dirty, NULL};
        for (int q = lo; q < hi; ++q) sc->active[q] = (unsigned char)query(&d, q);
    }
    /* the serial visits are those of the unfiltered pass: the scan marked the same queries (a pair
       with no dirty particle needs nothing), and a marked query visits all its candidates, so an
       impulse earlier in this pass that moved a clean pair is seen as it would be unfiltered */
    pass_ctx c = {sc, m, x, mode, 0, 0, 0, 0, NULL, touched};
    for (int q = 0; q < nq; ++q)
        if (sc->active[q]) query(&c, q);
    if (prox) *prox = c.prox;
    return c.count;
}

int wc_self_resolve(wc_self* sc, const wc_model* m, const wc_filter* filter, const unsigned char* stick, double he,
                    double* x, double* v, wc_self_stats* st) {
    int n = sc->n;
    if (sc->n_tris == 0) return 0;
    for (int i = 0; i < n; ++i) {
        int pinned = filter && filter->ndof[i] == 3 && !(stick && stick[i]);
        sc->inv_mass[i] = pinned ? 0.0 : m->inv_mass[i];
    }
    memcpy(sc->x_old, x, 3 * (size_t)n * sizeof(double));
    wc_self_stats local = {0, 0, 0, 0, 0};
    /* a pass that moved something (its trees were refitted before the moves, and pairs it checked
       early may have been moved later) proves nothing: only a pass that moved nothing shows the
       substep free of collisions; after WC_SELF_PASSES, the zone loop's detection passes decide.
       The first pass checks every pair; every later one only the pairs with a dirty particle: one
       of a pair that an earlier pass acted on or counted (touch), a zone's member, or one the
       relaxation moved. A pair with no dirty particle has not moved since a pass found it
       needing nothing, so it still needs nothing (tests compare both ways: detect_all). */
    unsigned char *dirty = sc->dirty, *touched = sc->dirty_next;
    memset(touched, 0, (size_t)n);
    local.impacts = pass(sc, m, x, MODE_PROXIMITY, &local.proximity, NULL, touched);
    int left = local.impacts + local.proximity;
    for (int p = 1; p < sc->passes && left; ++p) {
        unsigned char* tmp = dirty; /* this pass's dirty set: the last pass's touched particles */
        dirty = touched;
        touched = tmp;
        memset(touched, 0, (size_t)n);
        left = pass(sc, m, x, MODE_IMPULSE, NULL, sc->detect_all ? NULL : dirty, touched);
        local.impacts += left;
    }
    if (left) {
        for (int i = 0; i < n; ++i) {
            sc->parent[i] = i;
            sc->in_zone[i] = 0;
        }
        /* the zone loop's dirty set only grows: the last pass's touched particles, then every
           zone member and every particle the relaxation moved */
        dirty = touched;
        int it = 0;
        for (; it < WC_SELF_ZONE_ITERS; ++it) {
            left = pass(sc, m, x, MODE_DETECT, NULL, sc->detect_all ? NULL : dirty, NULL);
            if (left == 0) break;
            wc_self_rigidify(n, sc->x_start, x, m->mass, sc->inv_mass, sc->parent, sc->in_zone, sc->zone);
            for (int i = 0; i < n; ++i) dirty[i] |= sc->in_zone[i];
            if (sc->zone_strain < INFINITY)
                local.relaxed += wc_self_relax_zones(m, sc->x_old, x, sc->in_zone, sc->inv_mass, sc->zone_strain,
                                                     WC_SELF_RELAX_PASSES, dirty);
        }
        if (it == WC_SELF_ZONE_ITERS) local.unresolved = pass(sc, m, x, MODE_DETECT, NULL, NULL, NULL);
        for (int i = 0; i < n; ++i)
            if (sc->in_zone[i] && wc_uf_find(sc->parent, i) == i) ++local.zones;
    }
    for (int k = 0; k < 3 * n; ++k) v[k] += (x[k] - sc->x_old[k]) / he;
    if (st) {
        st->proximity += local.proximity;
        st->impacts += local.impacts;
        st->zones += local.zones;
        st->unresolved += local.unresolved;
        st->relaxed += local.relaxed;
    }
    return local.unresolved;
}

/* ---- intersection count ----------------------------------------------------------------------- */

static double orient(const double* a, const double* b, const double* c, const double* d) {
    double u[3], v[3], w[3], uv[3];
    v3_sub(u, b, a);
    v3_sub(v, c, a);
    v3_sub(w, d, a);
    v3_cross(uv, u, v);
    return v3_dot(uv, w);
}

/* Segment p-q passes through the interior of triangle a-b-c (strictly). */
static int seg_tri_cross(const double* p, const double* q, const double* a, const double* b, const double* c) {
    double o1 = orient(a, b, c, p), o2 = orient(a, b, c, q);
    if (!((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0))) return 0;
    double s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
    return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
}

static int edge_tri_cross(const wc_model* m, const int* ls, const int* ln, const double* x, int a, int b, int t) {
    const int* tv = m->tris + 3 * t;
    for (int k = 0; k < 3; ++k)
        if (linked(ls, ln, a, tv[k]) || linked(ls, ln, b, tv[k])) return 0;
    return seg_tri_cross(x + 3 * a, x + 3 * b, x + 3 * tv[0], x + 3 * tv[1], x + 3 * tv[2]);
}

int wc_self_intersections_brute(const wc_model* m, const double* x) {
    int count = 0;
    const wc_winged_edge* we = &m->we;
    wc_allocator A = {0};
    int *ls, *ln;
    if (seam_links_build(m, &A, &ls, &ln) != WC_OK) return -1;
    for (int e = 0; e < we->n_edges; ++e) {
        if (wc_we_repeats_previous(we, e)) continue;
        for (int t = 0; t < m->n_tris; ++t)
            count += edge_tri_cross(m, ls, ln, x, we->edges[e].v[0], we->edges[e].v[1], t);
    }
    wc_free(&A, ls);
    wc_free(&A, ln);
    return count;
}

typedef struct count_ctx {
    const wc_model* m;
    const int *ls, *ln;   /* seam links */
    const double* x;
    int a, b, count;
} count_ctx;

static int visit_count(void* user, int t) {
    count_ctx* c = (count_ctx*)user;
    c->count += edge_tri_cross(c->m, c->ls, c->ln, c->x, c->a, c->b, t);
    return 0;
}

wc_status wc_self_intersections(const wc_model* m, const double* x, const wc_allocator* alloc, int* count,
                                  wc_diag* diag) {
    if (count) *count = 0;
    if (!m || !x || !count) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "self intersections: NULL argument");
    if (m->n_tris == 0) return WC_OK;
    wc_allocator A = alloc ? *alloc : (wc_allocator){0};
    double* tb = WC_NEW(&A, double, 6 * (size_t)m->n_tris);
    if (!tb) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self intersections: out of memory");
    boxes(m, NULL, 0, NULL, x, 0.0, tb, NULL);
    int *ls, *ln;
    if (seam_links_build(m, &A, &ls, &ln) != WC_OK) {
        wc_free(&A, tb);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "self intersections: out of memory");
    }
    wc_bvh bvh;
    wc_status st = wc_bvh_build(&bvh, tb, m->n_tris, &A, diag);
    if (st != WC_OK) {
        wc_free(&A, tb);
        wc_free(&A, ls);
        wc_free(&A, ln);
        return st;
    }
    count_ctx c = {m, ls, ln, x, 0, 0, 0};
    const wc_winged_edge* we = &m->we;
    for (int e = 0; e < we->n_edges; ++e) {
        if (wc_we_repeats_previous(we, e)) continue;
        c.a = we->edges[e].v[0];
        c.b = we->edges[e].v[1];
        double b[6];
        wc_box_empty(b);
        wc_box_add(b, x + 3 * c.a);
        wc_box_add(b, x + 3 * c.b);
        wc_bvh_query(&bvh, b, visit_count, &c);
    }
    wc_bvh_free(&bvh);
    wc_free(&A, tb);
    wc_free(&A, ls);
    wc_free(&A, ln);
    *count = c.count;
    return WC_OK;
}
