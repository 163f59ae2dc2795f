/* The integrator's side of a substep on the GPU (core/bdf2.h's terms, wg_sim_impl.h): the
 * textures of xb, v* and mom, the pass that fills them and moves the history on, TR-BDF2's
 * lumped air, and A's assembly with it; shared by the substep's preparation (wg_step.c) and
 * Newton's systems (wg_newton.c). Backward Euler binds x, v and zeros for xb, v* and mom, so its
 * passes do the same arithmetic as without them. */
#include "wg_sim_impl.h"

const wg_tex* wg_integ_xb(wg_sim* g, const wc_integ* ig) { return ig->xb_form ? &g->xb : wg_ring_cur(&g->x); }
const wg_tex* wg_integ_vstar(wg_sim* g, const wc_integ* ig) {
    return ig->bdf2 || ig->stage ? &g->vstar : wg_ring_cur(&g->v);
}
const wg_tex* wg_integ_mom(wg_sim* g, const wc_integ* ig) { return ig->bdf2 || ig->stage ? &g->mom : &g->nw_zero; }

/* The integrator's xb, v*, mom after the contacts' correction (integ_prepare.glsl; core/bdf2.c
 * wc_integ_prepare), x_start the substep's x before it; a BDF2 cloth's history moves on. */
void wg_integ_prepare(wg_sim* g, wc_state* s, const wc_integ* ig, const wg_tex* x_start) {
    wg_runner* run = &g->run;
    const int mode = ig->stage == 1 ? 2 : ig->stage == 2 ? 3 : ig->bdf2 ? 1 : 0;
    WG_USE(run, WGP_INTEG_PREPARE, &(wg_integ_prepare_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
        .xs = ig->stage == 2 ? &g->xs : x_start, .xp = wg_ring_cur(&g->xp), .vp = wg_ring_cur(&g->vp)});
    wg_u1i(run, "u_mode", mode);
    wg_u1f(run, "u_h", ig->h);
    wg_u1f(run, "u_he", ig->he);
    wg_u1f(run, "u_c2", WC_TRBDF2_C2);
    if (mode == 3) {   /* stage 2 reads stage 1's start from the history, which stays */
        WG_RUN(run, g->n, &g->xb, &g->vstar, &g->mom);
        return;
    }
    int px = wg_ring_other(&g->xp, 0), pv = wg_ring_other(&g->vp, 0);
    WG_RUN(run, g->n, &g->xb, &g->vstar, &g->mom, &g->xp.t[px], &g->vp.t[pv]);
    g->xp.cur = px;
    g->vp.cur = pv;
    if (s->def.integrator == WC_INTEGRATOR_BDF2) {
        s->hist_h = ig->h;
        s->hist_valid = 1;
    }
}

void wg_integ_air_lump(wg_sim* g, const wc_state* s, const wg_tex* x) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_AIR_LUMP, &(wg_air_lump_in){.x = x, .rows = &g->rows, .row_tri = &g->row_tri, .tri = &g->tri});
    wg_u2f(run, "u_drag", s->def.air.normal_drag, s->def.air.tangent_drag);
    WG_RUN(run, g->n, &g->air_lo, &g->air_hi);
}

void wg_integ_assemble_a(wg_sim* g, double air_he, int friction) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_ASSEMBLE_A, &(wg_assemble_a_in){.block = &g->block, .block_list = &g->block_list, .mass = &g->mass,
        .spring_f = &g->sf, .spring_w = &g->sw, .spring_j = &g->sj, .air_lo = air_he != 0.0 ? &g->air_lo : &g->mass,
        .air_hi = air_he != 0.0 ? &g->air_hi : &g->mass, .fric_lo = friction ? &g->nw_fa[0] : &g->mass,
        .fric_hi = friction ? &g->nw_fa[1] : &g->mass});
    wg_u1f(run, "u_air_he", air_he);
    wg_u1i(run, "u_friction", friction);
    WG_RUN(run, g->nb, &g->A0, &g->A1);
}
