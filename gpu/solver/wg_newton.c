/* Newton's iterations and line search of a substep on the GPU, as core/newton.c, for backward
 * Euler, BDF2 and TR-BDF2's stages through core's coefficients (he, xb, v*, mom; core/bdf2.h). At
 * the iterate w (the velocity change; x(w) = xb + he (v_n + w)): the springs' elastic forces and
 * stiffness at x(w) with the substep start's damping directions, or in TR-BDF2's stages those at
 * x(w) and the implicit air refreshed there too, unless a contact is active in the stage (the air
 * then stays the stage start's: g->nw_air_frozen; newton_springs.glsl; core/newton.h "Refreshed"),
 * he f_total (assemble_b.glsl), g = -grad Phi(w) = he f_total - M (w - mom) + Fb - Fa w
 * (newton_gradient.glsl) into b and A + Fa into its blocks, Fa and Fb kinetic friction's terms as
 * the substep's friction pass and its rechecks assembled them, frozen (newton_friction.glsl: the
 * difference to a capture taken before that pass, as core's wc_newton_capture / friction_terms;
 * the rechecks are not repeated); stop when |S g| is within the solver's tolerance of the first
 * solve's scale or below float's resolution of g (a reduction read back); solve A d = g under
 * the substep's filter S, contacts included, with z = 0 (so every iterate keeps the first one's
 * prescribed part); stop unless d descends (g.d > 0, a reduction read back); w += d, or with the
 * line search w + alpha d for the first alpha of 1, 1/2, ... that passes Armijo's test on the
 * incremental potential Phi. Phi's change between two iterates is summed term by term
 * (newton_phi_particles.glsl with the penalty pairs' part added per particle, wg_pairs.h,
 * and newton_phi_springs.glsl: two reductions read back), not each Phi, so that float keeps the digits the test
 * compares; the penalty pairs' exact terms join each system (wg_pairs_newton, on the GPU); the
 * first step's search runs from w~0 = z + S (-v*) towards the first solve's result as core's. The energy guard as core's: past
 * newton_iterations, up to NW_ENERGY_EXTRA more iterations while the iterate's total energy
 * (the step's checks at x(w), v(w), read back) is above the cap, tested before the iteration's
 * system is built, so that the last linearisation (the contacts' release reads its residual) is
 * core's. */
#include <math.h>

#include "newton.h"
#include "wg_sim_impl.h"

/* 1 when TR-BDF2's implicit air stays the stage start's in Newton's systems (a contact is active:
   core/newton.c newton_system, g->nw_air_frozen): the gradient takes -he L w itself */
static int air_frozen(const wg_sim* g, const wc_integ* ig) { return ig->air_implicit && g->nw_air_frozen; }

/* newton_gradient.glsl at w with h f_total hf into out (its output 0), x(w) and v(w) into the
 * rings' free slots (xw, vw); friction: its frozen terms in out. */
static void gradient_pass(wg_sim* g, const wc_integ* ig, const wg_tex* hf, const wg_tex* w, int friction,
                          const wg_tex* out, const wg_tex* xw, const wg_tex* vw) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_NEWTON_GRADIENT, &(wg_newton_gradient_in){.hf = hf, .w = w, .mass = &g->mass,
        .xb = wg_integ_xb(g, ig), .mom = wg_integ_mom(g, ig), .v = wg_ring_cur(&g->v),
        .fric_lo = friction ? &g->nw_fa[0] : &g->mass, .fric_hi = friction ? &g->nw_fa[1] : &g->mass,
        .fric_b = friction ? &g->nw_fb : &g->mass, .air_lo = air_frozen(g, ig) ? &g->air_lo : &g->mass,
        .air_hi = air_frozen(g, ig) ? &g->air_hi : &g->mass});
    wg_u1f(run, "u_h", ig->he);
    wg_u1i(run, "u_friction", friction);
    wg_u1i(run, "u_air", air_frozen(g, ig));
    WG_RUN(run, g->n, out, xw, vw);
}

