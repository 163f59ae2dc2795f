/* Results in the host's vertex order: positions and smooth normals per host vertex (welded twins
 * read their shared particle, so they report identical values), triangles as host vertex
 * indices (each particle's first host vertex, model.particle_to_host).
 *
 * Normals: per particle, the sum over its triangles of (x_b - x_a) x (x_c - x_a) (twice the
 * area times the unit normal: area-weighted), normalised; zero where that sum is zero.
 * Spaces: WORLD as simulated; OBJECT = T^-1 x / unit_scale with T the last object transform
 * applied (exact affine inverse) and unit_scale the metres per mesh unit that were applied at
 * import (the def's unit_scale; for FBX times the file's unit), so OBJECT positions compare
 * directly with the host's mesh; normals are rotated back by T^-1 and renormalised.
 * A host vertex used by no polygon has no particle: it is reported at its rest position moved
 * rigidly with the object, with a zero normal. */
#include <math.h>
#include <string.h>
#include "api_internal.h"
#include "vec3.h"

static void particle_normals(const wa_cloth* c, double* nrm) {
    const wc_model* m = &c->model;
    const double* x = c->state->x;
    memset(nrm, 0, 3 * (size_t)m->n_particles * sizeof(double));
    for (int t = 0; t < m->n_tris; ++t) {
        const int* tri = m->tris + 3 * t;
        double e1[3], e2[3], n[3];
        v3_sub(e1, x + 3 * tri[1], x + 3 * tri[0]);
        v3_sub(e2, x + 3 * tri[2], x + 3 * tri[0]);
        v3_cross(n, e1, e2);
        for (int k = 0; k < 3; ++k) v3_add(nrm + 3 * tri[k], nrm + 3 * tri[k], n);
    }
    for (int i = 0; i < m->n_particles; ++i) {
        double len = v3_norm(nrm + 3 * i);
        if (len > 0.0) v3_scale(nrm + 3 * i, nrm + 3 * i, 1.0 / len);
    }
}

int wa_outputs_in_range(const wa_cloth* c, const wa_xform* T, int* vertex, double* value) {
    wa_xform inv;
    wa_xform_inverse(T, &inv);
    const double s = 1.0 / c->unit_scale;
    const int* h2p = c->model.host_to_particle;
    for (int v = 0; v < c->n_host; ++v) {
        const int p = h2p[v];
        double w[3], o[3];
        if (p < 0) {
            wa_xform_point(T, c->host_rest + 3 * v, w);
            v3_copy(o, c->host_rest + 3 * v);
        } else {
            v3_copy(w, c->state->x + 3 * p);
            wa_xform_point(&inv, w, o);
        }
        v3_scale(o, o, s);
        for (int k = 0; k < 6; ++k) {
            const double x = k < 3 ? w[k] : o[k - 3];
            if (!(fabs(x) <= WA_MAX_OUTPUT_COORD)) {
                *vertex = v;
                *value = x;
                return 0;
            }
        }
    }
    return 1;
}

weft_status weft_cloth_get_vertices(weft_context* ctx, weft_cloth cloth, weft_space space, float* positions,
                                    float* normals, int capacity, int* count) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_vertices";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (space != WEFT_SPACE_WORLD && space != WEFT_SPACE_OBJECT)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: space = %d is not a weft_space", fn, (int)space);
    int n = c->n_host;
    if (!positions && !normals) {
        if (!count) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: size query with count NULL", fn);
        *count = n;
        return wa_ok(ctx);
    }
    if (positions && positions == normals)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: positions and normals are the same buffer", fn);
    if (capacity < n)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: capacity %d is below the %d host vertices", fn, capacity, n);

    const int object = space == WEFT_SPACE_OBJECT;
    if (c->gpu) {   /* computed by the GPU's output passes, read straight into the caller's arrays */
        weft_status st = wa_gl_begin(ctx, fn);
        if (st != WEFT_OK) return st;
        st = wa_gpu_vertices(ctx, c, object, positions, normals, 0, 0, 0, 0, fn);
        wa_gl_end(ctx);
        if (st != WEFT_OK) return st;
        if (count) *count = n;
        return wa_ok(ctx);
    }
    wa_xform inv;
    wa_xform_inverse(&c->object, &inv);
    const double s = 1.0 / c->unit_scale;
    const double* x = c->state->x;
    const int* h2p = c->model.host_to_particle;
    if (normals) particle_normals(c, c->scratch);
    for (int v = 0; v < n; ++v) {
        int p = h2p[v];
        double pos[3], nrm[3] = {0.0, 0.0, 0.0};
        if (p < 0) {
            if (object) v3_scale(pos, c->host_rest + 3 * v, s);
            else wa_xform_point(&c->object, c->host_rest + 3 * v, pos);
        } else {
            if (object) {
                wa_xform_point(&inv, x + 3 * p, pos);
                v3_scale(pos, pos, s);
            } else {
                v3_copy(pos, x + 3 * p);
            }
            if (normals) {
                v3_copy(nrm, c->scratch + 3 * p);
                if (object) {
                    wa_xform_vector(&inv, nrm, nrm);
                    double len = v3_norm(nrm);
                    if (len > 0.0) v3_scale(nrm, nrm, 1.0 / len);
                }
            }
        }
        for (int k = 0; k < 3; ++k) {
            if (positions) positions[3 * v + k] = (float)pos[k];
            if (normals) normals[3 * v + k] = (float)nrm[k];
        }
    }
    if (count) *count = n;
    return wa_ok(ctx);
}

weft_status weft_cloth_get_triangles(weft_context* ctx, weft_cloth cloth, int* indices, int capacity, int* count) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_triangles";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    const wc_model* m = &c->model;
    if (!indices) {
        if (!count) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: size query with count NULL", fn);
        *count = m->n_tris;
        return wa_ok(ctx);
    }
    if (capacity < m->n_tris)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: capacity %d is below the %d triangles", fn, capacity, m->n_tris);
    for (int k = 0; k < 3 * m->n_tris; ++k) indices[k] = m->particle_to_host[m->tris[k]];
    if (count) *count = m->n_tris;
    return wa_ok(ctx);
}
