/* wc_source_mesh from host arrays, and freeing. The file importer is in import_assimp.c. */
#include "source_mesh.h"
#include <limits.h>
#include <math.h>
#include <string.h>

void wc_source_mesh_free(wc_source_mesh* m) {
    if (!m) return;
    wc_allocator a = m->alloc;
    wc_free(&a, m->pos);
    wc_free(&a, m->poly_start);
    wc_free(&a, m->poly_verts);
    memset(m, 0, sizeof *m);
}

wc_status wc_source_mesh_from_arrays(wc_source_mesh* out, const wc_allocator* alloc,
                                       const double* positions, int n_verts,
                                       const int* poly_sizes, int n_polys, const int* indices,
                                       double scale, wc_diag* diag) {
    if (!out) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "source mesh: out is NULL");
    memset(out, 0, sizeof *out);
    if (n_verts < 0 || n_polys < 0)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "source mesh: negative count (n_verts %d, n_polys %d)", n_verts, n_polys);
    if (n_verts > INT_MAX / 3)
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "source mesh: n_verts %d is too large",
                       n_verts);
    if (n_verts > 0 && !positions)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "source mesh: positions is NULL with n_verts %d", n_verts);
    if (n_polys > 0 && !poly_sizes)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "source mesh: poly_sizes is NULL with n_polys %d", n_polys);
    if (!(isfinite(scale) && scale > 0.0))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "source mesh: scale %g must be finite and > 0", scale);

    /* Corner counts: every polygon's indices are checked, kept ones are >= 3 corners. */
    long long n_idx = 0, n_keep_corners = 0;
    int n_keep = 0, n_points = 0, n_lines = 0;
    for (int p = 0; p < n_polys; ++p) {
        int s = poly_sizes[p];
        if (s < 1)
            return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                           "source mesh: polygon %d has %d corners (must be >= 1)", p, s);
        n_idx += s;
        if (n_idx > INT_MAX)
            return wc_fail(diag, WC_ERROR_OUT_OF_RANGE,
                           "source mesh: more than %d polygon corners", INT_MAX);
        if (s == 1) ++n_points;
        else if (s == 2) ++n_lines;
        else { ++n_keep; n_keep_corners += s; }
    }
    if (n_idx > 0 && !indices)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "source mesh: indices is NULL with %lld polygon corners", n_idx);
    for (long long k = 0, p = 0, end = n_polys > 0 ? poly_sizes[0] : 0; k < n_idx; ++k) {
        while (k >= end) end += poly_sizes[++p];
        if (indices[k] < 0 || indices[k] >= n_verts)
            return wc_fail(diag, WC_ERROR_OUT_OF_RANGE,
                           "source mesh: indices[%lld] = %d (corner %lld of polygon %lld) is "
                           "outside [0, %d)", k, indices[k], k - (end - poly_sizes[p]), p, n_verts);
    }
    for (int v = 0; v < n_verts; ++v) {
        const double* x = positions + 3 * (size_t)v;
        for (int c = 0; c < 3; ++c) {
            if (!isfinite(x[c]) || !isfinite(x[c] * scale))
                return wc_fail(diag, WC_ERROR_NONFINITE,
                               "source mesh: vertex %d is not finite (%g, %g, %g, scale %g)", v,
                               x[0], x[1], x[2], scale);
        }
    }
    if (n_keep == 0)
        return wc_fail(diag, WC_ERROR_EMPTY_MESH,
                       "source mesh: no polygons with >= 3 corners (%d vertices, %d points, "
                       "%d lines)", n_verts, n_points, n_lines);

    wc_source_mesh m;
    memset(&m, 0, sizeof m);
    if (alloc) m.alloc = *alloc;
    m.pos = WC_NEW(&m.alloc, double, 3 * (size_t)n_verts);
    m.poly_start = WC_NEW(&m.alloc, int, (size_t)n_keep + 1);
    m.poly_verts = WC_NEW(&m.alloc, int, (size_t)n_keep_corners);
    if (!m.pos || !m.poly_start || !m.poly_verts) {
        wc_source_mesh_free(&m);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY,
                       "source mesh: out of memory for %d vertices, %d polygons", n_verts, n_keep);
    }
    for (size_t i = 0; i < 3 * (size_t)n_verts; ++i) m.pos[i] = positions[i] * scale;
    int q = 0, c = 0;
    long long k = 0;
    for (int p = 0; p < n_polys; ++p) {
        int s = poly_sizes[p];
        if (s >= 3) {
            m.poly_start[q++] = c;
            for (int j = 0; j < s; ++j) m.poly_verts[c++] = indices[k + j];
        }
        k += s;
    }
    m.poly_start[q] = c;
    m.n_verts = n_verts;
    m.n_polys = n_keep;
    m.n_points = n_points;
    m.n_lines = n_lines;
    m.n_meshes = 1;
    m.unit_scale = scale;
    *out = m;
    return WC_OK;
}