void wg_newton_system(wg_sim* g, const wc_state* s, const wc_integ* ig, const wg_tex* w,
                      wc_compression compression) {
    const wc_model* m = g->m;
    wg_runner* run = &g->run;
    const double he = ig->he;
    const wg_tex* xw = &g->x.t[wg_ring_other(&g->x, 0)];
    const wg_tex* vw = &g->v.t[wg_ring_other(&g->v, 0)];
    const wc_air* air = &s->def.air;
    int use_air = (air->normal_drag != 0.0 || air->tangent_drag != 0.0) && g->nt > 0;
    const int refresh_air = ig->air_implicit && !air_frozen(g, ig);
    if (refresh_air) {
        /* TR-BDF2's air refreshed at the iterate (core/newton.c refresh_air): x(w), v(w) first
           (the gradient pass's outputs 1 and 2; its output 0 is redone below), then the air's
           force and lumped Jacobian there */
        gradient_pass(g, ig, &g->nw_zero, w, 0, &g->b, xw, vw);
        WG_USE(run, WGP_AIR, &(wg_air_in){.x = xw, .v = vw, .tri = &g->tri});
        wg_u3f(run, "u_wind", air->wind);
        wg_u2f(run, "u_drag", air->normal_drag, air->tangent_drag);
        WG_RUN(run, g->nt, &g->fair);
        wg_integ_air_lump(g, s, xw);
    }
    WG_USE(run, WGP_NEWTON_SPRINGS, &(wg_newton_springs_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
        .w = w, .xb = wg_integ_xb(g, ig), .spring = &g->spring, .spring_rest = &g->spring_rest, .rest = &g->rest,
        .wd = g->nw_held ? &g->nw_wd : w});
    wg_u4f(run, "u_k", m->material.k);
    wg_u4f(run, "u_d", m->material.d);
    wg_u1f(run, "u_h", he);
    wg_u1f(run, "u_seam_scale", s->seam_scale);
    wg_u1i(run, "u_compression_drop", compression == WC_COMPRESSION_DROP);
    wg_u1i(run, "u_refresh", ig->stage == 0 ? 0 : g->nw_held ? 2 : 1);
    WG_RUN(run, g->ns, &g->sf, &g->sw, &g->sj);
    /* otherwise the air of the substep's start stays in fair (frozen, as core's f_ext) */
    WG_USE(run, WGP_ASSEMBLE_B, &(wg_assemble_b_in){.mass = &g->mass, .rows = &g->rows, .row_entry = &g->row_entry,
        .spring_f = &g->sf, .spring_w = &g->sw, .row_tri = &g->row_tri, .tri_air = &g->fair, .mom = &g->mass});
    wg_u1f(run, "u_h", he);
    wg_u3f(run, "u_gravity", s->def.gravity);
    wg_u1i(run, "u_use_air", use_air);
    wg_u1i(run, "u_mom", 0);
    if (refresh_air) WG_RUN(run, g->n, &g->nw_hf, &g->ftot, &g->nw_fext);   /* f_ext at the iterate */
    else WG_RUN(run, g->n, &g->nw_hf, &g->ftot);
    gradient_pass(g, ig, &g->nw_hf, w, g->nw_friction, &g->b, xw, vw);
    wg_integ_assemble_a(g, ig->air_implicit ? he : 0.0, g->nw_friction);
    if (g->pairs) wg_pairs_newton(g->pairs, ig, w);   /* the penalty pairs touching at x(w) */
    g->nw_refreshed = ig->stage != 0;
}

void wg_newton_friction(wg_sim* g, int terms) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_NEWTON_FRICTION, &(wg_newton_friction_in){.pblocks = &g->pblocks, .a_lo = &g->A0, .a_hi = &g->A1,
        .b = &g->b, .cap_lo = terms ? &g->nw_cap[0] : &g->mass, .cap_hi = terms ? &g->nw_cap[1] : &g->mass,
        .cap_b = terms ? &g->nw_cap[2] : &g->mass});
    wg_u1i(run, "u_terms", terms);
    if (terms) WG_RUN(run, g->n, &g->nw_fa[0], &g->nw_fa[1], &g->nw_fb);
    else WG_RUN(run, g->n, &g->nw_cap[0], &g->nw_cap[1], &g->nw_cap[2]);
}

/* |S b|^2 (residual.glsl at x = 0), read back. */
static double filtered_norm2(wg_sim* g) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_RESIDUAL, &(wg_residual_in){.pblocks = &g->pblocks, .block = &g->block, .a_lo = &g->A0,
        .a_hi = &g->A1, .x = &g->nw_zero, .b = &g->b, .S0 = &g->S0, .S1 = &g->S1, .pairs = wg_sim_pair_in(g)});
    wg_sim_pair_uniform(g);
    WG_RUN(run, g->n, &g->rz);
    float v[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->rz, 0, 0, 0, 0), v);
    return (double)v[3];
}

