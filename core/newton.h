/* Newton iterations with a backtracking line search on the incremental potential of a substep
 * (backward Euler, or BDF2 through bdf2.h's he, xb and mom).
 *
 * Unknown: the velocity change w = v_{n+1} - v_n; x(w) = xb + he (v_n + w) (BE: xb = x_n, he = h).
 * The potential minimised (its gradient is the step's equations of motion, times -1):
 *   Phi(w) = 1/2 (w - mom)^T M (w - mom)                   inertia (BE: mom = 0)
 *          + U(x(w))                                       springs: sum k/2 (|L| - rest)^2
 *          - f_ext . (x(w) - x_n)                           gravity + air, frozen at the substep start
 *          - he/2 (v_n + w)^T D0 (v_n + w)                  spring damping D0 = dF/dv at x_n, frozen
 *          + 1/2 w^T Fa w - Fb . w                          kinetic friction as assembled (frozen)
 *          + he/2 w^T L w                                   TR-BDF2's implicit air drag (bdf2.h)
 *   grad Phi = M (w - mom) - he (f_springs(x) + D0 v + f_ext) + Fa w - Fb,
 *   Hessian  ~ A = M - he D0 - he^2 K(x) + Fa   (K with the step's compression mode: by default the
 *              compressed springs' negative geometric term is dropped, so A is SPD and every
 *              filtered Newton direction is a descent direction of Phi).
 * Forces without a potential enter frozen: air (drag and wind, explicit in the step anyway) is the
 * constant force f_ext evaluated at (x_n, v_n), i.e. a linear potential; kinetic friction is the
 * implicit damping that wc_contacts_friction put into A and b (Fa, Fb: a quadratic potential with
 * the slide/stick decisions of the first solve kept); spring damping uses the directions of the
 * substep's start. With these frozen, the first Newton step from x(w0) = x_n (w0 = -vstar) is
 * exactly the Baraff-Witkin step, so newton_iterations = 1 without line search is today's step
 * (and takes its code path bit for bit).
 *
 * Refreshed (issue 12), in TR-BDF2's stages: every further iteration re-freezes the non-potential
 * terms at its own iterate w_k before it linearises, so that the gradient is the true equation's
 * residual there and a converged stage solves the implicit equation itself, not one with the
 * start's geometry:
 *  - spring damping: D0 := -d u u^T with u the directions at x(w_k) (the damping force at w_k is
 *    then exact: -d (dv . u) u); the Jacobian stays Baraff-Witkin's (no d/dx of the directions);
 *  - TR-BDF2's implicit air (bdf2.h), when no contact is active in the stage: L := L(x(w_k)) and
 *    f_ext := M g + f_air(x(w_k), v_n + w_k) + L w_k, so -he f_ext + he L w, the potential's air
 *    gradient, is -he (M g + f_air) at w_k. With contacts the air's geometry stays the stage
 *    start's (refreshed, a corner particle sliding on a floor under Newton 2 + PCG 1e-3 kept a
 *    limit cycle in test_trbdf2's drop: the lumped L over-damps a lone vertex's motion, which the
 *    frozen form relied on).
 * Backward Euler and BDF2 keep the frozen damping (and take the air explicitly): refreshed, BE
 * with Newton 2 + line search lost test_api_motion's linear-inertia invariance (a cloth carried by
 * an accelerating object drifted 0.5 % of its size from the one at rest after 51 frames, from
 * 1e-13 the frame before; not understood), and BE is first order anyway. TR-BDF2 keeps it
 * refreshed (the same test with TR-BDF2: 1.6e-13).
 * Phi is thus a new (convex) function from each iteration on: its value is recomputed at w_k
 * after the refresh, and the line search and the flat-stop compare within one iteration. Without
 * damping and air (or with Newton 1) nothing changes. Frozen, a converged TR-BDF2 stage was only
 * first order in time on a whirling damped spring and a tumbling sheet in air
 * (tests/test_trbdf2_converged.c); refreshed, second.
 *
 * Constraints (filter S, z). Every accepted iterate satisfies (I - S) w = (I - S) z exactly as
 * the first solve does: the first iterate takes the prescribed part in full,
 * w~0 = z + S w0 (pins on their targets, contacts at their normal velocity, sticking particles
 * moving with their collider, free particles staying at x_n), and the line search of the first
 * step runs only along its free part d0 = w1 - w~0 = S (w1 - w0), from Phi(w~0) to the
 * Baraff-Witkin solution w1 at alpha = 1. Later iterations solve A d = -grad Phi with the same S
 * and z = 0, so d stays in the free directions.
 *
 * Line search: alpha = 1, 1/2, ... (at most 12 halvings) until Armijo's
 * Phi(w + alpha d) <= Phi(w) + 1e-4 alpha grad.d (the first step: the slope of its quadratic
 * model, A0 w~0 - b0, since grad Phi at w~0 is not evaluated); none found: the iterate stays
 * (first step: w~0) and Newton stops. Without line search alpha = 1.
 * Stops early: the filtered gradient |S grad Phi| at or below the linear solver's tolerance times
 * the first system's |S (b - A z)|; a direction that does not descend; a failed solve (the
 * iterate before it is kept); with line search, a decrease of Phi below 1e-13 of its size.
 * Every iteration re-evaluates the springs at x(w) and reassembles A; the friction recheck is not
 * repeated.
 * Inexact (Eisenstat & Walker 1996; wc_sim_def.newton_forcing, default 1e-2, 0 off): with more
 * than one Newton iteration, the substep's first system need not be solved past the nonlinear
 * error that the next iteration removes (after the first Baraff-Witkin step |S grad Phi| is still
 * 0.85-1.45x the first system's residual on the 32^2 hanging sheet with TR-BDF2). step.c solves it to forcing x its
 * own residual, never past tolerance x the solver's floor; not where a friction pass follows (it
 * reads the contact forces off that solve), nor while mesh-collider feature pairs or self-contact
 * pairs are in the system (loose, a roof's ridge cut through a sheet dropped on it in one frame of
 * tests/test_mesh_features.c's 60), nor with the direct solver. The later iterations'
 * solves are unchanged (tolerance x their own right-hand side): held instead to the first
 * system's absolute target, a cloth resting on a sphere with Newton 2 never settled
 * (tests/test_mesh_collider.c's drop: 0.056 m/s after 150 frames, asleep before).
 * Measured (weft bench accuracy --newton-forcing, README "Inexact Newton"); tests/test_newton_forcing.c.
 * Energy guard (energy_cap < HUGE_VAL; when it judges the substep's energy, the step passes the
 * total energy, kinetic + springs + gravity's potential, of the substep's start after the
 * contacts' position correction plus the gain its judge allows, fail_energy_gain x scale):
 * after newton_iterations, up to NW_ENERGY_EXTRA (4) more iterations are taken while the
 * accepted iterate's total energy is above energy_cap. (A cap at the start's energy itself, no
 * allowance, iterated on in most substeps of the tablecloth at rest for gains of no consequence:
 * 542 solves instead of 346 over its 90 frames.) Where the
 * first linearised step overshoots (a cloth landing: the particles that stop pull their falling
 * neighbours, and the springs' linearisation at x_n stretches them far beyond the solution:
 * +0.56 J in tablecloth's frame 7 against a converged -0.01 J), two iterations may leave the
 * iterate with energy nothing supplied, which the judge rolls back; the exact minimiser of Phi
 * dissipates (for the convex part of U), so iterating on towards it is the cure, and costs one
 * solve per extra iteration instead of a rollback's two halved substeps. Counted in
 * st->energy_iterations (and st->newton_iterations).
 * Reductions are over fixed chunks of particles and springs: the result does not depend
 * on the thread count. Nothing is allocated (state.h's nw_* scratch). */
