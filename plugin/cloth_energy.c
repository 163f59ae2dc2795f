/* weft_cloth_get_energy: the current state's kinetic, spring and gravitational energy
 * (core/state.h's sums) and its mass and centre of mass. Reads only: a GPU cloth's positions and
 * velocities are read back into its CPU mirror first. */
#include <string.h>
#include "api_internal.h"
#include "vec3.h"

weft_status weft_cloth_get_energy(weft_context* ctx, weft_cloth cloth, weft_cloth_energy* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_energy";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    if (c->gpu) {
        weft_status st = wa_gpu_download(ctx, c, fn);
        if (st != WEFT_OK) return st;
    }
    const wc_state* s = c->state;
    const wc_model* m = &c->model;
    weft_cloth_energy e;
    memset(&e, 0, sizeof e);
    double elastic_and_kinetic = 0.0;
    const double total = wc_state_total_energy(s, &elastic_and_kinetic);
    e.kinetic = wc_state_kinetic_energy(s);
    e.elastic = elastic_and_kinetic - e.kinetic;
    e.gravity = total - elastic_and_kinetic;
    e.mass = s->total_mass;
    for (int i = 0; i < m->n_particles; ++i)
        for (int k = 0; k < 3; ++k) e.center_of_mass[k] += m->mass[i] * s->x[3 * i + k];
    if (e.mass > 0)
        for (int k = 0; k < 3; ++k) e.center_of_mass[k] /= e.mass;
    *out = e;
    return wa_ok(ctx);
}
