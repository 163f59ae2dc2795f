/* A frame on the GPU: core's frame driver (wc_step_frame_ops: schedule, retries, judging, stats,
 * sleeping) with this file's substep, save/restore and measures. A substep (TR-BDF2: each of its
 * two stages) is the chain of passes of core/step.c's stage_step(), with core's integrator
 * coefficients (core/bdf2.h wc_integ_coefficients): pins (and contacts) into the filter, the
 * integrator's xb, v*, mom and history (BDF2, TR-BDF2; TR-BDF2's contact landing), springs, air,
 * assembly of b by particles and of A by blocks, (the penalty pairs found and assembled:
 * wg_pairs.h), (friction), the solve, (the pairs' rechecks and their solves), (Newton's iterations
 * and line search: wg_newton.c), (contact release; TR-BDF2's stage 1 holds its impulses instead),
 * integration with the pins snapped, strain limiting, (contact projection), (self-collision:
 * core's stage on the host, wg_self.h, unless the GPU proves it idle, wg_self_idle.h), and the checks as reductions (wg_checks.c): one read-back
 * of four texels per substep feeds core's judge. Rollback moves no data: the state rings keep the
 * substep's start. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "gpu_error.h"
#include "penalty_pairs.h"
#include "wg_mesh.h"
#include "wg_sim_impl.h"

/* springs.glsl and check_springs.glsl take the stiffness and damping of every spring type in a vec4 */
_Static_assert(WC_SPRING_TYPE_COUNT == 4, "one vec4 component per spring type");

/* What a timestamp (wg_stamps.h) starts: the stages of the step's statistics. */
typedef enum wg_stage {
    WG_STAGE_COLLIDE, WG_STAGE_FORCES, WG_STAGE_ASSEMBLE, WG_STAGE_SOLVE, WG_STAGE_INTEGRATE, WG_STAGE_COUNT
} wg_stage;

/* Pins of this frame: the particle map when the pinned set changed, targets every frame. */
void wg_step_upload_pins(wg_sim* g, const wc_state* s) {
    int n_pins = s->n_pins < g->pin_cap ? s->n_pins : g->pin_cap;
    int same = n_pins == g->n_pins_uploaded;
    for (int k = 0; k < n_pins && same; ++k) same = g->pin_particle[k] == s->pins[k].particle;
    if (!same) {
        for (int k = 0; k < g->n_pins_uploaded; ++k) g->pin_map_cpu[g->pin_particle[k]] = -1;
        for (int k = 0; k < n_pins; ++k) {
            g->pin_particle[k] = s->pins[k].particle;
            g->pin_map_cpu[s->pins[k].particle] = k;
        }
        g->n_pins_uploaded = n_pins;
        wg_array_upload(&g->layout, &g->pin_map, g->n, g->pin_map_cpu);
    }
    if (n_pins == 0) return;
    float* f = g->pin_scratch;
    for (int k = 0; k < n_pins; ++k)
        for (int c = 0; c < 4; ++c) f[4 * k + c] = c < 3 ? (float)s->pin_from[3 * k + c] : 0.0f;
    wg_array_upload(&g->layout, &g->pin_from, n_pins, f);
    for (int k = 0; k < n_pins; ++k)
        for (int c = 0; c < 4; ++c) f[4 * k + c] = c < 3 ? (float)s->pins[k].target[c] : 0.0f;
    wg_array_upload(&g->layout, &g->pin_target, n_pins, f);
    for (int k = 0; k < n_pins; ++k)
        for (int c = 0; c < 4; ++c) f[4 * k + c] = c < 3 ? (float)s->pins[k].free_axis[c] : 0.0f;
    wg_array_upload(&g->layout, &g->pin_axis, n_pins, f);
}

/* 1 when the substep has colliders: mesh colliders or analytic ones. */
static int colliding(const wc_state* s) { return s->n_mesh + s->n_colliders > 0; }

/* Pins, contacts, the integrator's vectors, springs, air, assembly: s->filter's GPU twin (S0, S1,
 * z), A0/A1, b (wg_sim_impl.h). */