#ifndef WEFT_CORE_NEWTON_H
#define WEFT_CORE_NEWTON_H
#include "bdf2.h"
#include "step_stats.h"

/* 1 when the def asks for more than one Baraff-Witkin step (iterations > 1 or line search). */
int wc_newton_wanted(const wc_sim_def* d);

/* In the substep's preparation, after the first assembly and before friction: keeps the frozen
 * damping blocks (from s->se) and A's diagonal blocks and b (friction's terms are told apart by
 * them later). */
void wc_newton_capture(wc_state* s);

/* After the first solve (s->dv = its solution w1; s->A, s->b its system, friction included;
 * residual_scale: its residual's scale, wc_solve_result.scale: the larger of |S (b - A z)| and the
 * solver's floor; the iterations stop when the gradient is within the tolerance of it): the line search of the first step and the further iterations.
 * On return s->dv is the accepted w and, when want_r, s->r the constraint residual A dv - b of
 * the last linearisation (wc_contacts_end reads the contact impulses there). Solves are added to
 * st. energy_cap (J): the energy guard's bound (above; HUGE_VAL: no guard). Returns OK unless the
 * first iterate itself is non-finite. */
wc_status wc_newton_iterate(wc_state* s, const wc_integ* ig, wc_solver_type solver, wc_compression compression,
                              double residual_scale, int want_r, double energy_cap, wc_step_stats* st, wc_diag* diag);

/* The incremental potential Phi(w) of the current substep (J), for tests; valid after
 * wc_newton_capture of the substep and before its positions advance. */
double wc_newton_potential(wc_state* s, const wc_integ* ig, const double* w);

#endif
