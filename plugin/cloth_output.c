/* Results in the host's vertex order (core/cloth_output.c computes them; the backend's output
 * operation fills the arrays or, on the GPU, the host's GL buffers): positions and normals per
 * host vertex in world or object space, triangles as host vertex indices. */
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

weft_status weft_cloth_get_vertices(weft_context* ctx, weft_cloth cloth, weft_space space, float* positions,
                                    float* normals, int capacity, int* count) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_vertices";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
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
    wc_diag d = wa_core_diag(ctx);
    wc_status st = wc_cloth_vertices(c, space == WEFT_SPACE_OBJECT, positions, normals, &d);
    if (st != WC_OK) return wa_fail_core(ctx, fn, st, &d);
    if (count) *count = n;
    return wa_ok(ctx);
}

weft_status weft_cloth_get_triangles(weft_context* ctx, weft_cloth cloth, int* indices, int capacity, int* count) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_triangles";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    int nt = c->model.n_tris;
    if (!indices) {
        if (!count) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: size query with count NULL", fn);
        *count = nt;
        return wa_ok(ctx);
    }
    if (capacity < nt)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: capacity %d is below the %d triangles", fn, capacity, nt);
    wc_cloth_triangles(c, indices);
    if (count) *count = nt;
    return wa_ok(ctx);
}

weft_status weft_cloth_write_gl_buffers(weft_context* ctx, weft_cloth cloth, weft_space space, unsigned position_buffer,
                                        size_t position_offset, unsigned normal_buffer, size_t normal_offset) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_write_gl_buffers";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (space != WEFT_SPACE_WORLD && space != WEFT_SPACE_OBJECT)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: space = %d is not a weft_space", fn, (int)space);
    wc_output_request r;
    memset(&r, 0, sizeof r);
    r.to_object = space == WEFT_SPACE_OBJECT;
    r.position_buffer = position_buffer;
    r.position_offset = position_offset;
    r.normal_buffer = normal_buffer;
    r.normal_offset = normal_offset;
    wc_diag d = wa_core_diag(ctx);
    wc_status st = wc_cloth_write_gl_buffers(c, &r, &d);
    return st == WC_OK ? wa_ok(ctx) : wa_fail_core(ctx, fn, st, &d);
}
