/* Triangle-mesh colliders of the ABI (weft_mesh_collider_def): defaults, validation, import
 * (file through core's assimp import, or host arrays; polygons triangulated, nothing welded),
 * the per-frame targets (rigid transform x rest, or the host's vertices) and
 * weft_cloth_set_mesh_collider_vertices. The core object (core/mesh_collider.h) holds the rest
 * shape (object space, m: its `rest`) and the world positions at the frame's start and end; the
 * step moves it linearly between them. Creation allocates everything; a frame allocates nothing. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "api_internal.h"
#include "source_mesh.h"
#include "triangulate.h"
#include "vec3.h"

weft_mesh_collider_def weft_default_mesh_collider_def(void) {
    weft_mesh_collider_def d;
    memset(&d, 0, sizeof d);
    d.unit_scale = 1.0;
    for (int k = 0; k < 16; ++k) d.transform[k] = (k % 5 == 0) ? 1.0f : 0.0f;
    d.thickness = 0.005;
    d.friction = 0.3;
    d.push_speed = 0.05;
    d.internal_cookie = WA_COOKIE_MESH_COLLIDER;
    return d;
}

#define FAIL(st, ...) return (snprintf(msg, msg_size, __VA_ARGS__), (st))

static weft_status validate_one(const weft_mesh_collider_def* d, int i, char* msg, size_t msg_size) {
    const char* p = "def->mesh_colliders";
    if (d->internal_cookie != WA_COOKIE_MESH_COLLIDER)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d] was not initialised by weft_default_mesh_collider_def() (internal_cookie)",
             p, i);
    const weft_mesh_desc* m = &d->mesh;
    if (m->path && m->positions) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh: both path and positions are set", p, i);
    if (!m->path && !m->positions) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh: neither path nor positions is set", p, i);
    if (m->path && m->path[0] == '\0') FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh.path is empty", p, i);
    if (m->positions) {
        if (m->n_vertices < 3) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh.n_vertices = %d must be >= 3", p, i, m->n_vertices);
        if (m->n_faces < 1) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh.n_faces = %d must be >= 1", p, i, m->n_faces);
        if (!m->indices) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh.indices is NULL", p, i);
        for (int k = 0; k < 3 * m->n_vertices; ++k)
            if (!isfinite(m->positions[k]))
                FAIL(WEFT_ERROR_NONFINITE, "%s[%d].mesh.positions[%d] (vertex %d) is %s", p, i, k, k / 3,
                     isnan(m->positions[k]) ? "NaN" : "Inf");
        long long total = 0;
        for (int f = 0; f < m->n_faces; ++f) {
            int sz = m->face_sizes ? m->face_sizes[f] : 3;
            if (sz < 1) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh.face_sizes[%d] = %d must be >= 1", p, i, f, sz);
            total += sz;
            if (total > 0x7fffffffLL) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].mesh: too many corners", p, i);
        }
        for (long long k = 0; k < total; ++k)
            if (m->indices[k] < 0 || m->indices[k] >= m->n_vertices)
                FAIL(WEFT_ERROR_OUT_OF_RANGE, "%s[%d].mesh.indices[%lld] = %d is outside [0, %d)", p, i, k, m->indices[k],
                     m->n_vertices);
    }
    if (!isfinite(d->unit_scale) || !(d->unit_scale > 0.0 && d->unit_scale <= 1e12))
        FAIL(isfinite(d->unit_scale) ? WEFT_ERROR_INVALID_ARGUMENT : WEFT_ERROR_NONFINITE,
             "%s[%d].unit_scale = %g must be in (0, 1e12]", p, i, d->unit_scale);
    if (!isfinite(d->thickness) || !isfinite(d->friction))
        FAIL(WEFT_ERROR_NONFINITE, "%s[%d]: thickness %g and friction %g must be finite", p, i, d->thickness, d->friction);
    if (d->thickness < 0 || d->friction < 0)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d]: thickness %g and friction %g must be >= 0", p, i, d->thickness,
             d->friction);
    if (!isfinite(d->push_speed)) FAIL(WEFT_ERROR_NONFINITE, "%s[%d].push_speed %g must be finite", p, i, d->push_speed);
    if (d->push_speed < 0) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].push_speed %g must be >= 0", p, i, d->push_speed);
    char why[160];
    weft_status st = wa_check_transform(d->transform, why, sizeof why);
    if (st != WEFT_OK) FAIL(st, "%s[%d].transform%s", p, i, why);
    return WEFT_OK;
}

weft_status wa_validate_mesh_colliders(const weft_mesh_collider_def* m, int n, char* msg, size_t msg_size) {
    if (n < 0) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->n_mesh_colliders = %d is negative", n);
    if (n > 0 && !m) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh_colliders is NULL with n_mesh_colliders = %d", n);
    for (int i = 0; i < n; ++i) {
        weft_status st = validate_one(&m[i], i, msg, msg_size);
        if (st != WEFT_OK) return st;
    }
    return WEFT_OK;
}

/* The def's mesh as a source mesh (metres, object space). */
static wc_status read_source(weft_context* ctx, const weft_mesh_collider_def* def, wc_source_mesh* src, wc_diag* d) {
    if (def->mesh.path) {
        wc_import_opts o = wc_default_import_opts();
        o.scale = def->unit_scale;
        o.select = def->mesh.select;
        return wc_import_file(src, &ctx->alloc, def->mesh.path, &o, d);
    }
    int n = def->mesh.n_vertices, nf = def->mesh.n_faces;
    double* pos = WC_NEW(&ctx->alloc, double, 3 * (size_t)n);
    int* sizes = WC_NEW(&ctx->alloc, int, (size_t)nf);
    wc_status st = WC_ERROR_OUT_OF_MEMORY;
    if (pos && sizes) {
        for (int i = 0; i < 3 * n; ++i) pos[i] = (double)def->mesh.positions[i];
        for (int f = 0; f < nf; ++f) sizes[f] = def->mesh.face_sizes ? def->mesh.face_sizes[f] : 3;
        st = wc_source_mesh_from_arrays(src, &ctx->alloc, pos, n, sizes, nf, def->mesh.indices, def->unit_scale, d);
    } else {
        wc_fail(d, st, "out of memory (%d vertices)", n);
    }
    wc_free(&ctx->alloc, pos);
    wc_free(&ctx->alloc, sizes);
    return st;
}