#define NW_ENERGY_EXTRA 4   /* core/newton.c's: iterations past newton_iterations at most while the
                               iterate holds more energy than the cap */
#define NW_ARMIJO 1e-4      /* core/newton.c's sufficient-decrease constant */
#define NW_BACKTRACKS 12    /* and its halvings of a step at most */

/* One of Newton's iterate textures that is neither a nor b. */
static wg_tex* spare(wg_sim* g, const wg_tex* a, const wg_tex* b) {
    int k = 0;
    while (&g->nw_w[k] == a || &g->nw_w[k] == b) ++k;
    return &g->nw_w[k];
}

/* trial = w + alpha d; returns sum g.d (a reduction read back). */
static double step_to(wg_sim* g, const wg_tex* w, const wg_tex* d, const wg_tex* gr, double alpha, const wg_tex* trial) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_NEWTON_STEP, &(wg_newton_step_in){.w = w, .d = d, .g = gr});
    wg_u1f(run, "u_alpha", alpha);
    WG_RUN(run, g->n, trial, &g->nw_gd);
    float v[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->nw_gd, 0, 0, 0, 0), v);
    return (double)v[0];
}

/* the particles' and the springs' changes summed; after a refresh (g->nw_refreshed) wa is the
   iterate it was made at */
double wg_newton_phi_change(wg_sim* g, const wc_state* s, const wc_integ* ig, const wg_tex* wa, const wg_tex* wb) {
    wg_runner* run = &g->run;
    const double h = ig->he;
    const int fric = g->nw_friction;
    WG_USE(run, WGP_NEWTON_PHI_PARTICLES, &(wg_newton_phi_particles_in){.wa = wa, .wb = wb, .mass = &g->mass,
        .fext = &g->nw_fext, .mom = wg_integ_mom(g, ig), .air_lo = ig->air_implicit ? &g->air_lo : &g->mass,
        .air_hi = ig->air_implicit ? &g->air_hi : &g->mass, .fric_lo = fric ? &g->nw_fa[0] : &g->mass,
        .fric_hi = fric ? &g->nw_fa[1] : &g->mass, .fric_b = fric ? &g->nw_fb : &g->mass});
    wg_u1f(run, "u_h", h);
    wg_u1i(run, "u_friction", fric);
    wg_u1i(run, "u_air", ig->air_implicit);
    wg_u1i(run, "u_air_at_wa", ig->air_implicit && g->nw_refreshed && !air_frozen(g, ig));
    WG_RUN(run, g->n, &g->nw_gd);
    /* the penalty pairs' change added per particle (wg_pairs.h): one reduction for both */
    const wg_tex* parts = g->pairs ? wg_pairs_energy_change(g->pairs, ig, wa, wb, &g->nw_gd) : &g->nw_gd;
    float p[4], q[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], parts, 0, 0, 0, 0), p);
    WG_USE(run, WGP_NEWTON_PHI_SPRINGS, &(wg_newton_phi_springs_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
        .wa = wa, .wb = wb, .xb = wg_integ_xb(g, ig), .spring = &g->spring, .spring_rest = &g->spring_rest,
        .rest = &g->rest, .wd = g->nw_held ? &g->nw_wd : wa});
    wg_u4f(run, "u_k", g->m->material.k);
    wg_u4f(run, "u_d", g->m->material.d);
    wg_u1f(run, "u_h", h);
    wg_u1f(run, "u_seam_scale", s->seam_scale);
    wg_u1i(run, "u_refresh", !g->nw_refreshed ? 0 : g->nw_held ? 2 : 1);
    WG_RUN(run, g->ns, &g->chk_s);
    wg_read1(&g->layout, wg_reduce(run, &g->red_s, &g->chk_s, 0, 0, 0, 0), q);
    return (double)p[0] + (double)q[0];
}

/* The line search of the first step (core/newton.c): from w~0 = z + S (-v*) along d0 = w1 - w~0,
 * alpha = 1 (w1 itself), 1/2, ... until Armijo's test against the slope of the first system's
 * quadratic model holds. Returns the accepted iterate, or w~0 with *stop set. */
