#include "springs.h"
#include <math.h>
#include "sort.h"

typedef struct cand_buf {
    uint64_t* items;      /* (pair << 2) | type */
    int n, cap;
    uint64_t np;
} cand_buf;

static void add(cand_buf* c, int a, int b, int type) {
    if (a < 0 || b < 0 || a == b) return; /* capacity is exact by construction */
    uint64_t lo = (uint64_t)(a < b ? a : b), hi = (uint64_t)(a < b ? b : a);
    c->items[c->n++] = ((lo * c->np + hi) << 2) | (uint64_t)type;
}

static double dist(const double* pos, int a, int b) {
    double dx = pos[3 * a] - pos[3 * b], dy = pos[3 * a + 1] - pos[3 * b + 1],
           dz = pos[3 * a + 2] - pos[3 * b + 2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

wc_status wc_build_springs(const wc_spring_input* in, wc_spring** out, int* n_out,
                             int type_start[WC_SPRING_TYPE_COUNT + 1], const wc_allocator* alloc,
                             wc_diag* diag) {
    const wc_winged_edge* we = in->we;
    const int np = in->n_particles;
    *out = NULL;
    *n_out = 0;
    if (np >= (1 << 30))
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "springs: %d particles is too many", np);

    /* polygon-edge adjacency (CSR) for the bend springs */
    int* deg = WC_NEW(alloc, int, np + 1);
    int* adj = WC_NEW(alloc, int, 2 * (size_t)we->n_edges + 1);
    int* fill = WC_NEW(alloc, int, np + 1);
    cand_buf c = {0};
    c.np = (uint64_t)np;
    if (!deg || !adj || !fill) goto oom;
    int n_poly_edges = 0;
    for (int e = 0; e < we->n_edges; ++e) {
        const wc_we_edge* ed = &we->edges[e];
        /* non-manifold copies repeat a pair: count each pair once (first copy) */
        if (!(ed->flags & WC_EDGE_POLYGON)) continue;
        if (wc_we_repeats_previous(we, e)) continue;
        ++deg[ed->v[0] + 1];
        ++deg[ed->v[1] + 1];
        ++n_poly_edges;
    }
    for (int v = 0; v < np; ++v) deg[v + 1] += deg[v];
    for (int v = 0; v < np; ++v) fill[v] = deg[v];
    for (int e = 0; e < we->n_edges; ++e) {
        const wc_we_edge* ed = &we->edges[e];
        if (!(ed->flags & WC_EDGE_POLYGON)) continue;
        if (wc_we_repeats_previous(we, e)) continue;
        adj[fill[ed->v[0]]++] = ed->v[1];
        adj[fill[ed->v[1]]++] = ed->v[0];
    }

    /* stretch <= edges, quad diagonals 2 per quad, wings <= edges, bend <= 2 per polygon edge */
    c.cap = 2 * we->n_edges + 2 * in->n_quads + 2 * n_poly_edges + 1;
    c.items = WC_NEW(alloc, uint64_t, c.cap);
    if (!c.items) goto oom;

    for (int e = 0; e < we->n_edges; ++e) /* stretch */
        if (we->edges[e].flags & WC_EDGE_POLYGON) add(&c, we->edges[e].v[0], we->edges[e].v[1], WC_SPRING_STRETCH);
    for (int q = 0; q < in->n_quads; ++q) { /* shear: quad diagonals */
        const int* v = in->quads + 4 * q;
        add(&c, v[0], v[2], WC_SPRING_SHEAR);
        add(&c, v[1], v[3], WC_SPRING_SHEAR);
    }
    for (int e = 0; e < we->n_edges; ++e) { /* shear: wing vertices across interior edges */
        const wc_we_edge* ed = &we->edges[e];
        if (ed->f[0] < 0 || ed->f[1] < 0 || (ed->flags & WC_EDGE_NON_MANIFOLD)) continue;
        if (in->tri_quad[ed->f[0]] && in->tri_quad[ed->f[1]]) continue;
        add(&c, wc_we_opposite_vertex(we, ed->f[0], e), wc_we_opposite_vertex(we, ed->f[1], e),
            WC_SPRING_SHEAR);
    }
    const double cos_max = cos(in->min_angle_deg * 3.14159265358979323846 / 180.0);
    for (int v = 0; v < np; ++v) { /* bend */
        const double* pv = in->pos + 3 * v;
        for (int i = deg[v]; i < deg[v + 1]; ++i) {
            int a = adj[i], best = -1;
            double best_cos = 2.0;
            double ua[3], la = 0;
            for (int k = 0; k < 3; ++k) {
                ua[k] = in->pos[3 * a + k] - pv[k];
                la += ua[k] * ua[k];
            }
            for (int j = deg[v]; j < deg[v + 1]; ++j) {
                int b = adj[j];
                if (b == a) continue;
                double dotp = 0, lb = 0;
                for (int k = 0; k < 3; ++k) {
                    double ub = in->pos[3 * b + k] - pv[k];
                    dotp += ua[k] * ub;
                    lb += ub * ub;
                }
                double cs = (la > 0 && lb > 0) ? dotp / sqrt(la * lb) : 2.0;
                if (cs < best_cos) {
                    best_cos = cs;
                    best = b;
                }
            }
            if (best >= 0 && best_cos <= cos_max + 1e-12) add(&c, a, best, WC_SPRING_BEND);
        }
    }

    if (!wc_radix_sort_u64(c.items, c.n, wc_bits_for(((uint64_t)np * (uint64_t)np) << 2), alloc)) goto oom;
    /* keep the lowest type of each pair; then order by type, (a, b) */
    int count[WC_SPRING_TYPE_COUNT] = {0};
    int m = 0;
    for (int i = 0; i < c.n; ++i) {
        if (i > 0 && (c.items[i] >> 2) == (c.items[m - 1] >> 2)) continue;
        c.items[m++] = c.items[i];
        ++count[c.items[i] & 3];
    }
    wc_spring* springs = WC_NEW(alloc, wc_spring, m > 0 ? m : 1);
    if (!springs) goto oom;
    type_start[0] = 0;
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) type_start[t + 1] = type_start[t] + count[t];
    int pos_of[WC_SPRING_TYPE_COUNT];
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) pos_of[t] = type_start[t];
    for (int i = 0; i < m; ++i) {
        uint64_t pair = c.items[i] >> 2;
        int t = (int)(c.items[i] & 3);
        wc_spring* s = &springs[pos_of[t]++];
        s->a = (int)(pair / c.np);
        s->b = (int)(pair % c.np);
        s->type = t;
        s->rest = dist(in->pos, s->a, s->b);
        s->w = 1.0;
    }
    wc_free(alloc, c.items);
    wc_free(alloc, deg);
    wc_free(alloc, adj);
    wc_free(alloc, fill);
    *out = springs;
    *n_out = m;
    return WC_OK;

oom:
    wc_free(alloc, c.items);
    wc_free(alloc, deg);
    wc_free(alloc, adj);
    wc_free(alloc, fill);
    return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "springs: out of memory");
}
