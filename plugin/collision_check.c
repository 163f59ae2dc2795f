/* weft_cloth_check_collisions: the cloth's crossings with itself and its deepest penetration of
 * a collider, at its current positions (core/cloth_check.c). */
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

weft_status weft_cloth_check_collisions(weft_context* ctx, weft_cloth cloth, weft_collision_check* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_check_collisions";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    memset(out, 0, sizeof *out);
    wc_diag d = wa_core_diag(ctx);
    int count = 0;
    double deepest = 0.0;
    wc_status st = wc_cloth_check_collisions(c, &count, &deepest, &d);
    if (st != WC_OK) return wa_fail_core(ctx, fn, st, &d);
    out->self_intersections = count;
    out->max_penetration = deepest;
    return wa_ok(ctx);
}