static const wg_tex* first_search(wg_sim* g, const wc_state* s, const wc_integ* ig, const wg_tex* w1, int* stop,
                                  wc_step_stats* st) {
    wg_runner* run = &g->run;
    wg_tex* w0 = spare(g, w1, NULL);
    WG_USE(run, WGP_NEWTON_START, &(wg_newton_start_in){.v = wg_integ_vstar(g, ig), .w1 = w1, .S0 = &g->S0,
        .S1 = &g->S1, .z = &g->z});
    WG_RUN(run, g->n, w0, &g->nw_d);
    /* (A w~0 - b) . d0 = -S (b - A w~0) . d0, d0 being in S's range */
    WG_USE(run, WGP_RESIDUAL, &(wg_residual_in){.pblocks = &g->pblocks, .block = &g->block, .a_lo = &g->A0,
        .a_hi = &g->A1, .x = w0, .b = &g->b, .S0 = &g->S0, .S1 = &g->S1, .pairs = wg_sim_pair_in(g)});
    wg_sim_pair_uniform(g);
    WG_RUN(run, g->n, &g->rz);
    wg_tex* trial = spare(g, w1, w0);
    const double slope = -step_to(g, w0, &g->nw_d, &g->rz, 1.0, trial);
    double alpha = 1.0;
    for (int b = 0; b <= NW_BACKTRACKS; ++b, alpha *= 0.5) {
        const wg_tex* at = w1;
        if (b > 0) {
            step_to(g, w0, &g->nw_d, &g->rz, alpha, trial);
            at = trial;
        }
        if (wg_newton_phi_change(g, s, ig, w0, at) <= NW_ARMIJO * alpha * (slope < 0.0 ? slope : 0.0)) return at;
        ++st->backtracks;
    }
    *stop = 1;
    return w0;
}

