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

/* b = the union of the particles' boxes pb of v[0 .. nv) (from empty, in that order), inflated by r:
 * wc_self_swept_box's box to the bit. That adds x1 then x0 of each particle in turn with strict
 * comparisons, so each bound is the first of those coordinates to reach the extreme (NaN never
 * does); a particle's box holds the first of its own two, and the union, taken in the same
 * particle order with the same comparisons, the first particle's whose box reaches it. */
static void union_box(double* b, const double* pb, const int* v, int nv, double r) {
    wc_box_empty(b);
    for (int j = 0; j < nv; ++j) {
        const double* q = pb + 6 * (size_t)v[j];
        for (int k = 0; k < 3; ++k) {
            if (q[k] < b[k]) b[k] = q[k];
            if (q[3 + k] > b[3 + k]) b[3 + k] = q[3 + k];
        }
    }
    wc_box_inflate(b, r);
}

void wc_self_refit(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r) {
    double* pb = sc->part_box;
    WC_PAR_REGION(sc) {
        int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
        /* each particle's box of x1, x0 once (2 points), then each element's the union of its
           particles' (3 boxes a triangle, 2 an edge, where the direct box adds 6 and 4 points) */
        wc_par_range(sc->n, t, nt, &lo, &hi);
        for (int i = lo; i < hi; ++i) { /* not inflated: the elements' boxes are, once */
            double* b = pb + 6 * (size_t)i;
            wc_box_empty(b);
            wc_box_add(b, x1 + 3 * (size_t)i);
            if (x0) wc_box_add(b, x0 + 3 * (size_t)i);
        }
        WC_PAR_BARRIER(); /* every particle's box before the elements' */
        wc_par_range(m->n_tris, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) union_box(sc->tri_box + 6 * k, pb, m->tris + 3 * k, 3, r);
        wc_par_range(sc->n_edges, t, nt, &lo, &hi);
        for (int k = lo; k < hi; ++k) union_box(sc->edge_box + 6 * k, pb, sc->edges + 2 * k, 2, r);
        WC_PAR_BARRIER(); /* every box before the trees */
        wc_self_trees_sweep(sc, 0, 1);
    }
    wc_self_trees_top(sc, 0, 1);
}

/* wc_bvh_query_masked's walk (each child tested before the walk goes down to it, a lone passing
 * child entered without the stack) with the subtrees of edges <= e skipped. */
int wc_self_edges_above_masked(const wc_self* sc, int e, const double* box, const unsigned char* mask,
                               wc_bvh_visit_fn visit, void* user) {
    const wc_bvh* b = &sc->edge_bvh;
    const int* mx = sc->edge_max;
    if (b->n_nodes == 0 || mx[0] <= e || (mask && !mask[0]) || !wc_box_overlap(b->box, box)) return 0;
    int stack[WC_BVH_MAX_DEPTH + 2];
    int top = 0, node = 0;
    for (;;) {
        const int* ch = b->child + 2 * node;
        if (ch[0] < 0) {
            int r = visit(user, ch[1]);
            if (r) return r;
            if (top == 0) return 0;
            node = stack[--top];
            continue;
        }
        int l = ch[0], rt = ch[1];
        int in_r = mx[rt] > e && !(mask && !mask[rt]) && wc_box_overlap(b->box + 6 * rt, box);
        int in_l = mx[l] > e && !(mask && !mask[l]) && wc_box_overlap(b->box + 6 * l, box);
        if (in_l) {
            if (in_r) stack[top++] = rt;
            node = l;
        } else if (in_r) {
            node = rt;
        } else {
            if (top == 0) return 0;
            node = stack[--top];
        }
    }
}

int wc_self_edges_above(const wc_self* sc, int e, const double* box, wc_bvh_visit_fn visit, void* user) {
    return wc_self_edges_above_masked(sc, e, box, NULL, visit, user);
}
