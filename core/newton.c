/* Newton iterations with a backtracking line search on a substep's incremental potential
 * (newton.h): how they work and why.
 *
 * Unknown: the velocity change w = v_{n+1} - v_n; x(w) = xb + he (v_n + w) (BE: xb = x_n, he = h).
 * The potential minimised (its gradient is the step's equations of motion, times -1):
 *   Phi(w) = 1/2 (w - mom)^T M (w - mom)                   inertia (BE: mom = 0)
 *          + U(x(w))                                       springs: sum k/2 (|L| - rest)^2
 *          - f_ext . (x(w) - x_n)                           gravity + air, frozen at the substep start
 *          - he/2 (v_n + w)^T D0 (v_n + w)                  spring damping D0 = dF/dv at x_n, frozen
 *          + 1/2 w^T Fa w - Fb . w                          kinetic friction as assembled (frozen)
 *          + he/2 w^T L w                                   TR-BDF2's implicit air drag (bdf2.h)
 *          + sum k/2 min(g(x(w)), 0)^2                      penalty pairs (penalty_pairs.h)
 *   grad Phi = M (w - mom) - he (f_springs(x) + D0 v + f_ext) + Fa w - Fb (+ the pairs' forces),
 *   Hessian  ~ A = M - he D0 - he^2 K(x) + Fa   (K with the step's compression mode: by default the
 *              compressed springs' negative geometric term is dropped, so A is SPD and every
 *              filtered Newton direction is a descent direction of Phi).
 * Forces without a potential enter frozen: air (drag and wind, explicit in the step anyway) is the
 * constant force f_ext evaluated at (x_n, v_n), i.e. a linear potential; kinetic friction is the
 * implicit damping that wc_contacts_friction put into A and b (Fa, Fb: a quadratic potential with
 * the slide/stick decisions of the first solve kept); spring damping uses the directions of the
 * substep's start. With these frozen, the first Newton step from x(w0) = x_n (w0 = -vstar) is
 * exactly the Baraff-Witkin step. The penalty pairs enter exactly (their potential and its
 * linearisation at x(w), active where g(x(w)) < 0), which is why step.c does not recheck them
 * when Newton iterates.
 *
 * Refreshed, in TR-BDF2's stages: every further iteration re-freezes the non-potential terms at
 * its own iterate w_k before it linearises, so that the gradient is the true equation's residual
 * there and a converged stage solves the implicit equation itself, not one with the start's
 * geometry (second order in time where the frozen form was first order):
 *  - spring damping: D0 := -d u u^T with u the directions at x(w_k) (the damping force at w_k is
 *    then exact: -d (dv . u) u); the Jacobian stays Baraff-Witkin's (no d/dx of the directions);
 *  - TR-BDF2's implicit air (bdf2.h), when no contact is active in the stage: L := L(x(w_k)) and
 *    f_ext := M g + f_air(x(w_k), v_n + w_k) + L w_k, so -he f_ext + he L w, the potential's air
 *    gradient, is -he (M g + f_air) at w_k. With contacts the air's geometry stays the stage
 *    start's: the lumped L over-damps a lone vertex sliding on a floor, which the frozen form
 *    relies on.
 * Stage 1 (TR-BDF2's trapezoidal stage, wc_sim_def.stage1_tolerance, default 2e-2; with more
 * than one Newton iteration and no contact or penalty pair in the stage): the damping's
 * directions are refreshed once, at the first iterate w_1 (the Baraff-Witkin solution), and held
 * from then on, and the stage iterates past newton_iterations (at most NW_STAGE1_EXTRA more)
 * until |S grad Phi| is at most stage1_tolerance x the first system's residual. Why: refreshed
 * at every iterate, the directions make each iteration a step of a fixed-point map the
 * Jacobian does not describe (no d/dx of u in -d (dv . u) u), and in the trapezoidal stage,
 * where stiffly damped relative velocities reverse instead of decaying, that map does not
 * contract: on the swinging 64 x 64 sheet the gradient stayed at 0.1-1.7 of the first residual
 * through nine iterations, the line search cut the steps, and whichever unconverged iterate the
 * count stopped at set the swing's energy (docs/bench/trbdf2_spread.md). Held after w_1, Phi is
 * one convex function and the stage converges in 2-4 more solves; the directions are within
 * O(h^2) of the stage end's, so the stage stays second order (tests/test_trbdf2_converged.c).
 * Moved once (Newton >= WC_NEWTON_STAGE1_MOVE_FROM): converged with w_1's directions, the
 * stage refreshes them at that iterate w* (kept in nw_wh), holds them there and iterates on, at
 * most NW_STAGE1_MOVED more solves, to the same test; when these do not reach it, the stage
 * ends on w*. Why: the fixed point with w_1's directions is biased by them (the swinging sheet
 * with Newton 6, which converges it furthest, ended 1.29 % from the reference, Newton 3 0.66 %);
 * moved to w*, Newton 6 0.43-0.61 %, Newton 3 0.41 %, at 1.7-3.8 more solves a stage: +14 %
 * solves for Newton 6, but +45 % for Newton 3 and +52 % for Newton 2 (no gain there), most of
 * them discarded: so not below 4.
 * Moving them at every convergence does not converge (the same map as refreshing each
 * iterate), and the moved stage's unconverged iterate is worse than w* (kept, Newton 3 rolled
 * back in 6 frames and ended 3.4 % off): hence once, with w* to fall back on.
 * Measured: docs/bench/trbdf2_converged.md, trbdf2_held_bias.md. Stage 2 (BDF2) keeps the
 * refresh at every iterate.
 * Backward Euler and BDF2 keep the frozen damping (and take the air explicitly): refreshed, BE
 * with Newton 2 + line search lost test_api_motion's linear-inertia invariance, and BE is first
 * order anyway. Phi is thus a new (convex) function from each iteration on: its value is
 * recomputed at w_k after the refresh, and the line search and the flat-stop compare within one
 * iteration. Without damping and air (or with Newton 1) nothing changes.
 *
 * Constraints (filter S, z). Every accepted iterate satisfies (I - S) w = (I - S) z exactly as
 * the first solve does: the first iterate takes the prescribed part in full,
 * w~0 = z + S w0 (pins on their targets, contacts at their normal velocity, sticking particles
 * moving with their collider, free particles staying at x_n), and the line search of the first
 * step runs only along its free part d0 = w1 - w~0 = S (w1 - w0), from Phi(w~0) to the
 * Baraff-Witkin solution w1 at alpha = 1. Later iterations solve A d = -grad Phi with the same S
 * and z = 0, so d stays in the free directions.
 *
 * Line search: alpha = 1, 1/2, ... (at most NW_BACKTRACKS halvings) until Armijo's
 * Phi(w + alpha d) <= Phi(w) + NW_ARMIJO alpha grad.d (the first step: the slope of its quadratic
 * model, A0 w~0 - b0, since grad Phi at w~0 is not evaluated); none found: the iterate stays
 * (first step: w~0) and Newton stops. Without line search alpha = 1.
 * Stops early: the filtered gradient |S grad Phi| at or below the linear solver's tolerance times
 * the first system's |S (b - A z)| (wc_sim_def.newton_tolerance, when larger, in its place: see
 * below); a direction that does not descend; a failed solve (the iterate before it is kept); with
 * line search, a decrease of Phi below NW_FLAT of its size.
 * The test is a ratio of two residuals of the same equations (scale-free: units, mass and time
 * step cancel), and it bounds what the next iteration would do: A >= M (the dropped compressed
 * terms keep -he D0 - he^2 K + Fa positive semidefinite), so the next Newton correction d obeys
 * |d|_M <= |M^-1/2 S grad Phi| and shrinks with the gradient. At the solver's tolerance it asks
 * no more of the nonlinear equations than the linear solves give; a larger newton_tolerance eta
 * accepts eta of the first system's residual left over, as the inexact first solve (forcing) does
 * for its linear error. Measured (docs/bench/newton_forcing.md "Newton's stopping test"): after
 * the first step the ratio is 0.55-1.1 on the hanging sheet (the springs' nonlinearity, not the
 * forcing: the same with forcing 0), 0.01-0.3 on the suit; so no eta below 1/2 skips a sheet's
 * second solve, and the option is off by default. The energy guard's iterations keep the
 * solver's tolerance (they run only while the iterate holds energy nothing supplied).
 * The friction recheck is not repeated.
 *
 * Friction (the stick/slide set the iterations see): step.c's first recheck after the first
 * solve frees the sticking contacts the solved cloth overloads and solves again; with Newton
 * iterations to follow, a later recheck's releases (the few contacts their freed neighbours now
 * overload) get no solve of their own. The filter, Fa and Fb already have them sliding: the
 * first step's line search runs from w~0 with them free towards the last solve's dv (which held
 * them), and the next iteration's solve, on the system with them sliding, moves them. The
 * measurements: docs/bench/friction_passes.md.
 *
 * Inexact (Eisenstat & Walker 1996; wc_sim_def.newton_forcing, default 1e-2, 0 off): with more
 * than one Newton iteration, the substep's first system need not be solved past the nonlinear
 * error that the next iteration removes (after the first Baraff-Witkin step |S grad Phi| is still
 * of the order of the first system's residual). step.c solves it to forcing x its own residual,
 * never past tolerance x the solver's floor; not where a friction pass follows (it reads the
 * contact forces off that solve), nor while penalty pairs are in the system (after a dance
 * frame it is 7-13x as far from a 1e-5 reference as the 1e-4 solves are; test_mesh_features'
 * ridge cuts the sheet under some forcings, as under some tolerances without it:
 * docs/bench/newton_forcing.md, "The loose first solve with penalty pairs"), nor with the
 * direct solver. The later iterations' solves are unchanged (tolerance x their own right-hand
 * side): held instead to the first system's absolute target, a cloth resting on a sphere with
 * Newton 2 never settled.
 *
 * Energy guard (energy_cap < HUGE_VAL; when it judges the substep's energy, the step passes the
 * total energy, kinetic + springs + gravity's potential, of the substep's start after the
 * contacts' position correction plus the gain its judge allows, fail_energy_gain x scale):
 * after newton_iterations, up to NW_ENERGY_EXTRA more iterations are taken while the accepted
 * iterate's total energy is above energy_cap. (A cap at the start's energy itself, no allowance,
 * iterates on for gains of no consequence in cloth at rest.) Where the first linearised step
 * overshoots (a cloth landing: the particles that stop pull their falling neighbours, and the
 * springs' linearisation at x_n stretches them far beyond the solution), two iterations may leave
 * the iterate with energy nothing supplied, which the judge rolls back; the exact minimiser of
 * Phi dissipates (for the convex part of U), so iterating on towards it is the cure, and costs one
 * solve per extra iteration instead of a rollback's two halved substeps. Counted in
 * st->energy_iterations (and st->newton_iterations).
 *
 * Reductions are over fixed chunks of particles and springs: the result does not depend on the
 * thread count. The measurements behind these choices: docs/design/solver.md, "Newton iterations
 * and line search" and "Integrators"; the penalty pairs': docs/design/contacts.md. */