void wg_step_prepare(wg_sim* g, wc_state* s, const wc_integ* ig, double alpha1, wc_compression compression) {
    const double h = ig->h, he = ig->he;
    g->residual_floor = wc_state_residual_floor(s, he); /* the solves' floor, as core's prepare */
    const wc_model* m = g->m;
    wg_runner* run = &g->run;
    wg_stamp(&g->stamps, WG_STAGE_COLLIDE);
    const wg_tex* x_start = wg_ring_cur(&g->x);   /* kept until integ_prepare: the contacts write another slot */
    WG_USE(run, WGP_PINS, &(wg_pins_in){.x = x_start, .v = wg_ring_cur(&g->v),
        .xp = g->integ ? wg_ring_cur(&g->xp) : x_start, .pin_map = &g->pin_map, .pin_from = &g->pin_from,
        .pin_target = &g->pin_target, .pin_axis = &g->pin_axis});
    wg_u1i(run, "u_n_pins", g->n_pins_uploaded);
    wg_u1f(run, "u_he", he);
    wg_u1f(run, "u_base_x", ig->bdf2 ? 1.0 / 3.0 : ig->stage == 2 ? WC_TRBDF2_C2 : 0.0);   /* wc_integ_base */
    wg_u1f(run, "u_base_v", ig->stage == 1 ? he : 0.0);
    wg_u1f(run, "u_alpha1", alpha1);
    WG_RUN(run, g->n, &g->S0, &g->S1, &g->z);
    if (colliding(s)) wg_contacts_begin(g->contacts, s, alpha1, h);
    if (g->integ) wg_integ_prepare(g, s, ig, x_start);
    if (colliding(s) && ig->stage) {   /* TR-BDF2: the contacts in the xb form (core/bdf2.c wc_integ_contacts) */
        const wg_contact_integ io = {&g->xb, &g->vstar, &g->mom, &g->vp};
        wg_contacts_integ(g->contacts, &io, ig->stage, h, he);
    }
    if (g->pairs) {   /* the penalty pairs found where core's prepare finds them (wg_pairs.h) */
        const wg_mesh* mesh = wg_contacts_mesh(g->contacts);
        wg_pairs_find(g->pairs, s, ig, wg_ring_cur(&g->x), wg_ring_cur(&g->v), wg_integ_vstar(g, ig),
                      wg_integ_xb(g, ig), g->n_pins_uploaded, mesh && mesh->n_resident > 0 ? g->sharp : NULL);
        if (g->amg) wg_amg_set_pairs(g->amg, g->pairs);   /* their terms in every level */
    }

    wg_stamp(&g->stamps, WG_STAGE_FORCES);
    WG_USE(run, WGP_SPRINGS, &(wg_springs_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
        .vstar = wg_integ_vstar(g, ig), .spring = &g->spring, .spring_rest = &g->spring_rest, .rest = &g->rest});
    wg_u4f(run, "u_k", m->material.k);
    wg_u4f(run, "u_d", m->material.d);
    wg_u1f(run, "u_h", he);
    wg_u1f(run, "u_seam_scale", s->seam_scale);   /* the host pairs' ramp, constant over the frame */
    wg_u1i(run, "u_compression_drop", compression == WC_COMPRESSION_DROP);
    WG_RUN(run, g->ns, &g->sf, &g->sw, &g->sj);
    const wc_air* air = &s->def.air;
    int use_air = (air->normal_drag != 0.0 || air->tangent_drag != 0.0) && g->nt > 0;
    if (use_air) {
        WG_USE(run, WGP_AIR, &(wg_air_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v), .tri = &g->tri});
        wg_u3f(run, "u_wind", air->wind);
        wg_u2f(run, "u_drag", air->normal_drag, air->tangent_drag);
        WG_RUN(run, g->nt, &g->fair);
    }
    if (ig->air_implicit) wg_integ_air_lump(g, s, wg_ring_cur(&g->x));

    wg_stamp(&g->stamps, WG_STAGE_ASSEMBLE);
    const int mom_mode = ig->stage == 1 ? 2 : ig->bdf2 || ig->stage ? 1 : 0;   /* assemble_b.glsl's u_mom */
    WG_USE(run, WGP_ASSEMBLE_B, &(wg_assemble_b_in){.mass = &g->mass, .rows = &g->rows, .row_entry = &g->row_entry,
        .spring_f = &g->sf, .spring_w = &g->sw, .row_tri = &g->row_tri, .tri_air = &g->fair,
        .mom = mom_mode == 1 ? &g->mom : &g->mass});
    wg_u1f(run, "u_h", he);
    wg_u3f(run, "u_gravity", s->def.gravity);
    wg_u1i(run, "u_use_air", use_air);
    wg_u1i(run, "u_mom", mom_mode);
    if (mom_mode == 2) WG_RUN(run, g->n, &g->b, &g->ftot, &g->nw_fext, &g->mom);   /* stage 1: mom = he f0 / m */
    else if (g->newton) WG_RUN(run, g->n, &g->b, &g->ftot, &g->nw_fext);   /* f_ext: the line search's potential */
    else WG_RUN(run, g->n, &g->b, &g->ftot);
    wg_integ_assemble_a(g, ig->air_implicit ? he : 0.0, 0);
    if (g->pairs) wg_pairs_assemble(g->pairs, s, ig);   /* before friction, which reads A, b and ftot */
    /* Newton tells friction's terms apart by this capture (zero where no friction pass runs) */
    if (g->nw_friction) wg_newton_friction(g, 0);
    if (colliding(s) && g->contacts) {
        wg_stamp(&g->stamps, WG_STAGE_COLLIDE);
        wg_contacts_friction(g->contacts, s, he, ig->stage ? &g->mom : NULL);
    }
}

