/* weft_cloth_get_energy: the current state's energies, mass and centre of mass
 * (core/cloth_energy.c). Reads only: a GPU cloth's particles are read back first. */
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

weft_status weft_cloth_get_energy(weft_context* ctx, weft_cloth cloth, weft_cloth_energy* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_energy";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    wc_diag d = wa_core_diag(ctx);
    wc_cloth_energy e;
    wc_status st = wc_cloth_energy_of(c, &e, &d);
    if (st != WC_OK) return wa_fail_core(ctx, fn, st, &d);
    weft_cloth_energy o;
    memset(&o, 0, sizeof o);
    o.kinetic = e.kinetic;
    o.elastic = e.elastic;
    o.gravity = e.gravity;
    o.mass = e.mass;
    for (int k = 0; k < 3; ++k) o.center_of_mass[k] = e.center_of_mass[k];
    *out = o;
    return wa_ok(ctx);
}