#include "newton.h"
#include <math.h>
#include <string.h>
#include "assemble.h"
#include "clock.h"
#include "forces.h"
#include "mesh_pairs.h"
#include "penalty_pairs.h"
#include "self_pairs.h"
#include "vec3.h"

#define NW_CHUNK 256          /* particles or springs per reduction chunk */
#define NW_ARMIJO 1e-4        /* sufficient-decrease constant */
#define NW_BACKTRACKS 12      /* halvings of the step at most */
#define NW_FLAT 1e-13         /* a decrease below this x |Phi| ends the iterations */
#define NW_ENERGY_EXTRA 4     /* iterations past newton_iterations at most while the iterate gains energy */
#define NW_STAGE1_EXTRA WC_NEWTON_STAGE1_EXTRA   /* TR-BDF2's stage 1 ("Stage 1"; newton.h) */
#define NW_STAGE1_MOVED WC_NEWTON_STAGE1_MOVED   /* its solves after the directions moved at most */

int wc_newton_wanted(const wc_sim_def* d) { return d->newton_iterations > 1 || d->line_search; }

void wc_newton_capture(wc_state* s) {
    const wc_model* m = s->model;
    const int* diag = m->pattern.diag;
    for (int k = 0; k < m->n_springs; ++k) memcpy(s->nw_kv0 + 9 * (size_t)k, s->se[k].kv, 9 * sizeof(double));
    for (int i = 0; i < m->n_particles; ++i) memcpy(s->nw_fa + 9 * (size_t)i, s->A + 9 * (size_t)diag[i], 9 * sizeof(double));
    memcpy(s->nw_fb, s->b, 3 * (size_t)m->n_particles * sizeof(double));
}