/* Triangles of every polygon of src (allocated into *tris, count *nt). */
static wc_status triangulate(weft_context* ctx, const wc_source_mesh* src, int** tris, int* nt, wc_diag* d) {
    long long total = 0;
    int kmax = 3;
    for (int p = 0; p < src->n_polys; ++p) {
        int k = src->poly_start[p + 1] - src->poly_start[p];
        total += k - 2;
        if (k > kmax) kmax = k;
    }
    if (total < 1 || total > 0x7fffffffLL / 3) return wc_fail(d, WC_ERROR_EMPTY_MESH, "%lld triangles", total);
    *tris = WC_NEW(&ctx->alloc, int, 3 * (size_t)total);
    unsigned char* mask = WC_NEW(&ctx->alloc, unsigned char, (size_t)kmax);
    int* scratch = WC_NEW(&ctx->alloc, int, (size_t)kmax);
    if (!*tris || !mask || !scratch) {
        wc_free(&ctx->alloc, mask);
        wc_free(&ctx->alloc, scratch);
        return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory (%lld triangles)", total);
    }
    int at = 0;
    for (int p = 0; p < src->n_polys; ++p) {
        int s0 = src->poly_start[p], k = src->poly_start[p + 1] - s0;
        at += wc_triangulate_polygon(src->poly_verts + s0, k, src->pos, *tris + 3 * at, mask, scratch);
    }
    *nt = at;
    wc_free(&ctx->alloc, mask);
    wc_free(&ctx->alloc, scratch);
    return WC_OK;
}

/* World positions transform x rest of collider k into c->mesh_scratch. */
static void world_positions(const wa_cloth* c, int k, const wa_xform* T) {
    const wc_mesh_collider* m = c->mesh[k];
    for (int v = 0; v < m->n_verts; ++v) wa_xform_point(T, m->rest + 3 * v, c->mesh_scratch + 3 * v);
}

weft_status wa_build_mesh_colliders(weft_context* ctx, wa_cloth* c, const weft_cloth_def* def, const char* fn) {
    int n = def->n_mesh_colliders;
    if (n == 0) return WEFT_OK;
    wc_allocator* A = &ctx->alloc;
    c->mesh = WC_NEW(A, wc_mesh_collider*, (size_t)n);
    c->mesh_xf = WC_NEW(A, wa_xform, (size_t)n);
    c->mesh_next = WC_NEW(A, wa_xform, (size_t)n);
    c->mesh_pending = WC_NEW(A, int, (size_t)n);
    if (!c->mesh || !c->mesh_xf || !c->mesh_next || !c->mesh_pending)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    c->n_mesh = n;
    int most = 0;
    for (int k = 0; k < n; ++k) {
        const weft_mesh_collider_def* md = &def->mesh_colliders[k];
        wc_diag d = wa_core_diag(ctx);
        wc_source_mesh src;
        memset(&src, 0, sizeof src);
        wc_status st = read_source(ctx, md, &src, &d);
        int* tris = NULL;
        int nt = 0;
        if (st == WC_OK) st = triangulate(ctx, &src, &tris, &nt, &d);
        if (st == WC_OK)
            st = wc_mesh_collider_create(&c->mesh[k], src.pos, src.n_verts, tris, nt, md->thickness, md->friction, A, &d);
        wc_free(A, tris);
        wc_source_mesh_free(&src);
        if (st != WC_OK) return wa_fail(ctx, wa_status(st), "%s: def->mesh_colliders[%d].mesh: %s", fn, k, d.message);
        c->mesh[k]->push_speed = md->push_speed;
        wa_xform_from_floats(&c->mesh_xf[k], md->transform);
        if (c->mesh[k]->n_verts > most) most = c->mesh[k]->n_verts;
    }
    c->mesh_scratch = WC_NEW(A, double, 3 * (size_t)most);
    if (!c->mesh_scratch) return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    for (int k = 0; k < n; ++k) {
        wc_diag d = wa_core_diag(ctx);
        world_positions(c, k, &c->mesh_xf[k]);
        weft_status st = wa_status(wc_mesh_collider_set_all(c->mesh[k], c->mesh_scratch, &d));
        if (st != WEFT_OK)
            return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: def->mesh_colliders[%d].transform: %s", fn, k, d.message);
    }
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wc_state_attach_mesh_colliders(c->state, c->mesh, n, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, d.message);
    return WEFT_OK;
}

