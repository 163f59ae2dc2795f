/* Triangle-mesh colliders: creation, positions across a frame, the substep's interpolation and
 * BVH refit (mesh_collider.h). The queries are in mesh_query.c. */
#include "mesh_collider.h"
#include <math.h>
#include <string.h>
#include "vec3.h"

#define COORD_MAX 1e30

static int positions_ok(const double* x, int n) {
    for (int i = 0; i < 3 * n; ++i)
        if (!isfinite(x[i]) || fabs(x[i]) > COORD_MAX) return 0;
    return 1;
}

/* Unit normals of every triangle at positions x (zero for a degenerate one). */
static void tri_normals(const wc_mesh_collider* m, const double* x, double* nrm) {
    for (int t = 0; t < m->n_tris; ++t) {
        const int* v = m->tris + 3 * t;
        double e1[3], e2[3], c[3];
        v3_sub(e1, x + 3 * v[1], x + 3 * v[0]);
        v3_sub(e2, x + 3 * v[2], x + 3 * v[0]);
        v3_cross(c, e1, e2);
        double l = v3_norm(c);
        if (l > 1e-300) v3_scale(nrm + 3 * t, c, 1.0 / l);
        else v3_zero(nrm + 3 * t);
    }
}

/* Triangle boxes over xa u xb, inflated by the thickness. */
static void swept_boxes(wc_mesh_collider* m) {
    for (int t = 0; t < m->n_tris; ++t) {
        double* b = m->boxes + 6 * t;
        wc_box_empty(b);
        for (int k = 0; k < 3; ++k) {
            wc_box_add(b, m->xa + 3 * m->tris[3 * t + k]);
            wc_box_add(b, m->xb + 3 * m->tris[3 * t + k]);
        }
        wc_box_inflate(b, m->thickness);
    }
}

wc_status wc_mesh_collider_create(wc_mesh_collider** out, const double* x, int n_verts, const int* tris,
                                    int n_tris, double thickness, double friction, const wc_allocator* alloc,
                                    wc_diag* diag) {
    if (!out) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "mesh collider: NULL output");
    *out = NULL;
    if (!x || !tris) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "mesh collider: NULL positions or triangles");
    if (n_verts < 3 || n_tris < 1)
        return wc_fail(diag, WC_ERROR_EMPTY_MESH, "mesh collider: %d vertices and %d triangles (needs >= 3 and >= 1)",
                       n_verts, n_tris);
    if (!(thickness >= 0 && thickness < INFINITY) || !(friction >= 0 && friction < INFINITY))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "mesh collider: thickness %g and friction %g must be finite and >= 0", thickness, friction);
    if (!positions_ok(x, n_verts))
        return wc_fail(diag, WC_ERROR_NONFINITE, "mesh collider: non-finite (or beyond 1e30) vertex position");
    for (int k = 0; k < 3 * n_tris; ++k)
        if (tris[k] < 0 || tris[k] >= n_verts)
            return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "mesh collider: triangle %d: vertex index %d out of range [0, %d)",
                           k / 3, tris[k], n_verts);
    wc_allocator A = alloc ? *alloc : (wc_allocator){0};
    wc_mesh_collider* m = WC_NEW(&A, wc_mesh_collider, 1);
    if (!m) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "mesh collider: out of memory");
    m->alloc = A;
    m->n_verts = n_verts;
    m->n_tris = n_tris;
    m->thickness = thickness;
    m->friction = friction;
    size_t nv3 = 3 * (size_t)n_verts, nt3 = 3 * (size_t)n_tris;
    m->tris = WC_NEW(&A, int, nt3);
    double** arrs[] = {&m->rest, &m->from, &m->to, &m->xa, &m->xb, &m->vel};
    int ok = m->tris != NULL;
    for (size_t k = 0; k < sizeof arrs / sizeof arrs[0]; ++k) ok &= (*arrs[k] = WC_NEW(&A, double, nv3)) != NULL;
    m->nrm_a = WC_NEW(&A, double, nt3);
    m->nrm_b = WC_NEW(&A, double, nt3);
    m->boxes = WC_NEW(&A, double, 6 * (size_t)n_tris);
    if (!ok || !m->nrm_a || !m->nrm_b || !m->boxes) {
        wc_mesh_collider_destroy(m);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "mesh collider: out of memory (%d triangles)", n_tris);
    }
    memcpy(m->tris, tris, nt3 * sizeof(int));
    memcpy(m->rest, x, nv3 * sizeof(double));
    wc_mesh_collider_set_all(m, x, NULL);
    swept_boxes(m);
    wc_status st = wc_bvh_build(&m->bvh, m->boxes, n_tris, &A, diag);
    if (st != WC_OK) {
        wc_mesh_collider_destroy(m);
        return st;
    }
    wc_mesh_poses_init(m);
    *out = m;
    return WC_OK;
}