/* Sum of per-chunk partials in chunk order (independent of the thread count). */
static double chunk_total(const double* partial, int chunks) {
    double sum = 0.0;
    for (int c = 0; c < chunks; ++c) sum += partial[c];
    return sum;
}

static int n_chunks(int items) { return (items + NW_CHUNK - 1) / NW_CHUNK; }

/* a . b over n3 = 3 n entries, by particle chunks. */
static double dot3(wc_state* s, const double* a, const double* b) {
    int n = s->model->n_particles, chunks = n_chunks(n);
    double* part = s->nw_partial;
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < n ? (c + 1) * NW_CHUNK : n;
            double acc = 0.0;
            for (int k = 3 * c * NW_CHUNK; k < 3 * hi; ++k) acc += a[k] * b[k];
            part[c] = acc;
        }
    }
    return chunk_total(part, chunks);
}

/* |S g|^2 by particle chunks. */
static double filtered_norm2(wc_state* s, const double* g) {
    int n = s->model->n_particles, chunks = n_chunks(n);
    double* part = s->nw_partial;
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < n ? (c + 1) * NW_CHUNK : n;
            double acc = 0.0;
            for (int i = c * NW_CHUNK; i < hi; ++i) {
                double o[3];
                wc_filter_apply(&s->filter, i, g + 3 * i, o);
                acc += v3_dot(o, o);
            }
            part[c] = acc;
        }
    }
    return chunk_total(part, chunks);
}

