/* Seam search (see sew.h): boundary vertices in a sorted uniform grid, each boundary edge visits
 * the cells its box (grown by sew_distance) covers and offers its closest point to the vertices
 * of other panels found there; each vertex keeps its closest offer. */
#include "sew.h"
#include <math.h>
#include <stdint.h>
#include <string.h>
#include "sort.h"
#include "union_find.h"
#include "vec3.h"

#define CELL_BITS 21
#define CELL_MAX ((1 << CELL_BITS) - 1)

double wc_seam_gap(const wc_seam* s, const double* x) {
    double g[3];
    for (int k = 0; k < 3; ++k)
        g[k] = x[3 * s->p + k] - (1.0 - s->t) * x[3 * s->q0 + k] - s->t * x[3 * s->q1 + k];
    return v3_norm(g);
}

static int is_boundary(const wc_we_edge* e) { return e->f[1] < 0 && !(e->flags & WC_EDGE_NON_MANIFOLD); }

static uint64_t cell_key(const int c[3]) {
    return ((uint64_t)c[0] << (2 * CELL_BITS)) | ((uint64_t)c[1] << CELL_BITS) | (uint64_t)c[2];
}

static int cell_of(double x, double lo, double h) {
    double c = floor((x - lo) / h);
    if (c < 0) return 0;
    if (c > CELL_MAX) return CELL_MAX;
    return (int)c;
}