#define FRICTION_PASSES 4   /* as core/step.c */

/* The judge's measure of a substep's start from its checks. */
static wc_substep_measure start_measure(const wg_checks* c) {
    wc_substep_measure m = {0};
    m.kinetic = c->kinetic;
    m.elastic = (double)c->kinetic + (double)c->elastic;
    m.total = m.elastic + (double)c->gravity;
    return m;
}

/* The penalty pairs' counts of a substep (stage) of length h into the statistics, the lists'
 * overflows logged as core/step.c's are. */
static void add_pair_counts(const wg_pair_counts* c, double h, wc_step_stats* st, wc_diag* diag) {
    st->mesh_pairs += c->mesh;
    st->mesh_pairs_active += c->mesh_active;
    st->mesh_pair_overflow += c->mesh_overflow;
    st->mesh_pair_skipped += c->mesh_skipped;
    st->self_pairs += c->self;
    st->self_pairs_active += c->self_active;
    st->self_pair_overflow += c->self_overflow;
    if (c->self_overflow > 0 || c->mesh_overflow > 0 || c->mesh_skipped > 0)
        wc_log(diag, WC_LOG_WARN,
               "substep (h = %g s, GPU): %d self-contact pairs and %d mesh feature pairs past the lists' capacities "
               "and %d without pattern blocks were left out of the solve", h, c->self_overflow, c->mesh_overflow,
               c->mesh_skipped);
}

/* TR-BDF2's total-energy judgement spans the whole substep (core/step.c stage_energy): stage 1
 * fills this in, stage 2 is judged against it. */
typedef struct stage_energy {
    double start_total;     /* J: total energy at the substep's start */
    double start_elastic;   /* J: its measure's elastic part (the allowance's scale) */
    double excluded;        /* J: what stage 1's collider corrections and self-collision stage put in */
} stage_energy;

/* One backward-Euler or BDF2 substep of length h, or TR-BDF2's stage `stage` (1 or 2) of the
 * substep of length h with `carry` from stage 1 to stage 2, ending at frame fraction alpha1
 * (core/step.c stage_step). Does not roll back: returns non-OK when the result must be discarded. */
