/* Scene mesh: grid generation, file reading (through the public API), transform, pin vertex
 * checks and selects. */
#include "scene_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void scene_mesh_free(scene_mesh* m) {
    if (!m) return;
    free(m->positions);
    free(m->face_sizes);
    free(m->face_start);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

weft_status scene_mesh_from_arrays(scene_mesh* out, const double* positions, int n_vertices, const int* face_sizes,
                                   int n_faces, const int* indices, cli_diag* diag) {
    memset(out, 0, sizeof *out);
    long long corners = 0;
    for (int f = 0; f < n_faces; ++f) corners += face_sizes[f];
    out->positions = malloc(sizeof(double) * 3 * (size_t)(n_vertices > 0 ? n_vertices : 1));
    out->face_sizes = malloc(sizeof(int) * (size_t)(n_faces > 0 ? n_faces : 1));
    out->face_start = malloc(sizeof(int) * ((size_t)n_faces + 1));
    out->indices = malloc(sizeof(int) * (size_t)(corners > 0 ? corners : 1));
    if (!out->positions || !out->face_sizes || !out->face_start || !out->indices) {
        scene_mesh_free(out);
        return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "out of memory for %d vertices", n_vertices);
    }
    if (n_vertices > 0) memcpy(out->positions, positions, sizeof(double) * 3 * (size_t)n_vertices);
    if (n_faces > 0) memcpy(out->face_sizes, face_sizes, sizeof(int) * (size_t)n_faces);
    if (corners > 0) memcpy(out->indices, indices, sizeof(int) * (size_t)corners);
    out->face_start[0] = 0;
    for (int f = 0; f < n_faces; ++f) out->face_start[f + 1] = out->face_start[f] + face_sizes[f];
    out->n_vertices = n_vertices;
    out->n_faces = n_faces;
    return WEFT_OK;
}

weft_status scene_make_grid(scene_mesh* out, int nx, int nz, double sx, double sz, cli_diag* diag) {
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
        cli_diag d = {0};
        st = scene_mesh_from_arrays(out, pos, nv, sizes, nq, idx, &d);
        if (st != WEFT_OK) cli_fail(diag, st, "grid: %s", d.message);
    }
    free(pos);
    free(sizes);
    free(idx);
    return st;
}

weft_status scene_mesh_read(scene_mesh* out, const char* path, const char* select, double scale, cli_diag* diag) {
    memset(out, 0, sizeof *out);
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = 1;
    weft_context* ctx = NULL;
    weft_status st = weft_context_create(WEFT_ABI, &cd, &ctx);
    if (st != WEFT_OK) return cli_fail(diag, st, "cannot create a context to read '%s'", path);
    weft_mesh_data md;
    st = weft_mesh_read(ctx, path, select, scale, &md);
    if (st != WEFT_OK) {
        static const char prefix[] = "weft_mesh_read: ";
        const char* msg = weft_context_last_error(ctx);
        if (strncmp(msg, prefix, sizeof prefix - 1) == 0) msg += sizeof prefix - 1;
        cli_fail(diag, st, "%s", msg);
    } else {
        st = scene_mesh_from_arrays(out, md.positions, md.n_vertices, md.face_sizes, md.n_faces, md.indices, diag);
        weft_mesh_free(ctx, &md);
    }
    weft_context_destroy(ctx);
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
    cli_diag d = {0};
    if (s->mesh_is_grid) {
        weft_status st = scene_make_grid(&s->mesh, s->grid_n[0], s->grid_n[1], s->grid_size[0], s->grid_size[1], &d);
        if (st != WEFT_OK) return cli_fail(diag, st, "%s: mesh.grid: %s", name, d.message);
    } else {
        weft_status st = scene_mesh_read(&s->mesh, s->mesh_file, s->mesh_select, s->mesh_scale, &d);
        if (st != WEFT_OK) return cli_fail(diag, st, "%s: mesh.file: %s", name, d.message);
    }
    if (s->has_transform) {
        scene_transform_points(s->transform, s->mesh.positions, s->mesh.n_vertices);
        for (int i = 0; i < 3 * s->mesh.n_vertices; ++i)
            if (!isfinite(s->mesh.positions[i]))
                return cli_fail(diag, WEFT_ERROR_SCENE, "%s: transform: vertex %d becomes non-finite", name, i / 3);
    }
    return WEFT_OK;
}

/* used[v] = 1 when host vertex v is a corner of some polygon. Caller frees. */
static unsigned char* used_vertices(const scene_mesh* m) {
    unsigned char* used = calloc((size_t)m->n_vertices + 1, 1);
    if (!used) return NULL;
    for (int k = 0; k < m->face_start[m->n_faces]; ++k) used[m->indices[k]] = 1;
    return used;
}

static weft_status select_vertices(scene_pin* p, const scene_mesh* m, const unsigned char* used, const char* name,
                                   int index, cli_diag* diag) {
    const int ax = p->select_axis;
    double extreme = p->select_max ? -INFINITY : INFINITY;
    for (int v = 0; v < m->n_vertices; ++v) {
        if (!used[v]) continue;
        double x = m->positions[3 * (size_t)v + ax];
        extreme = p->select_max ? fmax(extreme, x) : fmin(extreme, x);
    }
    free(p->vertices);   /* a repeated check selects afresh */
    p->vertices = NULL;
    p->n_vertices = 0;
    int n = 0;
    for (int v = 0; v < m->n_vertices; ++v)
        n += used[v] && fabs(m->positions[3 * (size_t)v + ax] - extreme) <= p->select_tolerance;
    p->vertices = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
    if (!p->vertices) return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    for (int v = 0; v < m->n_vertices; ++v)
        if (used[v] && fabs(m->positions[3 * (size_t)v + ax] - extreme) <= p->select_tolerance)
            p->vertices[p->n_vertices++] = v;
    if (p->n_vertices == 0)   /* only when the mesh has no used vertex, which the reader refuses */
        return cli_fail(diag, WEFT_ERROR_SCENE, "%s: pins[%d].select: selects no vertex", name, index);
    return WEFT_OK;
}

weft_status scene_mesh_check_pins(scene* s, const char* name, cli_diag* diag) {
    if (s->n_pins == 0) return WEFT_OK;
    unsigned char* used = used_vertices(&s->mesh);
    if (!used) return cli_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    weft_status st = WEFT_OK;
    for (int i = 0; i < s->n_pins && st == WEFT_OK; ++i) {
        scene_pin* p = &s->pins[i];
        if (p->from_select) {
            st = select_vertices(p, &s->mesh, used, name, i, diag);
            continue;
        }
        for (int k = 0; k < p->n_vertices && st == WEFT_OK; ++k) {
            int v = p->vertices[k];
            if (v >= s->mesh.n_vertices)
                st = cli_fail(diag, WEFT_ERROR_SCENE, "%s: pins[%d].vertices[%d]: %d is out of range (mesh has %d vertices)",
                             name, i, k, v, s->mesh.n_vertices);
            else if (!used[v])
                st = cli_fail(diag, WEFT_ERROR_SCENE,
                             "%s: pins[%d].vertices[%d]: vertex %d is a corner of no polygon (it is not simulated)",
                             name, i, k, v);
        }
    }
    free(used);
    return st;
}
