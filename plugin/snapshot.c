/* weft_cloth_save / weft_cloth_restore: the cloth's whole mutable state as a flat byte buffer
 * (the format, its checks and the device transfers: core/cloth_snapshot.c). A snapshot carries
 * this library's ABI and version and is refused by another's. */
#include "api_internal.h"
#include "call_guard.h"

static wc_snapshot_stamp library_stamp(void) {
    wc_snapshot_stamp s = {WEFT_ABI, (uint32_t)(WEFT_VERSION_MAJOR << 16 | WEFT_VERSION_MINOR << 8 | WEFT_VERSION_PATCH)};
    return s;
}

weft_status weft_cloth_save(weft_context* ctx, weft_cloth cloth, void* buf, size_t size) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_save";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!buf) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: buf is NULL", fn);
    if (size < c->snapshot_size)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE, "%s: size %zu is below the snapshot size %zu (weft_cloth_info)", fn,
                       size, c->snapshot_size);
    wc_snapshot_stamp stamp = library_stamp();
    wc_diag d = wa_core_diag(ctx);
    wc_status st = wc_cloth_save(c, &stamp, buf, &d);
    return st == WC_OK ? wa_ok(ctx) : wa_fail_core(ctx, fn, st, &d);
}

weft_status weft_cloth_restore(weft_context* ctx, weft_cloth cloth, const void* buf, size_t size) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_restore";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    wc_snapshot_stamp stamp = library_stamp();
    wc_diag d = wa_core_diag(ctx);
    wc_status st = wc_cloth_restore(c, &stamp, buf, size, &d);
    return st == WC_OK ? wa_ok(ctx) : wa_fail_core(ctx, fn, st, &d);
}