static wc_status gpu_stage(wg_sim* g, wc_state* s, double h, int stage, double alpha1, wc_solver_type solver,
                           int judge, double pin_energy, stage_energy* carry, wc_step_stats* st, wc_diag* diag) {
    wg_runner* run = &g->run;
    wc_substep_measure before, after = {0};
    int judge_energy = wc_substep_judges_energy(s, judge, pin_energy);
    wg_checks_run(g, s, wg_ring_cur(&g->x), wg_ring_cur(&g->v), WG_CHECKS_START);   /* read back with the end's */
    /* the start is read back when the stage runs, or now where the idle proof is not tried */
    const int proof = g->self_idle && wg_self_idle_begin(g->self_idle, wg_ring_cur(&g->x));
    if (g->self && !proof) wg_self_begin(g->self, s->self, wg_ring_cur(&g->x));   /* the previous substep's end */

    wc_integ ig;
    wc_integ_coefficients(s, h, stage, &ig);
    h = ig.h;   /* TR-BDF2: the stage's length */
    const wc_compression compression = judge != WC_JUDGE_ALL ? WC_COMPRESSION_DROP : s->def.compression;
    wg_step_prepare(g, s, &ig, alpha1, compression);
    if (g->pairs) add_pair_counts(wg_pairs_counts(g->pairs), h, st, diag);
    /* the colliders' position corrections (begin's push out of the shells, project's) are
       collision responses: the energy they put in is left out of the judgement, as core's
       collide_gain (core/step.c stage_step); begin's (with TR-BDF2's contact velocities) measured
       now (two texels read back), and Newton's energy guard starts from the energy after it. */
    const int judge_collide = judge_energy && colliding(s) && g->contacts;
    double collide_gain = 0.0, begin_total = 0.0;   /* J */
    if (judge_collide) {
        wg_checks start;
        wg_checks_read(g, &start, NULL);
        begin_total = wg_checks_energy(g, s, wg_ring_cur(&g->x), wg_ring_cur(&g->v));
        collide_gain = fmax(begin_total - start_measure(&start).total, 0.0);
    }
    wg_stamp(&g->stamps, WG_STAGE_SOLVE);
    wc_solver_opts opts = s->def.solver;
    const wg_tex *dvres = NULL, *rdv = NULL;
    wc_solve_result res;
    /* inexact Newton (core/step.c first_solve): with further iterations to correct it, the first
       solve stops at forcing x its own residual, unless a contact sticks (a friction recheck
       reads its forces off that solve: the count read back) or penalty pairs are in the system;
       res.scale stays the tight solve's */
    const double tolerance = opts.tolerance, floor = g->residual_floor, forcing = s->def.newton_forcing;
    const int loose = s->def.newton_iterations > 1 && forcing > tolerance && !wg_pairs_on(g->pairs) &&
                      !(colliding(s) && wg_contacts_stuck(g->contacts) > 0);
    if (loose) {
        opts.tolerance = forcing;
        g->residual_floor = floor * tolerance / forcing;
    }
    wc_status status = wg_solve(g, &opts, solver, wg_ring_cur(&g->dv), &dvres, &res);
    if (loose) {
        opts.tolerance = tolerance;
        g->residual_floor = floor;
        res.scale = fmax(res.residual0, floor);
        wc_solve_result counted = res;
        counted.residual = 0.0;   /* held to the forcing term (step_stats.h) */
        wc_step_stats_add_solve(st, solver, &counted);
    } else {
        wc_step_stats_add_solve(st, solver, &res);
    }
    /* as core/step.c: with Newton iterations to follow, a later recheck's releases go into the
       next Newton iteration's system instead of a solve of their own */
    const int newton_takes_tail = g->newton && s->def.newton_iterations > 1;
    for (int pass = 0; pass < FRICTION_PASSES && status == WC_OK && colliding(s) && g->contacts; ++pass) {
        if (!wg_contacts_recheck(g->contacts, s, dvres)) break;
        if (pass > 0 && newton_takes_tail) break;
        ++st->friction_passes;
        /* the next solve starts from this one's result: keep it out of the solver's iterates */
        int nd = wg_ring_other(&g->dv, 0);
        wg_copy(run, &g->dv.t[nd], dvres);
        status = wg_solve(g, &opts, solver, &g->dv.t[nd], &dvres, &res);
        wc_step_stats_add_solve(st, solver, &res);
    }
    /* the penalty pairs (the mesh colliders' feature pairs, then the self-contact pairs) whose
       solved gap disagrees with their state switch, and the system is solved again (core/step.c
       pair_passes; only without Newton's iterations, which take the pairs' exact terms instead) */
    for (int list = 0; list < 2 && status == WC_OK && !g->newton; ++list)
        for (int pass = 0; pass < WC_PENALTY_PASSES && status == WC_OK && wg_pairs_list_on(g->pairs, list); ++pass) {
            if (wg_pairs_recheck(g->pairs, s, list, &ig, dvres) == 0) break;
            ++*(list ? &st->self_pair_passes : &st->mesh_pair_passes);
            int nd = wg_ring_other(&g->dv, 0);
            wg_copy(run, &g->dv.t[nd], dvres);
            status = wg_solve(g, &opts, solver, &g->dv.t[nd], &dvres, &res);
            wc_step_stats_add_solve(st, solver, &res);
        }
    if (status != WC_OK)
        return wc_fail(diag, status, "substep (h = %g s, %s, GPU): the solver failed (status %d)", h,
                       wc_solver_name(solver), (int)status);
    if (g->newton) {
        /* Newton's energy guard (core/step.c): the start's energy (after begin's correction with
           colliders; TR-BDF2's stage 2: the substep's start's) plus what the judge allows; the
           start's checks read back now (one more read-back) */
        double energy_cap = HUGE_VAL;
        if (judge_energy) {
            wg_checks start;
            wg_checks_read(g, &start, NULL);
            wc_substep_measure m0 = start_measure(&start);
            if (stage == 2) {   /* the substep's start, with what stage 1's and this stage's begin put in */
                m0.total = carry->start_total + carry->excluded;
                m0.elastic = carry->start_elastic;
                energy_cap = m0.total + collide_gain + wc_substep_energy_allowance(s, &m0);
            } else {
                energy_cap = (judge_collide ? begin_total : m0.total) + wc_substep_energy_allowance(s, &m0);
            }
        }
        /* TR-BDF2's implicit air stays the stage start's while a contact is active (core/newton.h
           "Refreshed"): the count read back */
        const int ask = ig.air_implicit || (ig.stage == 1 && s->def.newton_iterations > 1);   /* a read-back */
        const int contact = ask && colliding(s) && wg_contacts_active(g->contacts) > 0;
        g->nw_air_frozen = ig.air_implicit && contact;
        g->nw_stage1_ok = !contact && !wg_pairs_list_on(g->pairs, 0) && !wg_pairs_list_on(g->pairs, 1);
        wg_newton_iterate(g, s, &ig, solver, compression, res.scale, energy_cap, &dvres, &rdv, st);
    }
    int nd = wg_ring_other(&g->dv, 0);
    wg_copy(run, &g->dv.t[nd], dvres);

    wg_stamp(&g->stamps, WG_STAGE_INTEGRATE);
    /* the release reads the last linearisation's residual (core/newton.h wc_newton_iterate) */
    if (colliding(s)) wg_contacts_end(g->contacts, s, rdv ? rdv : &g->dv.t[nd], stage);
    int nx = wg_ring_other(&g->x, 0), nv = wg_ring_other(&g->v, 0);
    WG_USE(run, WGP_INTEGRATE, &(wg_integrate_in){.xb = wg_integ_xb(g, &ig), .v = wg_ring_cur(&g->v),
        .dv = &g->dv.t[nd], .pin_map = &g->pin_map, .pin_from = &g->pin_from, .pin_target = &g->pin_target,
        .pin_axis = &g->pin_axis});
    wg_u1i(run, "u_n_pins", g->n_pins_uploaded);
    wg_u1f(run, "u_he", ig.he);
    wg_u1f(run, "u_alpha1", alpha1);
    WG_RUN(run, g->n, &g->x.t[nx], &g->v.t[nv]);
    g->x.cur = nx;
    g->v.cur = nv;
    g->dv.cur = nd;
    if (stage == 1) wg_copy(run, &g->xs, wg_ring_cur(&g->x));   /* x_g as solved (core/bdf2.c wc_integ_solved) */
    if (s->def.strain_limit > 0 && s->def.strain_passes > 0) {
        /* core stops early once no spring is above the limit; here every pass runs (a pass with
           nothing to correct changes nothing) */
        for (int pass = 0; pass < s->def.strain_passes; ++pass) {
            WG_USE(run, WGP_STRAIN_SPRINGS, &(wg_strain_springs_in){.x = wg_ring_cur(&g->x), .spring = &g->spring,
                .spring_rest = &g->spring_rest, .mass = &g->mass, .S0 = &g->S0, .S1 = &g->S1});
            wg_u1f(run, "u_limit", s->def.strain_limit);
            WG_RUN(run, g->ns, &g->corr);
            int sx = wg_ring_other(&g->x, 0), sv = wg_ring_other(&g->v, 0);
            WG_USE(run, WGP_STRAIN_GATHER, &(wg_strain_gather_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v),
                .rows = &g->rows, .row_entry = &g->row_entry, .corr = &g->corr, .mass = &g->mass, .S0 = &g->S0,
                .S1 = &g->S1, .spring = &g->spring});
            wg_u1f(run, "u_h", ig.he);
            WG_RUN(run, g->n, &g->x.t[sx], &g->v.t[sv]);
            g->x.cur = sx;
            g->v.cur = sv;
        }
    }
    double project_from = 0.0;   /* J: before the projection (judge_collide) */
    if (colliding(s) && g->contacts) {
        wg_stamp(&g->stamps, WG_STAGE_COLLIDE);
        if (judge_collide) project_from = wg_checks_energy(g, s, wg_ring_cur(&g->x), wg_ring_cur(&g->v));
        wg_contacts_project(g->contacts, s);
    }
    /* self-collision at the very end, on the host (wg_self.h): timed there, not by the stamps */
    double self_gain = 0.0;   /* J: energy the self-collision stage put in (not judged, core/step.c) */
    if (g->self) {
        wg_stamp(&g->stamps, WG_STAGE_COUNT);
        double t0 = wc_now_ms();
        wc_self_stats ss = {0, 0, 0, 0, 0};
        /* the GPU's proof that the stage would move nothing (wg_self_idle.h); where it fails, the
           stage as without it, on the start positions the proof kept */
        int idle = 0;
        if (proof) {
            long long bytes = 0;
            if (g->self_prox && wg_self_idle_get_mode(g->self_idle) == WG_SELF_IDLE_ON) {
                /* core's proximity pass on the listed pairs, then the refined proof (wg_self_prox.h) */
                const int c = wg_self_idle_list(g->self_idle, wg_ring_cur(&g->x), wg_ring_cur(&g->v), 0,
                                                wg_self_prox_buffer(g->self_prox), &bytes);
                long long up = 0;
                int moved = 0;
                idle = c == 0;
                if (c > 0 && wg_self_prox_run(g->self_prox, g->self_idle, s->self, s, g->n_pins_uploaded, ig.he, c,
                                              wg_ring_cur(&g->x), wg_ring_cur(&g->v), &ss, &bytes, &up, &moved,
                                              judge_energy ? &self_gain : NULL)) {
                    idle = 1;
                    wg_self_count_prox(g->self, moved, up);
                }
                wg_self_idle_outcome(g->self_idle, !idle);
            } else {
                idle = wg_self_idle_count(g->self_idle, wg_ring_cur(&g->x), &bytes) == 0;
            }
            wg_self_count_proof(g->self, idle, bytes);
        } else if (g->self_idle) {
            wg_self_count_untried(g->self);
        }
        const int check = idle && wg_self_idle_get_mode(g->self_idle) == WG_SELF_IDLE_CHECK;
        if (!idle || check) {
            const long long uploads = wg_self_transfers(g->self)->uploads;
            if (proof) wg_self_begin(g->self, s->self, wg_self_idle_start(g->self_idle));
            wg_self_end(g->self, s->self, s, g->n_pins_uploaded, ig.he, wg_ring_cur(&g->x), wg_ring_cur(&g->v),
                        judge_energy, &ss, &self_gain);
            if (check) wg_self_count_check(g->self, wg_self_transfers(g->self)->uploads != uploads);
        }
        st->self_proximity += ss.proximity;
        st->self_impacts += ss.impacts;
        st->self_zones += ss.zones;
        st->self_unresolved += ss.unresolved;
        st->self_zone_relaxed += ss.relaxed;
        st->ms.self_collide += wc_now_ms() - t0;
    }
    wg_stamp(&g->stamps, WG_STAGE_INTEGRATE);
    wg_checks_run(g, s, wg_ring_cur(&g->x), wg_ring_cur(&g->v), WG_CHECKS_END);
    wg_checks start, end;
    wg_checks_read(g, &start, &end);
    wg_stamp(&g->stamps, WG_STAGE_COUNT);
    if (glGetError() != GL_NO_ERROR) g->gl_error = 1;

    before = start_measure(&start);
    if (stage == 2) {   /* judged from the substep's start (core/step_judge.h "TR-BDF2's energy") */
        before.total = carry->start_total;
        before.elastic = carry->start_elastic;
    } else if (stage == 1) {
        carry->start_total = before.total;
        carry->start_elastic = before.elastic;
    }
    after.finite = isfinite(end.max_coord) != 0;
    after.kinetic = end.kinetic;
    /* what the colliders' corrections (begin's, then the projection's) and the self-collision
       stage put in is not judged (core/step.c) */
    after.total = (double)end.kinetic + (double)end.elastic + (double)end.gravity - self_gain;
    double excluded = self_gain;
    if (judge_collide) {
        double project_gain = fmax(after.total - project_from, 0.0);
        after.total -= collide_gain + project_gain;
        excluded += collide_gain + project_gain;
    }
    if (stage == 2) after.total -= carry->excluded;
    if (stage == 1) carry->excluded = excluded;
    after.strain = end.max_strain;
    if (!after.finite) after.strain = HUGE_VAL;
    status = wc_substep_judge(s, &before, &after, judge, judge_energy && stage != 1, pin_energy, h,
                              wc_solver_name(solver), diag);
    if (status == WC_OK && ig.bdf2) ++st->bdf2_substeps;
    return status;
}