void wg_newton_iterate(wg_sim* g, const wc_state* s, const wc_integ* ig, wc_solver_type solver,
                       wc_compression compression, double residual_scale, double energy_cap, const wg_tex** dv,
                       const wg_tex** r_dv, wc_step_stats* st) {
    wg_runner* run = &g->run;
    const wg_tex* w = &g->nw_w[0];
    g->nw_refreshed = 0;
    g->nw_held = 0;
    if (g->nw_friction) wg_newton_friction(g, 1);
    wg_copy(run, &g->nw_w[0], *dv);
    const int ls = s->def.line_search != 0;
    int stop = 0;
    if (ls) w = first_search(g, s, ig, w, &stop, st);
    const wg_tex* rv = NULL;   /* the contacts' residual vector: NULL while the first system is the last */
    const double tol = s->def.solver.tolerance > 1e-12 ? s->def.solver.tolerance : 1e-12;
    /* the gradient's float floor (as PCG's, wg_solve.c): each spring force k (l - rest) u rounds
       by about 2^-24 |k| l (l's own rounding; at rest the terms k l and k rest cancel), and
       h m gravity against m w by 2^-24 of the solves' residual floor (wc_state_residual_floor:
       their norm). 2^-24 of these terms' sizes summed per particle (the springs at their rest
       lengths) is what float can resolve of |S g|: below it core's exact stop cannot be seen, a
       step would solve for rounding and its line search compare rounding */
    const double gfloor = ldexp(ig->he * g->nw_force_scale + g->residual_floor, -24);
    wc_solver_opts opts = s->def.solver;
    const int guard = energy_cap < HUGE_VAL;
    /* TR-BDF2's stage 1 holds its damping directions from the first system on and iterates to its
       own tolerance (core/newton.c "Stage 1"; g->nw_stage1_ok: no contact or penalty pair) */
    const int n_it = s->def.newton_iterations;
    const double s1_tol = s->def.stage1_tolerance;
    const int stage1 = ig->stage == 1 && n_it > 1 && s1_tol > 0.0 && g->nw_stage1_ok;
    const int extra = guard && NW_ENERGY_EXTRA > (stage1 ? WC_NEWTON_STAGE1_EXTRA : 0) ? NW_ENERGY_EXTRA
                      : stage1                                                         ? WC_NEWTON_STAGE1_EXTRA
                                                                                       : 0;
    int converged = 0;
    /* stage 1's held directions move once, to the iterate converged with w_1's (core/newton.c
       "Stage 1"): nw_wd then keeps that iterate, the stage's end when the moved ones do not converge */
    int rehold = stage1 && n_it >= WC_NEWTON_STAGE1_MOVE_FROM, moved = 0, end = n_it + extra;
    double glast = 0.0;   /* the last gradient tested, over residual_scale */
    for (int it = 1; it < end && !stop; ++it) {
        const int past = it >= n_it;
        int hot = 0;   /* past the count: the energy guard wants this iteration */
        if (past) {
            /* past the configured count only while the iterate holds more energy than the
               substep may end with (core/newton.h "Energy guard"): x(w), v(w) into the free slots;
               or stage 1 is not converged */
            if (guard && it < n_it + NW_ENERGY_EXTRA) {
                const wg_tex* xw = &g->x.t[wg_ring_other(&g->x, 0)];
                const wg_tex* vw = &g->v.t[wg_ring_other(&g->v, 0)];
                gradient_pass(g, ig, &g->nw_zero, w, 0, &g->nw_gd, xw, vw);
                hot = wg_checks_energy(g, s, xw, vw) > energy_cap;
            }
            if (!hot && !stage1) break;
            if (hot) ++st->energy_iterations;
        }
        wg_newton_system(g, s, ig, w, compression);
        if (stage1 && it == 1) {   /* the directions just refreshed at w_1 are held from here on */
            wg_copy(run, &g->nw_wd, w);
            g->nw_held = 1;
        }
        rv = &g->nw_zero;   /* core's R_GRADIENT: -g at w */
        double gn = sqrt(filtered_norm2(g));
        if (rehold && it > 1 && !(gn > s1_tol * residual_scale)) {
            rehold = 0;
            moved = 1;
            if (end < it + WC_NEWTON_STAGE1_MOVED) end = it + WC_NEWTON_STAGE1_MOVED;
            wg_copy(run, &g->nw_wd, w);
            wg_newton_system(g, s, ig, w, compression);
            gn = sqrt(filtered_norm2(g));
        }
        glast = gn / residual_scale;
        if (!(gn > fmax(tol * residual_scale, gfloor)) || (past && !hot && !(gn > s1_tol * residual_scale))) {
            converged = 1;
            break;
        }
        if (past && !hot) ++st->stage1_iterations;
        /* A d = g from d = 0 with the filter's z = 0 (the iterate already holds the prescribed part) */
        wg_tex z = g->z;
        g->z = g->nw_zero;
        const wg_tex* d = NULL;
        wc_solve_result res;
        wc_status status = wg_solve(g, &opts, solver, &g->nw_zero, &d, &res);
        g->nw_zero = g->z;
        g->z = z;
        wc_step_stats_add_solve(st, solver, &res);
        if (status != WC_OK) break;   /* the iterate before it is kept, as core's */
        wg_tex* trial = spare(g, w, NULL);
        const double slope = -step_to(g, w, d, &g->b, 1.0, trial);   /* grad Phi . d */
        if (!(slope < 0.0)) break;
        double alpha = 1.0;
        if (ls) {
            /* alpha = 1, 1/2, ... until Armijo's test holds; none: the iterate stays, Newton stops
               (core's flat-potential stop, a decrease below 1e-13 of Phi, is below float's
               resolution: not tested) */
            int ok = wg_newton_phi_change(g, s, ig, w, trial) <= NW_ARMIJO * alpha * slope;
            for (int b = 1; b <= NW_BACKTRACKS && !ok; ++b) {
                alpha *= 0.5;
                ++st->backtracks;
                step_to(g, w, d, &g->b, alpha, trial);
                ok = wg_newton_phi_change(g, s, ig, w, trial) <= NW_ARMIJO * alpha * slope;
            }
            if (!ok) break;
        }
        if (g->contacts) {
            /* core's R_STEP: the step alpha d from the last system's iterate (nw_d is free after the
               first search) */
            WG_USE(run, WGP_NEWTON_STEP, &(wg_newton_step_in){.w = &g->nw_zero, .d = d, .g = &g->b});
            wg_u1f(run, "u_alpha", alpha);
            WG_RUN(run, g->n, &g->nw_d, &g->nw_gd);
            rv = &g->nw_d;
        }
        w = trial;
        ++st->newton_iterations;
    }
    if (moved && !converged && glast > s1_tol) {   /* the moved directions did not converge: back to nw_wd's iterate */
        wg_tex* t = spare(g, w, NULL);
        wg_copy(run, t, &g->nw_wd);
        w = t;
        converged = 1;
        wg_newton_system(g, s, ig, w, compression);   /* its gradient for the residual (core's R_GRADIENT) */
        rv = &g->nw_zero;
    }
    if (stage1 && !converged) ++st->stage1_unconverged;
    g->nw_held = 0;
    *dv = w;
    *r_dv = rv ? rv : w;
}