/* x = xb + he (v_n + w), v = v_n + w into nw_x, nw_v. */
static void positions(wc_state* s, const wc_integ* ig, const double* w) {
    int n3 = 3 * s->model->n_particles;
    const double *xb = ig->xb, *v = s->v;
    double *x = s->nw_x, *vv = s->nw_v, he = ig->he;
    WC_PAR_REGION(&s->par)
    {
        int lo, hi;
        wc_par_range(n3, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int k = lo; k < hi; ++k) {
            vv[k] = v[k] + w[k];
            x[k] = xb[k] + he * vv[k];
        }
    }
}

static int have_friction(const wc_state* s) { return s->n_all > 0 && s->contacts.active > 0; }

/* 1 when x(w), v(w) (in nw_x, nw_v) are the substep's start as prepare evaluated the springs
 * there: the same positions bit for bit and every velocity 0 (the first iterate w~0 of a cloth
 * whose pins and contacts hold still: x_n + he (v_n - v_n)). There each spring's potential term
 * is its energy from prepare: its damping term -he/2 dv^T D0 dv is a +-0 (dv = +-0, D0 finite),
 * and E - (+-0) is E, so the chunks' sums are the loop's bits. */
static int at_start(const wc_state* s) {
    const wc_model* m = s->model;
    int n3 = 3 * m->n_particles;
    if (!s->nw_spring_e_valid || s->judge_fresh) return 0;
    if (memcmp(&s->nw_spring_e_seam, &s->seam_scale, sizeof(double)) != 0) return 0;
    for (int k = 0; k < n3; ++k)
        if (s->nw_v[k] != 0.0) return 0;
    return memcmp(s->nw_x, s->nw_spring_e_x, (size_t)n3 * sizeof(double)) == 0;
}