/* One substep of length h ending at frame fraction alpha1: a gpu_stage, or TR-BDF2's two (stage 1
 * to the fraction gamma of the way; core/step.c substep). */
static wc_status gpu_substep(void* user, wc_state* s, double h, double alpha1, wc_solver_type solver, int judge,
                               double pin_energy, wc_step_stats* st, wc_diag* diag) {
    wg_sim* g = user;
    if (s->def.integrator != WC_INTEGRATOR_TRBDF2)
        return gpu_stage(g, s, h, 0, alpha1, solver, judge, pin_energy, NULL, st, diag);
    double a0 = s->sub_alpha0, ag = a0 + WC_TRBDF2_GAMMA * (alpha1 - a0);
    stage_energy carry = {0.0, 0.0, 0.0};
    wc_status status = gpu_stage(g, s, h, 1, ag, solver, judge, pin_energy, &carry, st, diag);
    if (status != WC_OK) return status;
    s->sub_alpha0 = ag;
    status = gpu_stage(g, s, h, 2, alpha1, solver, judge, pin_energy, &carry, st, diag);
    s->sub_alpha0 = a0;
    return status;
}

static void gpu_save(void* user, wc_state* s) {
    wg_sim* g = user;
    wg_ring_save(&g->x);
    wg_ring_save(&g->v);
    wg_ring_save(&g->dv);
    if (g->integ) {   /* the history with the substep's start (core/bdf2.c wc_integ_save) */
        wg_ring_save(&g->xp);
        wg_ring_save(&g->vp);
        s->hist_valid0 = s->hist_valid;
        s->hist_h0 = s->hist_h;
    }
    if (colliding(s)) wg_contacts_save(g->contacts);
}

