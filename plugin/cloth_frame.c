/* weft_cloth_step: one host frame (weft_context_step, context_step.c, uses the same validation,
 * conversion and statistics for each of its cloths). The frame is validated first (nothing changes on a refused
 * call: every transform finite and rigid, dt within the cloth's max_frame_time), converted to
 * core's wc_cloth_frame and run by the cloth (core/cloth_frame.c: inertia, teleport, reset,
 * pins, colliders, wind, the backend's step, the whole-frame rollback); its statistics are
 * turned into the ABI's. */
#include <math.h>
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"
#include "clock.h"

#define WA_FRAME_FLAGS ((uint32_t)(WEFT_FRAME_TELEPORT | WEFT_FRAME_RESET))

/* n host transforms (16 floats each) of the frame's field, items named by kind in messages. */
static weft_status check_transforms(weft_context* ctx, const float* m, int n, const char* field, const char* kind,
                                    const char* fn, const char* name) {
    char why[160];
    for (int i = 0; m && i < n; ++i) {
        weft_status st = wa_check_transform(m + 16 * i, why, sizeof why);
        if (st != WEFT_OK)
            return wa_fail(ctx, st, "%s: %s%s (%s %d, elements %d..%d)%s", fn, name, field, kind, i, 16 * i,
                           16 * i + 15, why);
    }
    return WEFT_OK;
}

weft_status wa_validate_frame(weft_context* ctx, const wc_cloth* c, const weft_frame* fr, const char* fn,
                              const char* name) {
    char why[160];
    weft_status st;
    if (!isfinite(fr->dt))
        return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: %sdt is %s", fn, name, isnan(fr->dt) ? "NaN" : "Inf");
    if (!(fr->dt > 0.0) || fr->dt > c->settings.max_frame_time)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: %sdt = %g s must be in (0, max_frame_time = %g s]", fn,
                       name, fr->dt, c->settings.max_frame_time);
    if (fr->flags & ~WA_FRAME_FLAGS)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: %sflags 0x%x has unknown bits 0x%x", fn, name,
                       (unsigned)fr->flags, (unsigned)(fr->flags & ~WA_FRAME_FLAGS));
    if (fr->object_transform && (st = wa_check_transform(fr->object_transform, why, sizeof why)) != WEFT_OK)
        return wa_fail(ctx, st, "%s: %sobject_transform%s", fn, name, why);
    if ((st = check_transforms(ctx, fr->attachment_transforms, c->n_attachments, "attachment_transforms", "attachment",
                               fn, name)) != WEFT_OK ||
        (st = check_transforms(ctx, fr->collider_transforms, c->n_colliders, "collider_transforms", "collider", fn,
                               name)) != WEFT_OK ||
        (st = check_transforms(ctx, fr->mesh_collider_transforms, c->n_mesh, "mesh_collider_transforms",
                               "mesh collider", fn, name)) != WEFT_OK)
        return st;
    if (fr->wind)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(fr->wind[k]))
                return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: %swind[%d] is %s", fn, name, k,
                               isnan(fr->wind[k]) ? "NaN" : "Inf");
    return WEFT_OK;
}

wc_cloth_frame wa_core_frame(const weft_frame* fr) {
    wc_cloth_frame f;
    memset(&f, 0, sizeof f);
    f.dt = fr->dt;
    f.reset = (fr->flags & WEFT_FRAME_RESET) != 0;
    f.teleport = (fr->flags & WEFT_FRAME_TELEPORT) != 0;
    f.object_transform = fr->object_transform;
    f.attachment_transforms = fr->attachment_transforms;
    f.collider_transforms = fr->collider_transforms;
    f.mesh_collider_transforms = fr->mesh_collider_transforms;
    f.wind = fr->wind;
    return f;
}

void wa_fill_stats(weft_frame_stats* o, const wc_step_stats* st, const wc_state* s, double ms_total) {
    memset(o, 0, sizeof *o);
    o->ms_total = ms_total;
    o->ms_forces = st->ms.forces;
    o->ms_assemble = st->ms.assemble;
    o->ms_solve = st->ms.solve;
    o->ms_collide = st->ms.collide;
    o->ms_integrate = st->ms.integrate;
    o->substeps = st->substeps;
    o->iterations = st->iterations;
    o->solves = st->solves;
    o->ms_precond = st->precond_ms;
    o->max_iterations = st->max_iterations;
    o->residual = st->residual;
    o->not_converged = st->not_converged;
    o->solver = (weft_solver)st->solver;
    o->rollbacks = st->rollbacks;
    o->halvings = st->halvings;
    o->direct_fallbacks = st->direct_fallbacks;
    o->failures = st->failures;
    o->contacts = st->contacts;
    o->max_strain = st->max_strain;
    o->kinetic_energy = st->kinetic_energy;
    o->time = s->time;
    o->frame = s->frame;
    o->asleep = st->asleep;
    o->fell_asleep = st->fell_asleep;
    o->woke = st->woke;
    o->self_impacts = st->self_impacts;
    o->self_zones = st->self_zones;
    o->self_unresolved = st->self_unresolved;
    o->ms_self_collide = st->ms.self_collide;
    o->newton_steps = st->newton_iterations;
    o->line_search_backtracks = st->backtracks;
    o->energy_steps = st->energy_iterations;
    o->friction_passes = st->friction_passes;
    o->bdf2_substeps = st->bdf2_substeps;
    o->self_proximity = st->self_proximity;
    o->self_zone_relaxed = st->self_zone_relaxed;
    o->self_pairs = st->self_pairs;
    o->self_pairs_active = st->self_pairs_active;
    o->self_pair_passes = st->self_pair_passes;
    o->self_pair_overflow = st->self_pair_overflow;
    o->mesh_pairs = st->mesh_pairs;
    o->mesh_pairs_active = st->mesh_pairs_active;
    o->mesh_pair_passes = st->mesh_pair_passes;
    o->mesh_pair_overflow = st->mesh_pair_overflow;
    o->mesh_pair_skipped = st->mesh_pair_skipped;
}

weft_status weft_cloth_step(weft_context* ctx, weft_cloth cloth, const weft_frame* fr, weft_frame_stats* stats) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_step";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    double t_start = wc_now_ms();
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!fr) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: fr is NULL", fn);
    weft_status st = wa_validate_frame(ctx, c, fr, fn, "fr->");
    if (st != WEFT_OK) return st;
    wc_cloth_frame f = wa_core_frame(fr);
    wc_step_stats ss;
    wc_diag d = wa_core_diag(ctx);
    wc_status cs = wc_cloth_step(c, &f, &ss, &d);
    if (cs != WC_OK) return wa_fail_core(ctx, fn, cs, &d);
    if (stats) wa_fill_stats(stats, &ss, c->state, wc_now_ms() - t_start);
    return wa_ok(ctx);
}