/* Phi(w); start: the springs' energies from prepare may stand in for the spring loop (at_start) */
static double potential(wc_state* s, const wc_integ* ig, const double* w, int start) {
    const wc_model* m = s->model;
    int n = m->n_particles, fric = have_friction(s);
    positions(s, ig, w);
    const double *x = s->nw_x, *vv = s->nw_v, *x0 = s->x, *mom = ig->mom, *fext = s->f_ext;
    const double *fa = s->nw_fa, *fb = s->nw_fb, *kv0 = s->nw_kv0;
    const double* air = ig->air_implicit ? s->air_lump : NULL;
    double he = ig->he;
    int pc = n_chunks(n), sc = n_chunks(m->n_springs);
    double* part = s->nw_partial;
    WC_PAR_REGION(&s->par)
    {
        int c0, c1;
        wc_par_range(pc, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int hi = (c + 1) * NW_CHUNK < n ? (c + 1) * NW_CHUNK : n;
            double acc = 0.0;
            for (int i = c * NW_CHUNK; i < hi; ++i) {
                const double* wi = w + 3 * i;
                double dw[3], dx[3];
                v3_copy(dw, wi);
                if (mom) v3_sub(dw, dw, mom + 3 * i);
                v3_sub(dx, x + 3 * i, x0 + 3 * i);
                acc += 0.5 * m->mass[i] * v3_dot(dw, dw) - v3_dot(fext + 3 * i, dx);
                if (fric) {
                    double Fw[3];
                    m3_mulv(Fw, fa + 9 * (size_t)i, wi);
                    acc += 0.5 * v3_dot(wi, Fw) - v3_dot(fb + 3 * i, wi);
                }
                if (air) {
                    double Lw[3];
                    m3_mulv(Lw, air + 9 * (size_t)i, wi);
                    acc += 0.5 * he * v3_dot(wi, Lw);
                }
            }
            part[c] = acc;
        }
    }
    double phi = chunk_total(part, pc);
    if (start && at_start(s)) {
        const double* e = s->nw_spring_e;
        for (int c = 0; c < sc; ++c) {
            int hi = (c + 1) * NW_CHUNK < m->n_springs ? (c + 1) * NW_CHUNK : m->n_springs;
            double acc = 0.0;
            for (int k = c * NW_CHUNK; k < hi; ++k) acc += e[k];
            part[c] = acc;
        }
        ++s->nw_spring_e_used;
    } else {
        WC_PAR_REGION(&s->par)
        {
            int c0, c1;
            wc_par_range(sc, wc_par_tid(), wc_par_nt(), &c0, &c1);
            for (int c = c0; c < c1; ++c) {
                int hi = (c + 1) * NW_CHUNK < m->n_springs ? (c + 1) * NW_CHUNK : m->n_springs;
                part[c] = wc_newton_spring_terms(m, x, vv, kv0, he, s->seam_scale, c * NW_CHUNK, hi, 1);
            }
        }
    }
    phi += chunk_total(part, sc);
    /* the penalty pairs (penalty_pairs.h: the mesh colliders' feature pairs, the self-contact
       pairs): k/2 min(g(x(w)), 0)^2, serial */
    if (s->n_mesh > 0 && s->pairs && s->pairs->list.n > 0) phi += wc_penalty_pairs_energy(&s->pairs->list, x);
    if (s->self_pairs && s->self_pairs->list.n > 0) phi += wc_penalty_pairs_energy(&s->self_pairs->list, x);
    return phi;
}

double wc_newton_potential(wc_state* s, const wc_integ* ig, const double* w) { return potential(s, ig, w, 0); }

/* TR-BDF2's implicit air at the iterate ("Refreshed" above): air_lump = L(x(w)) and
 * f_ext = M g + f_air(x(w), v_n + w) + L(x(w)) w, so that -he f_ext + he L w, the potential's
 * air gradient, is -he (M g + f_air) at w itself. Expects positions(s, ig, w) done. */
static void refresh_air(wc_state* s, const double* w) {
    const wc_model* m = s->model;
    wc_air_lumped(m, s->nw_x, &s->def.air, &s->par, s->air_lump);
    wc_eval_external(m, s->nw_x, s->nw_v, s->def.gravity, &s->def.air, &s->par, s->tri_scratch, s->f_ext);
    for (int i = 0; i < m->n_particles; ++i) {
        double Lw[3];
        m3_mulv(Lw, s->air_lump + 9 * (size_t)i, w + 3 * i);
        v3_add(s->f_ext + 3 * i, s->f_ext + 3 * i, Lw);
    }
}

/* The Newton system at w: springs at x(w); in TR-BDF2's stages their damping blocks refreshed to
 * x(w)'s directions (nw_kv0 := them: the potential's damping term from now on) and the air to
 * x(w) (refresh_air), otherwise the frozen damping; A (friction's Fa on the diagonal) and
 * g = -grad Phi(w) into nw_g. */