void wa_free_mesh_colliders(wa_cloth* c) {
    wc_allocator a = c->ctx->alloc;
    if (c->mesh)
        for (int k = 0; k < c->n_mesh; ++k) wc_mesh_collider_destroy(c->mesh[k]);
    void* arrays[] = {c->mesh, c->mesh_xf, c->mesh_next, c->mesh_pending, c->mesh_scratch};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i) wc_free(&a, arrays[i]);
}

weft_status wa_check_mesh_frame(weft_context* ctx, const wa_cloth* c, const weft_frame* fr, const char* fn) {
    if (!fr->mesh_collider_transforms) return WEFT_OK;
    char why[160];
    for (int i = 0; i < c->n_mesh; ++i) {
        weft_status st = wa_check_transform(fr->mesh_collider_transforms + 16 * i, why, sizeof why);
        if (st != WEFT_OK)
            return wa_fail(ctx, st, "%s: fr->mesh_collider_transforms (mesh collider %d, elements %d..%d)%s", fn, i,
                           16 * i, 16 * i + 15, why);
    }
    return WEFT_OK;
}

void wa_mesh_frame(wa_cloth* c, const weft_frame* fr, int jump) {
    for (int k = 0; k < c->n_mesh; ++k) {
        wc_mesh_collider* m = c->mesh[k];
        if (fr->mesh_collider_transforms) wa_xform_from_floats(&c->mesh_next[k], fr->mesh_collider_transforms + 16 * k);
        else c->mesh_next[k] = c->mesh_xf[k];
        if (!c->mesh_pending[k] && fr->mesh_collider_transforms) {
            /* a rigid transform is finite and rigid (validated); its image of a rest shape within
               1e30 stays finite, and wc_state_set_mesh_target checks it */
            world_positions(c, k, &c->mesh_next[k]);
            wc_diag d = wa_core_diag(c->ctx);
            if (wc_state_set_mesh_target(c->state, k, c->mesh_scratch, &d) != WC_OK)
                wa_log(c->ctx, WEFT_LOG_WARN, "mesh collider %d: %s (kept where it was)", k, d.message);
        }
        if (jump) {
            memcpy(c->mesh_scratch, m->to, 3 * (size_t)m->n_verts * sizeof(double));
            (void)wc_mesh_collider_set_all(m, c->mesh_scratch, NULL);
            wc_state_wake(c->state);
        }
    }
}

void wa_mesh_frame_done(wa_cloth* c) {
    for (int k = 0; k < c->n_mesh; ++k) {
        c->mesh_xf[k] = c->mesh_next[k];
        c->mesh_pending[k] = 0;
    }
}

weft_status weft_cloth_set_mesh_collider_vertices(weft_context* ctx, weft_cloth cloth, int index, const float* positions,
                                                  int n_vertices) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_set_mesh_collider_vertices";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (index < 0 || index >= c->n_mesh)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: index %d is outside [0, %d) (the cloth's mesh colliders)", fn,
                       index, c->n_mesh);
    if (!positions) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: positions is NULL", fn);
    wc_mesh_collider* m = c->mesh[index];
    if (n_vertices != m->n_verts)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: n_vertices = %d, mesh collider %d has %d vertices", fn,
                       n_vertices, index, m->n_verts);
    for (int i = 0; i < 3 * n_vertices; ++i) {
        float p = positions[i];
        if (!isfinite(p))
            return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: positions[%d] (vertex %d) is %s", fn, i, i / 3,
                           isnan(p) ? "NaN" : "Inf");
        if (fabs((double)p) > WA_MAX_OUTPUT_COORD)
            return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: positions[%d] (vertex %d) = %g is beyond %g", fn, i, i / 3,
                           (double)p, WA_MAX_OUTPUT_COORD);
    }
    for (int i = 0; i < 3 * n_vertices; ++i) c->mesh_scratch[i] = (double)positions[i];
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wc_state_set_mesh_target(c->state, index, c->mesh_scratch, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, d.message);
    c->mesh_pending[index] = 1;
    return wa_ok(ctx);
}
