/* weft_cloth_check_collisions: the crossings of a cloth with itself at its current positions
 * (core/self_collide.h's counter, through a BVH built for the call). max_penetration (a particle
 * inside a collider) is left 0 here: the mesh-collider work fills it in. */
#include <string.h>
#include "api_internal.h"
#include "self_collide.h"

weft_status weft_cloth_check_collisions(weft_context* ctx, weft_cloth cloth, weft_collision_check* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_check_collisions";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    memset(out, 0, sizeof *out);
    if (c->gpu) {   /* the positions live on the GPU: read them back first */
        weft_status st = wa_gpu_download(ctx, c, fn);
        if (st != WEFT_OK) return st;
    }
    wc_diag d = wa_core_diag(ctx);
    int count = 0;
    weft_status st = wc_self_intersections(&c->model, c->state->x, &ctx->alloc, &count, &d);
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, d.message);
    out->self_intersections = count;
    out->max_penetration = 0.0; /* not measured yet: the lead wires the colliders' depth at merge */
    return wa_ok(ctx);
}