/* First index in sorted keys[0..n) with key >= k. */
static int lower_bound(const wc_keyed* keys, int n, uint64_t k) {
    int lo = 0, hi = n;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (keys[mid].key < k) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Closest point of segment (a, b) to p: parameter t in [0, 1] and distance. */
static double closest_on_segment(const double* p, const double* a, const double* b, double* t_out) {
    double ab[3], ap[3];
    v3_sub(ab, b, a);
    v3_sub(ap, p, a);
    double l2 = v3_dot(ab, ab), t = l2 > 0.0 ? v3_dot(ap, ab) / l2 : 0.0;
    if (t < 0.0) t = 0.0;
    if (t > 1.0) t = 1.0;
    double d[3];
    for (int k = 0; k < 3; ++k) d[k] = ap[k] - t * ab[k];
    *t_out = t;
    return v3_norm(d);
}

typedef struct sew_tmp {
    unsigned char* bv;   /* (np) boundary vertex */
    wc_keyed* keys;      /* (n boundary vertices) cell key -> particle */
    double* best;        /* (np) distance of the closest offer */
    int* best_e;         /* (np) edge of it, -1 none */
    double* best_t;      /* (np) its parameter */
    int* parent;         /* (n_components) union-find */
} sew_tmp;

static void tmp_free(sew_tmp* t, const wc_allocator* a) {
    wc_free(a, t->bv);
    wc_free(a, t->keys);
    wc_free(a, t->best);
    wc_free(a, t->best_e);
    wc_free(a, t->best_t);
    wc_free(a, t->parent);
}

/* Offers of every boundary edge to the boundary vertices of other panels (fills best*). */
static int offer_edges(const wc_sew_input* in, sew_tmp* t, const wc_allocator* a) {
    const wc_winged_edge* we = in->we;
    const double* x = in->pos;
    const double d = in->sew_distance;
    int nbv = 0, nbe = 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, len = 0.0;
    for (int e = 0; e < we->n_edges; ++e) {
        const wc_we_edge* ed = &we->edges[e];
        if (!is_boundary(ed)) continue;
        ++nbe;
        double ev[3];
        v3_sub(ev, x + 3 * ed->v[0], x + 3 * ed->v[1]);
        len += v3_norm(ev);
        for (int s = 0; s < 2; ++s) t->bv[ed->v[s]] = 1;
    }
    if (nbe == 0) return 0;
    for (int p = 0; p < in->n_particles; ++p) {
        if (!t->bv[p]) continue;
        ++nbv;
        for (int k = 0; k < 3; ++k) {
            if (x[3 * p + k] < lo[k]) lo[k] = x[3 * p + k];
            if (x[3 * p + k] > hi[k]) hi[k] = x[3 * p + k];
        }
    }
    double h = len / nbe > d ? len / nbe : d;
    for (int k = 0; k < 3; ++k) /* keep cell coordinates within CELL_BITS */
        if ((hi[k] - lo[k]) / h > CELL_MAX / 2) h = (hi[k] - lo[k]) / (CELL_MAX / 2);
    if (!(h > 0.0)) h = 1.0;
    t->keys = WC_NEW(a, wc_keyed, nbv);
    if (!t->keys) return -1;
    int n = 0;
    for (int p = 0; p < in->n_particles; ++p) {
        if (!t->bv[p]) continue;
        int c[3];
        for (int k = 0; k < 3; ++k) c[k] = cell_of(x[3 * p + k], lo[k], h);
        t->keys[n].key = cell_key(c);
        t->keys[n].val = p;
        ++n;
    }
    if (!wc_radix_sort(t->keys, n, 3 * CELL_BITS, a)) return -1;
    for (int e = 0; e < we->n_edges; ++e) {
        const wc_we_edge* ed = &we->edges[e];
        if (!is_boundary(ed)) continue;
        const double *q0 = x + 3 * ed->v[0], *q1 = x + 3 * ed->v[1];
        int cmp = in->component[ed->v[0]], c0[3], c1[3], c[3];
        for (int k = 0; k < 3; ++k) {
            c0[k] = cell_of((q0[k] < q1[k] ? q0[k] : q1[k]) - d, lo[k], h);
            c1[k] = cell_of((q0[k] > q1[k] ? q0[k] : q1[k]) + d, lo[k], h);
        }
        for (c[0] = c0[0]; c[0] <= c1[0]; ++c[0])
            for (c[1] = c0[1]; c[1] <= c1[1]; ++c[1])
                for (c[2] = c0[2]; c[2] <= c1[2]; ++c[2]) {
                    uint64_t key = cell_key(c);
                    for (int i = lower_bound(t->keys, n, key); i < n && t->keys[i].key == key; ++i) {
                        int p = t->keys[i].val;
                        if (in->component[p] == cmp) continue;
                        double tt, dist = closest_on_segment(x + 3 * p, q0, q1, &tt);
                        if (dist <= d && (t->best_e[p] < 0 || dist < t->best[p])) {
                            t->best[p] = dist;
                            t->best_e[p] = e;
                            t->best_t[p] = tt;
                        }
                    }
                }
    }
    return 0;
}

/* Vertex p's offer as a seam, snapped to an edge end when within WC_SEW_SNAP. */
static wc_seam offer_seam(const wc_sew_input* in, const sew_tmp* t, int p) {
    const wc_we_edge* ed = &in->we->edges[t->best_e[p]];
    wc_seam s = {p, ed->v[0], ed->v[1], t->best_t[p]};
    if (s.t <= WC_SEW_SNAP) {
        s.q1 = s.q0;
        s.t = 0.0;
    } else if (s.t >= 1.0 - WC_SEW_SNAP) {
        s.q0 = s.q1;
        s.t = 0.0;
    }
    return s;
}

int wc_sew_find(const wc_sew_input* in, wc_seam** out, int* n_out, int* n_panels, const wc_allocator* a) {
    *out = NULL;
    *n_out = 0;
    *n_panels = in->n_components;
    const int np = in->n_particles;
    sew_tmp t;
    memset(&t, 0, sizeof t);
    t.bv = WC_NEW(a, unsigned char, np + 1);
    t.best = WC_NEW(a, double, np + 1);
    t.best_e = WC_NEW(a, int, np + 1);
    t.best_t = WC_NEW(a, double, np + 1);
    t.parent = WC_NEW(a, int, in->n_components + 1);
    if (!t.bv || !t.best || !t.best_e || !t.best_t || !t.parent) goto oom;
    for (int p = 0; p < np; ++p) t.best_e[p] = -1;
    if (in->sew_distance > 0.0 && offer_edges(in, &t, a) != 0) goto oom;

    int cap = in->n_pairs;
    for (int p = 0; p < np; ++p) cap += t.best_e[p] >= 0;
    wc_seam* seams = cap > 0 ? WC_NEW(a, wc_seam, cap) : NULL;
    if (cap > 0 && !seams) goto oom;
    int ns = 0;
    for (int p = 0; p < np; ++p) {
        if (t.best_e[p] < 0) continue;
        wc_seam s = offer_seam(in, &t, p);
        if (s.q1 == s.q0 && s.q0 < p && t.best_e[s.q0] >= 0) { /* the pair from both sides: keep once */
            wc_seam back = offer_seam(in, &t, s.q0);
            if (back.q1 == back.q0 && back.q0 == p) continue;
        }
        seams[ns++] = s;
    }
    for (int i = 0; i < in->n_pairs; ++i) {
        wc_seam s = {in->pair_a[i], in->pair_b[i], in->pair_b[i], 0.0};
        seams[ns++] = s;
    }
    for (int c = 0; c < in->n_components; ++c) t.parent[c] = c;
    for (int i = 0; i < ns; ++i) {
        wc_uf_union(t.parent, in->component[seams[i].p], in->component[seams[i].q0]);
        wc_uf_union(t.parent, in->component[seams[i].p], in->component[seams[i].q1]);
    }
    int panels = 0;
    for (int c = 0; c < in->n_components; ++c) panels += wc_uf_find(t.parent, c) == c;
    tmp_free(&t, a);
    *out = seams;
    *n_out = ns;
    *n_panels = panels;
    return 0;
oom:
    tmp_free(&t, a);
    return -1;
}
