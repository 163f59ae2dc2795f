/* Self-collision's broad phase and seam links (self_broad.h). */
#include "self_broad.h"
#include "par.h"

wc_status wc_self_seam_links(const wc_model* m, const wc_allocator* A, int** start_out, int** nbr_out) {
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

int wc_self_linked(const wc_self* sc, int a, int b) { return wc_self_seam_linked(sc->seam_start, sc->seam_nbr, a, b); }

void wc_self_swept_box(double* b, const int* v, int nv, const double* x_start, const double* x, double r) {
    wc_box_empty(b);
    for (int k = 0; k < nv; ++k) {
        wc_box_add(b, x + 3 * v[k]);
        if (x_start) wc_box_add(b, x_start + 3 * v[k]);
    }
    wc_box_inflate(b, r);
}

void wc_self_boxes(const wc_model* m, const int* edges, int n_edges, const double* x_start, const double* x, double r,
                   double* tri_box, double* edge_box) {
    for (int t = 0; t < m->n_tris; ++t) wc_self_swept_box(tri_box + 6 * t, m->tris + 3 * t, 3, x_start, x, r);
    if (!edge_box) return;
    for (int e = 0; e < n_edges; ++e) wc_self_swept_box(edge_box + 6 * e, edges + 2 * e, 2, x_start, x, r);
}

void wc_self_trees_sweep(wc_self* sc, int mask_up, int refit) {
    int ns = sc->tri_split.n_sub, nsub = ns + sc->edge_split.n_sub;
    WC_PAR_FOR_DYNAMIC(1)
    for (int k = 0; k < nsub; ++k) {
        int tri = k < ns;
        wc_bvh* b = tri ? &sc->tri_bvh : &sc->edge_bvh;
        const int* sub = (tri ? sc->tri_split.sub : sc->edge_split.sub) + 2 * (tri ? k : k - ns);
        unsigned char* mask = mask_up ? (tri ? sc->tri_mask : sc->edge_mask) : NULL;
        if (mask) wc_bvh_mask_up_span(b, mask, sub[0], sub[1]);
        if (refit) wc_bvh_refit_span(b, tri ? sc->tri_box : sc->edge_box, mask, sub[0], sub[1]);
    }
}

void wc_self_trees_top(wc_self* sc, int mask_up, int refit) {
    if (mask_up) {
        wc_bvh_mask_up_top(&sc->tri_bvh, &sc->tri_split, sc->tri_mask);
        wc_bvh_mask_up_top(&sc->edge_bvh, &sc->edge_split, sc->edge_mask);
    }
    if (refit) {
        wc_bvh_refit_top(&sc->tri_bvh, &sc->tri_split, mask_up ? sc->tri_mask : NULL);
        wc_bvh_refit_top(&sc->edge_bvh, &sc->edge_split, mask_up ? sc->edge_mask : NULL);
    }
}

void wc_self_refit(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r) {
    WC_PAR_REGION(sc) {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
        wc_par_range(m->n_tris, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) wc_self_swept_box(sc->tri_box + 6 * k, m->tris + 3 * k, 3, x0, x1, r);
        wc_par_range(sc->n_edges, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) wc_self_swept_box(sc->edge_box + 6 * k, sc->edges + 2 * k, 2, x0, x1, r);
        WC_PAR_BARRIER(); /* every box before the trees */
        wc_self_trees_sweep(sc, 0, 1);
    }
    wc_self_trees_top(sc, 0, 1);
}

int wc_self_edges_above_masked(const wc_self* sc, int e, const double* box, const unsigned char* mask,
                               wc_bvh_visit_fn visit, void* user) {
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
    return wc_self_edges_above_masked(sc, e, box, NULL, visit, user);
}
