/* Newton's further iterations of a backward-Euler substep on the GPU: core/newton.c without the
 * line search. At the iterate w (the velocity change; x(w) = x_n + h (v_n + w)): the springs'
 * elastic forces and stiffness at x(w) with the substep start's damping directions
 * (newton_springs.glsl), h f_total (assemble_b.glsl), g = -grad Phi(w) = h f_total - M w
 * (newton_gradient.glsl) into b and A into its blocks; stop when |S g| is within the solver's
 * tolerance of the first solve's scale (a reduction read back); solve A d = g under the substep's
 * filter S with z = 0 (so every iterate keeps the first one's prescribed part); stop unless d
 * descends (g.d > 0, a reduction read back); w += d. The energy guard as core's: past
 * newton_iterations, up to NW_ENERGY_EXTRA more iterations while the iterate's total energy
 * (the step's checks at x(w), v(w), read back) is above the cap. Colliders are refused with
 * Newton at creation (wg_sim_create): kinetic friction's frozen terms are not carried here. */
#include <math.h>

#include "wg_sim_impl.h"

/* Newton's system at w: A0/A1 and b = -grad Phi(w); the iterate's x(w), v(w) into the rings'
 * free slots (the integration after the iterations writes them anew). */
static void newton_system(wg_sim* g, const wc_state* s, double h, const wg_tex* w, wc_compression compression) {
    const wc_model* m = g->m;
    wg_runner* run = &g->run;
    WG_USE(run, WGP_NEWTON_SPRINGS, &(wg_newton_springs_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
        .w = w, .spring = &g->spring, .spring_rest = &g->spring_rest, .rest = &g->rest});
    wg_u4f(run, "u_k", m->material.k);
    wg_u4f(run, "u_d", m->material.d);
    wg_u1f(run, "u_h", h);
    wg_u1f(run, "u_seam_scale", s->seam_scale);
    wg_u1i(run, "u_compression_drop", compression == WC_COMPRESSION_DROP);
    WG_RUN(run, g->ns, &g->sf, &g->sw, &g->sj);
    /* the air of the substep's start stays in fair (frozen, as core's f_ext) */
    const wc_air* air = &s->def.air;
    int use_air = (air->normal_drag != 0.0 || air->tangent_drag != 0.0) && g->nt > 0;
    WG_USE(run, WGP_ASSEMBLE_B, &(wg_assemble_b_in){.mass = &g->mass, .rows = &g->rows, .row_entry = &g->row_entry,
        .spring_f = &g->sf, .spring_w = &g->sw, .row_tri = &g->row_tri, .tri_air = &g->fair});
    wg_u1f(run, "u_h", h);
    wg_u3f(run, "u_gravity", s->def.gravity);
    wg_u1i(run, "u_use_air", use_air);
    WG_RUN(run, g->n, &g->nw_hf, &g->ftot);
    WG_USE(run, WGP_NEWTON_GRADIENT, &(wg_newton_gradient_in){.hf = &g->nw_hf, .w = w, .mass = &g->mass,
        .x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v)});
    wg_u1f(run, "u_h", h);
    WG_RUN(run, g->n, &g->b, &g->x.t[wg_ring_other(&g->x, 0)], &g->v.t[wg_ring_other(&g->v, 0)]);
    WG_USE(run, WGP_ASSEMBLE_A, &(wg_assemble_a_in){.block = &g->block, .block_list = &g->block_list, .mass = &g->mass,
        .spring_f = &g->sf, .spring_w = &g->sw, .spring_j = &g->sj});
    WG_RUN(run, g->nb, &g->A0, &g->A1);
}

/* |S b|^2 (residual.glsl at x = 0), read back. */
static double filtered_norm2(wg_sim* g) {
    wg_runner* run = &g->run;
    WG_USE(run, WGP_RESIDUAL, &(wg_residual_in){.pblocks = &g->pblocks, .block = &g->block, .a_lo = &g->A0,
        .a_hi = &g->A1, .x = &g->nw_zero, .b = &g->b, .S0 = &g->S0, .S1 = &g->S1});
    WG_RUN(run, g->n, &g->rz);
    float v[4];
    wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->rz, 0, 0, 0, 0), v);
    return (double)v[3];
}

#define NW_ENERGY_EXTRA 4   /* core/newton.c's: iterations past newton_iterations at most while the
                               iterate holds more energy than the cap */

void wg_newton_iterate(wg_sim* g, const wc_state* s, double h, wc_solver_type solver, wc_compression compression,
                       double residual_scale, double energy_cap, const wg_tex** dv, wc_step_stats* st) {
    wg_runner* run = &g->run;
    int cur = 0;
    wg_copy(run, &g->nw_w[cur], *dv);
    const double tol = s->def.solver.tolerance > 1e-12 ? s->def.solver.tolerance : 1e-12;
    wc_solver_opts opts = s->def.solver;
    const int guard = energy_cap < HUGE_VAL;
    for (int it = 1; it < s->def.newton_iterations + (guard ? NW_ENERGY_EXTRA : 0); ++it) {
        newton_system(g, s, h, &g->nw_w[cur], compression);
        if (it >= s->def.newton_iterations) {
            /* past the configured count only while the iterate holds more energy than the
               substep may end with (core/newton.h "Energy guard") */
            double e = wg_checks_energy(g, s, &g->x.t[wg_ring_other(&g->x, 0)], &g->v.t[wg_ring_other(&g->v, 0)]);
            if (!(e > energy_cap)) break;
            ++st->energy_iterations;
        }
        double gn = sqrt(filtered_norm2(g));
        if (!(gn > tol * residual_scale)) break;
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
        int next = 1 - cur;
        WG_USE(run, WGP_NEWTON_STEP, &(wg_newton_step_in){.w = &g->nw_w[cur], .d = d, .g = &g->b});
        WG_RUN(run, g->n, &g->nw_w[next], &g->nw_gd);
        float slope[4];
        wg_read1(&g->layout, wg_reduce(run, &g->red_p[0], &g->nw_gd, 0, 0, 0, 0), slope);
        if (!((double)slope[0] > 0.0)) break;   /* grad Phi . d = -g.d must be negative */
        cur = next;
        ++st->newton_iterations;
    }
    *dv = &g->nw_w[cur];
}