void wc_mesh_collider_destroy(wc_mesh_collider* m) {
    if (!m) return;
    wc_allocator A = m->alloc;
    wc_bvh_free(&m->bvh);
    void* arrs[] = {m->tris, m->rest, m->from, m->to, m->xa, m->xb, m->vel, m->nrm_a, m->nrm_b, m->boxes};
    for (size_t k = 0; k < sizeof arrs / sizeof arrs[0]; ++k) wc_free(&A, arrs[k]);
    wc_free(&A, m);
}

wc_status wc_mesh_collider_set_target(wc_mesh_collider* m, const double* x, wc_diag* diag) {
    if (!m || !x) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "mesh collider positions: NULL argument");
    if (!positions_ok(x, m->n_verts))
        return wc_fail(diag, WC_ERROR_NONFINITE, "mesh collider positions: non-finite (or beyond 1e30) value");
    memcpy(m->to, x, 3 * (size_t)m->n_verts * sizeof(double));
    return WC_OK;
}

wc_status wc_mesh_collider_set_all(wc_mesh_collider* m, const double* x, wc_diag* diag) {
    wc_status st = wc_mesh_collider_set_target(m, x, diag);
    if (st != WC_OK) return st;
    size_t nv3 = 3 * (size_t)m->n_verts * sizeof(double);
    double jump = 0.0;
    for (int i = 0; i < 3 * m->n_verts; ++i) jump = fmax(jump, fmax(fabs(x[i] - m->xa[i]), fabs(x[i] - m->xb[i])));
    m->travel = nextafter(m->travel + jump, INFINITY); /* never below the sum: a bound */
    memcpy(m->from, x, nv3);
    memcpy(m->xa, x, nv3);
    memcpy(m->xb, x, nv3);
    memset(m->vel, 0, nv3);
    m->max_speed = 0.0;
    tri_normals(m, m->xa, m->nrm_a);
    tri_normals(m, m->xb, m->nrm_b);
    if (m->bvh.n_nodes > 0) {
        swept_boxes(m);
        wc_bvh_refit(&m->bvh, m->boxes);
        wc_mesh_poses_update(m);
    }
    return WC_OK;
}

int wc_mesh_collider_moving(const wc_mesh_collider* m) {
    if (m->on_device) return m->device_moves;
    return memcmp(m->from, m->to, 3 * (size_t)m->n_verts * sizeof(double)) != 0;
}

void wc_mesh_collider_end_frame(wc_mesh_collider* m) {
    memcpy(m->from, m->to, 3 * (size_t)m->n_verts * sizeof(double));
}

void wc_mesh_collider_substep(wc_mesh_collider* m, double a0, double a1, double h) {
    double vmax2 = 0.0, jump = 0.0;
    for (int i = 0; i < 3 * m->n_verts; i += 3) {
        for (int c = 0; c < 3; ++c) {
            double f = m->from[i + c], d = m->to[i + c] - f;
            /* a fraction of exactly 1 lands exactly on the target */
            double xa = a0 >= 1.0 ? m->to[i + c] : f + a0 * d, xb = a1 >= 1.0 ? m->to[i + c] : f + a1 * d;
            jump = fmax(jump, fmax(fabs(xa - m->xa[i + c]), fabs(xb - m->xb[i + c])));
            m->xa[i + c] = xa;
            m->xb[i + c] = xb;
            m->vel[i + c] = h > 0.0 ? (m->xb[i + c] - m->xa[i + c]) / h : 0.0;
        }
        double v2 = v3_dot(m->vel + i, m->vel + i);
        if (v2 > vmax2) vmax2 = v2;
    }
    m->travel = nextafter(m->travel + jump, INFINITY); /* never below the sum: a bound */
    m->h = h;
    m->max_speed = sqrt(vmax2);
    tri_normals(m, m->xa, m->nrm_a);
    tri_normals(m, m->xb, m->nrm_b);
    swept_boxes(m);
    wc_bvh_refit(&m->bvh, m->boxes);
    if (jump != 0.0) wc_mesh_poses_update(m); /* nothing moved: the same state */
}

void wc_mesh_collider_serial(wc_mesh_collider* m, wc_serial* k) {
    size_t nv3 = 3 * (size_t)m->n_verts * sizeof(double);
    wc_serial_bytes(k, m->from, nv3);
    wc_serial_bytes(k, m->to, nv3);
    if (wc_serial_reading(k)) wc_mesh_collider_substep(m, 0.0, 0.0, 0.0);
}
