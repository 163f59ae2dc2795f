/* Edge-triangle crossings: the test, and the counters (self_crossings.h). */
#include "self_crossings.h"
#include "self_broad.h"
#include "vec3.h"

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

int wc_self_edge_tri_cross(const wc_model* m, const int* ls, const int* ln, const double* x, int a, int b, int t) {
    const int* tv = m->tris + 3 * t;
    for (int k = 0; k < 3; ++k)
        if (wc_self_seam_linked(ls, ln, a, tv[k]) || wc_self_seam_linked(ls, ln, b, tv[k])) return 0;
    return seg_tri_cross(x + 3 * a, x + 3 * b, x + 3 * tv[0], x + 3 * tv[1], x + 3 * tv[2]);
}

int wc_self_intersections_brute(const wc_model* m, const double* x) {
    int count = 0;
    const wc_winged_edge* we = &m->we;
    wc_allocator A = {0};
    int *ls, *ln;
    if (wc_self_seam_links(m, &A, &ls, &ln) != WC_OK) return -1;
    for (int e = 0; e < we->n_edges; ++e) {
        if (wc_we_repeats_previous(we, e)) continue;
        for (int t = 0; t < m->n_tris; ++t)
            count += wc_self_edge_tri_cross(m, ls, ln, x, we->edges[e].v[0], we->edges[e].v[1], t);
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
    c->count += wc_self_edge_tri_cross(c->m, c->ls, c->ln, c->x, c->a, c->b, t);
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
    wc_self_boxes(m, NULL, 0, NULL, x, 0.0, tb, NULL);
    int *ls, *ln;
    if (wc_self_seam_links(m, &A, &ls, &ln) != WC_OK) {
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