static void gpu_restore(void* user, wc_state* s) {
    wg_sim* g = user;
    wg_ring_restore(&g->x);
    wg_ring_restore(&g->v);
    wg_ring_restore(&g->dv);
    if (g->integ) {
        wg_ring_restore(&g->xp);
        wg_ring_restore(&g->vp);
        s->hist_valid = s->hist_valid0;
        s->hist_h = s->hist_h0;
    }
    if (colliding(s)) wg_contacts_restore(g->contacts);
    g->rho_valid = 0;
    wg_amg_cold(g->amg);   /* the retry's bounds estimated afresh */
}

static void gpu_measure(void* user, const wc_state* s, double* max_speed, double* kinetic, double* max_strain) {
    wg_sim* g = user;
    wg_checks_run(g, s, wg_ring_cur(&g->x), wg_ring_cur(&g->v), WG_CHECKS_START);
    wg_checks now;
    wg_checks_read(g, &now, NULL);
    *kinetic = now.kinetic;
    *max_speed = sqrt((double)now.max_v2);
    *max_strain = now.max_strain;
}

static void gpu_sleep(void* user, wc_state* s) {
    (void)s;
    wg_sim* g = user;
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, Z[9] = {0}, z3[3] = {0, 0, 0};
    wg_sim_transform_state(g, I, z3, Z, z3, I);   /* v = 0; the warm start kept, as core does */
}

