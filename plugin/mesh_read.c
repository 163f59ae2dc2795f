/* weft_mesh_read / weft_mesh_free: a mesh file into host arrays through the import a cloth's
 * mesh goes through (core/source_mesh.h, wc_import_file), copied into arrays of the context's
 * allocator. Nothing is welded or cleaned: the file's vertices and polygons as the library reads
 * them. */
#include <math.h>
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"
#include "source_mesh.h"

void weft_mesh_free(weft_context* ctx, weft_mesh_data* mesh) {
    if (!ctx || !mesh) return;
    wc_free(&ctx->alloc, mesh->positions);
    wc_free(&ctx->alloc, mesh->face_sizes);
    wc_free(&ctx->alloc, mesh->indices);
    memset(mesh, 0, sizeof *mesh);
}

weft_status weft_mesh_read(weft_context* ctx, const char* path, const char* select, double unit_scale,
                           weft_mesh_data* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_mesh_read";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    memset(out, 0, sizeof *out);
    if (!path) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: path is NULL", fn);
    if (!path[0]) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: path is empty", fn);
    if (!isfinite(unit_scale)) return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: unit_scale is not finite", fn);
    if (!(unit_scale > 0 && unit_scale <= 1e12))
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: unit_scale = %g must be in (0, 1e12]", fn, unit_scale);

    wc_import_opts o = wc_default_import_opts();
    o.scale = unit_scale;
    o.select = select;
    wc_source_mesh src;
    memset(&src, 0, sizeof src);
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wc_import_file(&src, &ctx->alloc, path, &o, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, d.message);

    const int nv = src.n_verts, nf = src.n_polys, ni = src.poly_start ? src.poly_start[nf] : 0;
    weft_mesh_data m;
    memset(&m, 0, sizeof m);
    m.positions = WC_NEW(&ctx->alloc, double, 3 * (size_t)nv + 1);
    m.face_sizes = WC_NEW(&ctx->alloc, int, (size_t)nf + 1);
    m.indices = WC_NEW(&ctx->alloc, int, (size_t)ni + 1);
    if (!m.positions || !m.face_sizes || !m.indices) {
        weft_mesh_free(ctx, &m);
        wc_source_mesh_free(&src);
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory (%d vertices, %d polygons)", fn, nv, nf);
    }
    if (nv > 0) memcpy(m.positions, src.pos, 3 * (size_t)nv * sizeof(double));
    for (int f = 0; f < nf; ++f) m.face_sizes[f] = src.poly_start[f + 1] - src.poly_start[f];
    if (ni > 0) memcpy(m.indices, src.poly_verts, (size_t)ni * sizeof(int));
    m.n_vertices = nv;
    m.n_faces = nf;
    m.unit_scale = src.unit_scale;
    wc_source_mesh_free(&src);
    *out = m;
    return wa_ok(ctx);
}