static void newton_system(wc_state* s, const wc_integ* ig, const double* w, wc_compression compression,
                          int refresh_damping, wc_step_stats* st) {
    const wc_model* m = s->model;
    double t0 = wc_now_ms();
    positions(s, ig, w);
    wc_eval_springs_at(m, s->nw_x, s->nw_zero, compression, s->seam_scale, &s->par, s->se);
    const double* vv = s->nw_v;
    double* kv0 = s->nw_kv0;
    const int refresh = ig->stage != 0 && refresh_damping;   /* TR-BDF2's stages ("Refreshed", "Stage 1" above) */
    wc_spring_eval* se = s->se;
    WC_PAR_REGION(&s->par)
    {
        int lo, hi;
        wc_par_range(m->n_springs, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int k = lo; k < hi; ++k) {
            const wc_spring* sp = &m->springs[k];
            double dv[3];
            if (refresh) memcpy(kv0 + 9 * (size_t)k, se[k].kv, 9 * sizeof(double));   /* -d u u^T at x(w) */
            else memcpy(se[k].kv, kv0 + 9 * (size_t)k, 9 * sizeof(double));
            v3_sub(dv, vv + 3 * sp->a, vv + 3 * sp->b);
            m3_mulv_add(se[k].f, se[k].kv, dv);
        }
    }
    if (ig->air_implicit && !have_friction(s)) refresh_air(s, w);   /* contacts: frozen ("Refreshed") */
    double t1 = wc_now_ms();
    st->ms.forces += t1 - t0;
    wc_assemble(m, se, s->f_ext, s->nw_zero, ig->he, &s->par, s->A, s->nw_g, NULL);
    int fric = have_friction(s);
    const int* diag = m->pattern.diag;
    const double *mom = ig->mom, *fa = s->nw_fa, *fb = s->nw_fb;
    const double* air = ig->air_implicit ? s->air_lump : NULL;
    const double he = ig->he;
    double *g = s->nw_g, *A = s->A;
    WC_PAR_REGION(&s->par)
    {
        int lo, hi;
        wc_par_range(m->n_particles, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* gi = g + 3 * i;
            const double* wi = w + 3 * i;
            for (int c = 0; c < 3; ++c) gi[c] -= m->mass[i] * (wi[c] - (mom ? mom[3 * i + c] : 0.0));
            if (fric) {
                double Fw[3];
                m3_mulv(Fw, fa + 9 * (size_t)i, wi);
                for (int c = 0; c < 3; ++c) gi[c] += fb[3 * i + c] - Fw[c];
                m3_axpy(A + 9 * (size_t)diag[i], 1.0, fa + 9 * (size_t)i);
            }
            if (air) {
                double Lw[3];
                m3_mulv(Lw, air + 9 * (size_t)i, wi);
                for (int c = 0; c < 3; ++c) gi[c] -= he * Lw[c];
                m3_axpy(A + 9 * (size_t)diag[i], he, air + 9 * (size_t)i);
            }
        }
    }
    /* the penalty pairs touching at x(w): their force and stiffness (serial: rows shared) */
    if (s->n_mesh > 0 && s->pairs && s->pairs->list.n > 0)
        wc_penalty_pairs_newton(&s->pairs->list, m, s->nw_x, he, A, g);
    if (s->self_pairs && s->self_pairs->list.n > 0)
        wc_penalty_pairs_newton(&s->self_pairs->list, m, s->nw_x, he, A, g);
    st->ms.assemble += wc_now_ms() - t1;
}

/* Friction's terms: what wc_contacts_friction (and its rechecks) added to A's diagonal blocks and
 * to b since wc_newton_capture (zero without contacts). */
static void friction_terms(wc_state* s) {
    const wc_model* m = s->model;
    if (!have_friction(s)) return;
    const int* diag = m->pattern.diag;
    for (int i = 0; i < m->n_particles; ++i) {
        double* fa = s->nw_fa + 9 * (size_t)i;
        const double* Ai = s->A + 9 * (size_t)diag[i];
        for (int q = 0; q < 9; ++q) fa[q] = Ai[q] - fa[q];
    }
    for (int k = 0; k < 3 * m->n_particles; ++k) s->nw_fb[k] = s->b[k] - s->nw_fb[k];
}

void wc_newton_debug_system(wc_state* s, const wc_integ* ig, const double* w, wc_compression compression) {
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    friction_terms(s);
    newton_system(s, ig, w, compression, 1, &st);
}

/* Total energy (J) of the iterate w: kinetic of v_n + w, springs and gravity's potential at x(w)
 * (the step's energy judge's measure, energy_memo.h: where the substep then ends on exactly
 * x(w), v(w), its judge takes this measure over). Leaves x(w), v(w) in nw_x, nw_v. */
static double iterate_energy(wc_state* s, const wc_integ* ig, const double* w) {
    positions(s, ig, w);
    return wc_state_judge_energy(s, s->nw_x, s->nw_v, NULL);
}

static void trace(wc_state* s, int it, double phi, const double* w) {
    if (s->newton_trace) s->newton_trace(s->newton_trace_user, s, it, phi, w);
}

enum { R_FIRST, R_STEP, R_GRADIENT };   /* which linearisation the constraint residual comes from */