/* The frame's stamps as the statistics' milliseconds per stage; 0 when there are none. */
static int collect_stamps(wg_sim* g, wc_step_stats* st) {
    double ms[WG_STAGE_COUNT] = {0};
    if (!wg_stamps_collect(&g->stamps, ms, WG_STAGE_COUNT)) return 0;
    st->ms.collide = ms[WG_STAGE_COLLIDE];
    st->ms.forces = ms[WG_STAGE_FORCES];
    st->ms.assemble = ms[WG_STAGE_ASSEMBLE];
    st->ms.solve = ms[WG_STAGE_SOLVE];
    st->ms.integrate = ms[WG_STAGE_INTEGRATE];
    return 1;
}

wc_status wg_sim_step_frame(wg_sim* g, wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag) {
    wc_step_stats local;
    wc_step_stats* st = stats ? stats : &local;
    double t0 = wc_now_ms();
    wg_stamps_reset(&g->stamps);
    g->gl_error = 0;
    glGetError();
    glDisable(GL_BLEND);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_RASTERIZER_DISCARD);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    wg_step_upload_pins(g, s);
    wg_mesh_host_frame(wg_contacts_mesh(g->contacts));   /* the bodies core's copy moves: their frame end */
    /* the multigrid's bounds estimated afresh at the frame's first solve: a frame depends on its
       starting state alone (snapshots, rollbacks, teleports) */
    wg_amg_cold(g->amg);
    wc_step_ops ops = {g, gpu_substep, gpu_save, gpu_restore, gpu_measure, gpu_sleep, s->def.solver.type};
    wc_status r = wc_step_frame_ops(s, dt, st, diag, &ops);
    wg_mesh_body_end_frame(wg_contacts_mesh(g->contacts));   /* as the driver ended core's bodies' frame */
    if (r == WC_OK && colliding(s) && g->contacts && !st->asleep) {
        s->contacts.active = wg_contacts_active(g->contacts);
        st->contacts = s->contacts.active;
    }
    GLenum e = glGetError();
    if ((g->gl_error || e != GL_NO_ERROR) && r == WC_OK)
        r = wc_fail(diag, WC_ERROR_GPU, "GPU step: GL error %s", e != GL_NO_ERROR ? wg_gl_error_name(e) : "in a pass");
    if (g->run.fault[0] && r == WC_OK) r = wc_fail(diag, WC_ERROR_GPU, "GPU step: %s", g->run.fault);
    if (!collect_stamps(g, st) && !st->asleep)
        st->ms.solve = wc_now_ms() - t0 - st->ms.forces - st->ms.assemble - st->ms.self_collide;
    const wg_mesh* body = wg_contacts_mesh(g->contacts);
    if (body && body->n_mesh > 0)
        wc_log(diag, WC_LOG_DEBUG,
               "GPU mesh colliders: %d of %d moved on the GPU; transfers since creation: %lld bytes uploaded, %lld "
               "bytes read back (their sharp pairs' not counted)",
               body->n_resident, body->n_mesh, body->up_bytes, body->read_bytes);
    if (g->self) {
        const wg_self_io* io = wg_self_transfers(g->self);
        wc_log(diag, WC_LOG_DEBUG,
               "GPU self-collision, transfers since creation: %lld stage runs, %lld bytes read back, %lld bytes "
               "uploaded by %lld of the runs; idle proof: %lld substeps, %lld skipped, %lld checked, %lld broken, %lld "
               "untried (backing off); %lld settled by the proximity pass on the listed pairs (%lld moved)",
               io->runs, io->read_bytes, io->upload_bytes, io->uploads, io->proofs, io->skipped, io->checked,
               io->broken, io->untried, io->prox_settled, io->prox_moved);
        if (getenv("WEFT_GPU_SELF_IO_STDERR"))   /* measurements (docs/design/gpu_self.md): the same line */
            fprintf(stderr, "self io: runs %lld read %lld up %lld proofs %lld skipped %lld untried %lld prox %lld moved %lld\n",
                    io->runs, io->read_bytes, io->upload_bytes, io->proofs, io->skipped, io->untried, io->prox_settled,
                    io->prox_moved);
    }
    if (g->self_prox) {
        const wg_self_prox_io* io = wg_self_prox_transfers(g->self_prox);
        wc_log(diag, WC_LOG_DEBUG,
               "GPU self proximity pass, since creation: %lld refined walks, %lld proved by the margin; %lld local "
               "energy gains, %lld full; largest |local - full| %.3e J, gain %.3e J, total %.3e J; margin proofs "
               "checked %lld, missed %lld (%lld pairs compared)",
               io->refined_walks, io->refined_skipped, io->local_gains, io->full_gains, io->gain_diff_max, io->gain_max,
               io->total_max, io->margin_checked, io->margin_missed, io->margin_pairs);
        if (getenv("WEFT_GPU_SELF_IO_STDERR"))
            fprintf(stderr, "self prox: refined walks %lld margin %lld local gains %lld full %lld diff %.3e gain %.3e "
                    "total %.3e margin checked %lld missed %lld pairs %lld\n", io->refined_walks, io->refined_skipped,
                    io->local_gains, io->full_gains, io->gain_diff_max, io->gain_max, io->total_max, io->margin_checked,
                    io->margin_missed, io->margin_pairs);
    }
    if (g->pairs) {
        const wg_pairs_io* io = wg_pairs_transfers(g->pairs);
        wc_log(diag, WC_LOG_DEBUG,
               "GPU penalty pairs, since creation: %lld substeps, %lld bytes read back; %lld Newton systems and %lld "
               "potential changes (on the GPU)", io->substeps, io->read_bytes, io->systems, io->changes);
    }
    if (g->gself) {
        const wg_self_pairs_io* io = wg_self_pairs_transfers(g->gself);
        wc_log(diag, WC_LOG_DEBUG,
               "GPU self pairs, since creation: %lld substeps found (%lld by core: %lld too many candidates, %lld "
               "not finite), %lld candidates, %lld bytes read back", io->finds, io->by_core, io->over_room,
               io->non_finite, io->candidates, io->read_bytes);
    }
    return r;
}
