/* weft_cloth_check_collisions: the crossings of a cloth with itself at its current positions
 * (core/self_collide.h's counter, through a BVH built for the call) and the deepest particle
 * behind the surface of any collider: the mesh colliders (core/mesh_collider.h, at their
 * current end-of-frame positions) and the analytic ones (at their last frame's placement),
 * thickness not included. */
#include <string.h>
#include "api_internal.h"
#include "mesh_collider.h"
#include "self_collide.h"

static double analytic_penetration(const wc_state* s) {
    double deepest = 0.0;
    for (int k = 0; k < s->n_colliders; ++k)
        for (int i = 0; i < s->model->n_particles; ++i) {
            double n[3], d = wc_collider_distance(&s->colliders[k], s->x + 3 * i, n);
            if (-d > deepest) deepest = -d;
        }
    return deepest;
}

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
    weft_status st = wa_status(wc_self_intersections(&c->model, c->state->x, &ctx->alloc, &count, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, d.message);
    out->self_intersections = count;
    double mesh = wc_mesh_max_penetration((const wc_mesh_collider* const*)c->mesh, c->n_mesh, c->state->x,
                                          c->model.n_particles);
    double analytic = analytic_penetration(c->state);
    out->max_penetration = mesh > analytic ? mesh : analytic;
    return wa_ok(ctx);
}