wc_status wc_newton_iterate(wc_state* s, const wc_integ* ig, wc_solver_type solver, wc_compression compression,
                              double residual_scale, int want_r, double energy_cap, wc_step_stats* st, wc_diag* diag) {
    const wc_model* m = s->model;
    int n = m->n_particles, n3 = 3 * n;
    int ls = s->def.line_search != 0;
    double* w = s->nw_w;
    double* d = s->nw_d;
    double t0 = wc_now_ms();
    friction_terms(s);
    memcpy(w, s->dv, (size_t)n3 * sizeof(double));
    int rmode = R_FIRST;
    double alpha = 1.0, phi = 0.0;

    if (ls) {
        /* the first step, from w~0 = z + S w0 (w0 = -vstar: x(w0) = x_n) along its free part */
        for (int i = 0; i < n; ++i) {
            double w0[3], o[3];
            v3_scale(w0, ig->vstar + 3 * i, -1.0);
            wc_filter_apply(&s->filter, i, w0, o);
            for (int c = 0; c < 3; ++c) {
                double wt = s->filter.z[3 * i + c] + o[c];
                d[3 * i + c] = s->dv[3 * i + c] - wt;
                w[3 * i + c] = wt;
            }
        }
        double phi0 = potential(s, ig, w, 1);
        if (!isfinite(phi0)) return wc_fail(diag, WC_ERROR_NONFINITE, "newton: non-finite potential at the first iterate");
        trace(s, 0, phi0, w);
        wc_state_mul_system(s, w, s->nw_g);
        for (int k = 0; k < n3; ++k) s->nw_g[k] -= s->b[k];
        double slope = dot3(s, s->nw_g, d);
        double phi1 = 0.0;
        int ok = 0;
        for (int b = 0; b <= NW_BACKTRACKS && !ok; ++b, alpha *= 0.5) {
            if (b == 0) memcpy(s->nw_g, s->dv, (size_t)n3 * sizeof(double)); /* alpha = 1: w1 itself */
            else
                for (int k = 0; k < n3; ++k) s->nw_g[k] = w[k] + alpha * d[k];
            phi1 = wc_newton_potential(s, ig, s->nw_g);
            ok = phi1 <= phi0 + NW_ARMIJO * alpha * (slope < 0.0 ? slope : 0.0);
            if (!ok) ++st->backtracks;
        }
        if (ok) {
            alpha *= 2.0;   /* undo the loop's last halving */
            memcpy(w, s->nw_g, (size_t)n3 * sizeof(double));
            phi = phi1;
        } else {
            alpha = 0.0;
            phi = phi0;
        }
        trace(s, 1, phi, w);
    }

    s->nw_spring_e_valid = 0;   /* the substep's start energies: the first potential's only */
    double gref = residual_scale, tol = s->def.solver.tolerance > 1e-12 ? s->def.solver.tolerance : 1e-12;
    double ntol = s->def.newton_tolerance > tol ? s->def.newton_tolerance : tol;   /* "Stops early" */
    int stop = ls && alpha == 0.0;
    wc_filter fz = s->filter;
    fz.z = s->nw_zero;
    double system_ms = 0.0;
    const int guard = energy_cap < HUGE_VAL;
    /* TR-BDF2's trapezoidal stage iterates on to its own tolerance ("Stage 1" above) */
    const double s1_tol = s->def.stage1_tolerance;
    const int pairs =
        (s->n_mesh > 0 && s->pairs && s->pairs->list.n > 0) || (s->self_pairs && s->self_pairs->list.n > 0);
    const int stage1 = ig->stage == 1 && s->def.newton_iterations > 1 && s1_tol > 0.0 && !have_friction(s) && !pairs;
    const int extra = guard && NW_ENERGY_EXTRA > (stage1 ? NW_STAGE1_EXTRA : 0) ? NW_ENERGY_EXTRA
                      : stage1                                                   ? NW_STAGE1_EXTRA
                                                                                 : 0;
    int converged = 0;   /* the loop ended on a gradient at or below the stopping test */
    /* stage 1's held directions move once, to the iterate converged with w_1's ("Stage 1") */
    int rehold = stage1 && s->def.newton_iterations >= WC_NEWTON_STAGE1_MOVE_FROM, moved = 0;
    int end = s->def.newton_iterations + extra;
    double glast = 0.0;   /* the last gradient tested, over gref */
    for (int it = 1; it < end && !stop; ++it) {
        const int past = it >= s->def.newton_iterations;
        int hot = 0;   /* past the count: the energy guard wants this iteration */
        if (past) {
            /* past the configured count only while the iterate holds more energy than the
               substep started with ("Energy guard" above), or stage 1 is not converged */
            hot = guard && it < s->def.newton_iterations + NW_ENERGY_EXTRA && iterate_energy(s, ig, w) > energy_cap;
            if (!hot && !stage1) break;
            if (hot) ++st->energy_iterations;
        }
        double ts = wc_now_ms();
        newton_system(s, ig, w, compression, !stage1 || it == 1, st);
        system_ms += wc_now_ms() - ts;
        /* the potential was refreshed at w (damping directions, air): the line search compares
           against its value there */
        if (ls && ig->stage != 0) phi = wc_newton_potential(s, ig, w);
        rmode = R_GRADIENT;
        double gn = sqrt(filtered_norm2(s, s->nw_g));
        if (rehold && it > 1 && !(gn > s1_tol * gref)) {
            /* converged with w_1's directions: hold them at this iterate instead (kept in nw_wh),
               and go on, at most NW_STAGE1_MOVED solves, while the gradient is above the test
               (a stop below it, a flat potential, keeps its iterate) */
            rehold = 0;
            moved = 1;
            memcpy(s->nw_wh, w, (size_t)n3 * sizeof(double));
            if (end < it + NW_STAGE1_MOVED) end = it + NW_STAGE1_MOVED;
            ts = wc_now_ms();
            newton_system(s, ig, w, compression, 1, st);
            system_ms += wc_now_ms() - ts;
            if (ls) phi = wc_newton_potential(s, ig, w);
            gn = sqrt(filtered_norm2(s, s->nw_g));
        }
        glast = gn / gref;
        if (!(gn > (past ? tol : ntol) * gref)) {
            converged = 1;
            break;
        }
        if (past && !hot && !(gn > s1_tol * gref)) {   /* stage 1 converged */
            converged = 1;
            break;
        }
        if (past && !hot) ++st->stage1_iterations;
        memset(d, 0, (size_t)n3 * sizeof(double));
        wc_solve_result res;
        wc_status status = wc_solve(s->solver, solver, s->A, s->nw_g, &fz, d, &s->par, &res);
        wc_step_stats_add_solve(st, solver, &res);
        if (status != WC_OK) break;
        double slope = -dot3(s, s->nw_g, d);   /* grad Phi . d */
        if (!(slope < 0.0)) break;
        alpha = 1.0;
        if (ls) {
            int ok = 0;
            double phi1 = 0.0;
            for (int b = 0; b <= NW_BACKTRACKS && !ok; ++b) {
                if (b > 0) {
                    alpha *= 0.5;
                    ++st->backtracks;
                }
                for (int k = 0; k < n3; ++k) s->dv[k] = w[k] + alpha * d[k];   /* the trial (s->dv: free here) */
                phi1 = wc_newton_potential(s, ig, s->dv);
                ok = phi1 <= phi + NW_ARMIJO * alpha * slope;
            }
            if (!ok) break;
            double drop = phi - phi1;
            memcpy(w, s->dv, (size_t)n3 * sizeof(double));
            phi = phi1;
            trace(s, it + 1, phi, w);
            stop = drop <= NW_FLAT * fabs(phi);
        } else {
            for (int k = 0; k < n3; ++k) w[k] += d[k];
        }
        ++st->newton_iterations;
        rmode = R_STEP;
    }
    if (moved && !converged && glast > s1_tol) {   /* the moved directions did not converge: back to nw_wh */
        memcpy(w, s->nw_wh, (size_t)n3 * sizeof(double));
        converged = 1;
        if (want_r) {   /* its gradient, for the constraint residual */
            newton_system(s, ig, w, compression, 1, st);
            rmode = R_GRADIENT;
        }
    }
    if (stage1 && !converged) ++st->stage1_unconverged;
    /* the accepted iterate, and the constraint residual of its linearisation */
    memcpy(s->dv, w, (size_t)n3 * sizeof(double));
    if (want_r) {
        if (rmode == R_FIRST) {
            wc_state_mul_system(s, w, s->r);
            for (int k = 0; k < n3; ++k) s->r[k] -= s->b[k];
        } else if (rmode == R_GRADIENT) {
            for (int k = 0; k < n3; ++k) s->r[k] = -s->nw_g[k];
        } else {
            for (int k = 0; k < n3; ++k) s->nw_x[k] = alpha * d[k];
            wc_state_mul_system(s, s->nw_x, s->r);
            for (int k = 0; k < n3; ++k) s->r[k] -= s->nw_g[k];
        }
    }
    st->ms.solve += wc_now_ms() - t0 - system_ms;   /* solves and line searches (the systems: forces, assemble) */
    return WC_OK;
}
