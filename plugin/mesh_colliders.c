/* Triangle-mesh colliders of the ABI (weft_mesh_collider_def): defaults, validation, and a
 * deforming body's vertices for the next frame, from host arrays
 * (weft_cloth_set_mesh_collider_vertices) or from a host GL buffer object
 * (weft_cloth_set_mesh_collider_gl_buffer: kept and checked on a GPU that moves the body there,
 * else read by the backend, then checked and set as the arrays are). The cloth imports, creates
 * and moves them (core/cloth_mesh.c). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

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

/* The checks of a body's vertices for the next frame, shared by the host-array and GL-buffer
 * calls: finite, within WC_CLOTH_MAX_COORD. buffer: the GL buffer they came from (messages name
 * the vertex and its coordinate there), 0 for the host array `positions`; first: the index of
 * positions' first vertex (a GPU's check hands over the bad vertex only). */
static weft_status check_vertices(weft_context* ctx, const char* fn, unsigned buffer, const float* positions, int n,
                                  int first) {
    char at[80];
    for (int i = 0; i < 3 * n; ++i) {
        float p = positions[i];
        int bad_value = !isfinite(p), beyond = !bad_value && fabs((double)p) > WC_CLOTH_MAX_COORD;
        if (!bad_value && !beyond) continue;
        if (buffer) snprintf(at, sizeof at, "buffer %u: vertex %d's coordinate %d", buffer, first + i / 3, i % 3);
        else snprintf(at, sizeof at, "positions[%d] (vertex %d)", i, i / 3);
        if (bad_value) return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: %s is %s", fn, at, isnan(p) ? "NaN" : "Inf");
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: %s = %g is beyond %g", fn, at, (double)p, WC_CLOTH_MAX_COORD);
    }
    return WEFT_OK;
}

/* The cloth holding mesh collider `index`; NULL with the error set in *st. */
static wc_cloth* lookup_mesh(weft_context* ctx, weft_cloth cloth, int index, const char* fn, weft_status* st) {
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) {
        *st = WEFT_ERROR_INVALID_HANDLE;
        return NULL;
    }
    if (index < 0 || index >= c->n_mesh) {
        *st = wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: index %d is outside [0, %d) (the cloth's mesh colliders)", fn,
                      index, c->n_mesh);
        return NULL;
    }
    return c;
}

static weft_status check_count(weft_context* ctx, const wc_cloth* c, int index, int n_vertices, const char* fn) {
    int n = c->mesh[index]->n_verts;
    if (n_vertices == n) return WEFT_OK;
    return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: n_vertices = %d, mesh collider %d has %d vertices", fn, n_vertices,
                   index, n);
}

weft_status weft_cloth_set_mesh_collider_vertices(weft_context* ctx, weft_cloth cloth, int index, const float* positions,
                                                  int n_vertices) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_set_mesh_collider_vertices";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    weft_status st = WEFT_OK;
    wc_cloth* c = lookup_mesh(ctx, cloth, index, fn, &st);
    if (!c) return st;
    if (!positions) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: positions is NULL", fn);
    st = check_count(ctx, c, index, n_vertices, fn);
    if (st == WEFT_OK) st = check_vertices(ctx, fn, 0, positions, n_vertices, 0);
    if (st != WEFT_OK) return st;
    wc_diag d = wa_core_diag(ctx);
    wc_status cs = wc_cloth_set_mesh_vertices(c, index, positions, &d);
    return cs == WC_OK ? wa_ok(ctx) : wa_fail_core(ctx, fn, cs, &d);
}

weft_status weft_cloth_set_mesh_collider_gl_buffer(weft_context* ctx, weft_cloth cloth, int index, unsigned buffer,
                                                   size_t offset, size_t stride, int n_vertices) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_set_mesh_collider_gl_buffer";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    weft_status st = WEFT_OK;
    wc_cloth* c = lookup_mesh(ctx, cloth, index, fn, &st);
    if (!c) return st;
    st = check_count(ctx, c, index, n_vertices, fn);
    if (st != WEFT_OK) return st;
    if (buffer == 0) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: buffer is 0 (no buffer object)", fn);
    if (stride == 0) stride = 3 * sizeof(float);
    if (offset % 4 || stride % 4 || stride < 3 * sizeof(float))
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT,
                       "%s: offset %zu and stride %zu must be multiples of 4 bytes, the stride 0 (packed) or >= 12", fn,
                       offset, stride);
    const size_t room = SIZE_MAX - 3 * sizeof(float);
    if (offset > room || stride > (room - offset) / (size_t)n_vertices)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: offset %zu + stride %zu x %d vertices overflows", fn,
                       offset, stride, n_vertices);
    wc_gl_vertex_source src = {.buffer = buffer, .offset = offset, .stride = stride, .n = n_vertices};
    const float* positions = NULL;
    wc_gl_vertex_result res;
    wc_diag d = wa_core_diag(ctx);
    wc_status cs = wc_cloth_read_mesh_gl(c, index, &src, &positions, &res, &d);
    if (cs != WC_OK) return wa_fail_core(ctx, fn, cs, &d);
    if (res.taken) {   /* kept on the GPU, checked there */
        if (res.bad_vertex < 0) return wa_ok(ctx);
        st = check_vertices(ctx, fn, buffer, res.bad, 1, res.bad_vertex);
        return st != WEFT_OK ? st
                             : wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: buffer %u: vertex %d is not finite", fn, buffer,
                                       res.bad_vertex);
    }
    st = check_vertices(ctx, fn, buffer, positions, n_vertices, 0);
    if (st != WEFT_OK) return st;
    cs = wc_cloth_set_mesh_vertices(c, index, positions, &d);
    return cs == WC_OK ? wa_ok(ctx) : wa_fail_core(ctx, fn, cs, &d);
}
