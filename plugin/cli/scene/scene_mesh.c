/* Scene mesh: grid generation, file import, transform, pin vertex checks and selects. */
#include "scene_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

weft_status scene_make_grid(wc_source_mesh* out, int nx, int nz, double sx, double sz, cli_diag* diag) {
    memset(out, 0, sizeof *out);
    if (nx < 2 || nz < 2 || (long long)nx * nz > SCENE_GRID_MAX_VERTICES || !(sx > 0) || !(sz > 0) ||
        !isfinite(sx) || !isfinite(sz))
        return cli_fail(diag, WEFT_ERROR_INVALID_ARGUMENT, "grid: invalid size %d x %d, %g x %g m", nx, nz, sx, sz);
    const int nv = nx * nz, nq = (nx - 1) * (nz - 1);
    double* pos = malloc(sizeof(double) * 3 * (size_t)nv);
    int* sizes = malloc(sizeof(int) * (size_t)nq);
    int* idx = malloc(sizeof(int) * 4 * (size_t)nq);
    weft_status st;
    if (!pos || !sizes || !idx) {
        st = cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "grid: out of memory for %d vertices", nv);
    } else {
        for (int j = 0; j < nz; ++j)
            for (int i = 0; i < nx; ++i) {
                double* p = pos + 3 * ((size_t)i + (size_t)nx * j);
                p[0] = -0.5 * sx + sx * i / (nx - 1);
                p[1] = 0.0;
                p[2] = -0.5 * sz + sz * j / (nz - 1);
            }
        int q = 0;
        for (int j = 0; j + 1 < nz; ++j)
            for (int i = 0; i + 1 < nx; ++i, ++q) {
                int a = i + nx * j;
                sizes[q] = 4;
                idx[4 * q + 0] = a;
                idx[4 * q + 1] = a + nx;
                idx[4 * q + 2] = a + nx + 1;
                idx[4 * q + 3] = a + 1;
            }
        wc_diag d = {0};
        st = (weft_status)wc_source_mesh_from_arrays(out, NULL, pos, nv, sizes, nq, idx, 1.0, &d);
        if (st != WEFT_OK) cli_fail(diag, st, "%s", d.message);
    }
    free(pos);
    free(sizes);
    free(idx);
    return st;
}

void scene_transform_points(const double t[16], double* pos, int n) {
    for (int v = 0; v < n; ++v) {
        double* p = pos + 3 * (size_t)v;
        double x = p[0], y = p[1], z = p[2];
        for (int r = 0; r < 3; ++r) p[r] = t[r] * x + t[4 + r] * y + t[8 + r] * z + t[12 + r];
    }
}

weft_status scene_mesh_make(scene* s, const char* name, cli_diag* diag) {
    weft_status st;
    if (s->mesh_is_grid) {
        cli_diag d = {0};
        st = scene_make_grid(&s->src, s->grid_n[0], s->grid_n[1], s->grid_size[0], s->grid_size[1], &d);
        if (st != WEFT_OK) return cli_fail(diag, st, "%s: mesh.grid: %s", name, d.message);
    } else {
        wc_import_opts opts = wc_default_import_opts();
        opts.scale = s->mesh_scale;
        opts.select = s->mesh_select;
        wc_diag d = {0};
        st = (weft_status)wc_import_file(&s->src, NULL, s->mesh_file, &opts, &d);
        if (st != WEFT_OK) return cli_fail(diag, st, "%s: mesh.file: %s", name, d.message);
    }
    if (s->has_transform) {
        scene_transform_points(s->transform, s->src.pos, s->src.n_verts);
        for (int i = 0; i < 3 * s->src.n_verts; ++i)
            if (!isfinite(s->src.pos[i]))
                return cli_fail(diag, WEFT_ERROR_SCENE, "%s: transform: vertex %d becomes non-finite", name, i / 3);
    }
    return WEFT_OK;
}

/* used[v] = 1 when host vertex v is a corner of some polygon. Caller frees. */
static unsigned char* used_vertices(const wc_source_mesh* m) {
    unsigned char* used = calloc((size_t)m->n_verts + 1, 1);
    if (!used) return NULL;
    for (int k = 0; k < m->poly_start[m->n_polys]; ++k) used[m->poly_verts[k]] = 1;
    return used;
}

static weft_status select_vertices(scene_pin* p, const wc_source_mesh* m, const unsigned char* used, const char* name,
                                   int index, cli_diag* diag) {
    const int ax = p->select_axis;
    double extreme = p->select_max ? -INFINITY : INFINITY;
    for (int v = 0; v < m->n_verts; ++v) {
        if (!used[v]) continue;
        double x = m->pos[3 * (size_t)v + ax];
        extreme = p->select_max ? fmax(extreme, x) : fmin(extreme, x);
    }
    free(p->vertices);   /* a repeated check selects afresh */
    p->vertices = NULL;
    p->n_vertices = 0;
    int n = 0;
    for (int v = 0; v < m->n_verts; ++v)
        n += used[v] && fabs(m->pos[3 * (size_t)v + ax] - extreme) <= p->select_tolerance;
    p->vertices = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    if (!p->vertices) return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    for (int v = 0; v < m->n_verts; ++v)
        if (used[v] && fabs(m->pos[3 * (size_t)v + ax] - extreme) <= p->select_tolerance)
            p->vertices[p->n_vertices++] = v;
    if (p->n_vertices == 0)   /* only when the mesh has no used vertex, which the importer refuses */
        return cli_fail(diag, WEFT_ERROR_SCENE, "%s: pins[%d].select: selects no vertex", name, index);
    return WEFT_OK;
}

weft_status scene_mesh_check_pins(scene* s, const char* name, cli_diag* diag) {
    if (s->n_pins == 0) return WEFT_OK;
    unsigned char* used = used_vertices(&s->src);
    if (!used) return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    weft_status st = WEFT_OK;
    for (int i = 0; i < s->n_pins && st == WEFT_OK; ++i) {
        scene_pin* p = &s->pins[i];
        if (p->from_select) {
            st = select_vertices(p, &s->src, used, name, i, diag);
            continue;
        }
        for (int k = 0; k < p->n_vertices && st == WEFT_OK; ++k) {
            int v = p->vertices[k];
            if (v >= s->src.n_verts)
                st = cli_fail(diag, WEFT_ERROR_SCENE, "%s: pins[%d].vertices[%d]: %d is out of range (mesh has %d vertices)",
                             name, i, k, v, s->src.n_verts);
            else if (!used[v])
                st = cli_fail(diag, WEFT_ERROR_SCENE,
                             "%s: pins[%d].vertices[%d]: vertex %d is a corner of no polygon (it is not simulated)",
                             name, i, k, v);
        }
    }
    free(used);
    return st;
}
