/* Newton iterations with a backtracking line search on the incremental potential Phi(w) of a
 * substep (backward Euler, or BDF2 and TR-BDF2's stages through bdf2.h's he, xb and mom), w the
 * velocity change v_{n+1} - v_n. The first iteration, from x_n, is exactly the Baraff-Witkin
 * step: newton_iterations = 1 without line search is the plain step, bit for bit. Each further
 * iteration re-evaluates the springs at x(w), reassembles A and solves A d = -grad Phi under the
 * substep's constraints, so every accepted iterate keeps (I - S) w = (I - S) z. The potential,
 * the line search and the stopping rules are set out in newton.c, and so are these three:
 *   Refreshed: in TR-BDF2's stages every further iteration re-freezes the spring damping and the
 *     implicit air at its own iterate, so a converged stage solves the implicit equation itself.
 *   Inexact (wc_sim_def.newton_forcing): with more than one iteration, step.c solves the
 *     substep's first system only to forcing x its own residual (not before a friction pass,
 *     with penalty pairs in the system, or with the direct solver; the pairs' case measured in
 *     docs/bench/newton_forcing.md, "The loose first solve with penalty pairs").
 *   Stage 1 (wc_sim_def.stage1_tolerance): TR-BDF2's trapezoidal stage holds its damping's
 *     directions from the first iterate on and iterates past newton_iterations to that tolerance;
 *     from WC_NEWTON_STAGE1_MOVE_FROM iterations on, converged, it moves them once to that
 *     iterate and iterates on (at most WC_NEWTON_STAGE1_MOVED solves) to the same tolerance, or
 *     ends on that iterate.
 *   Energy guard (energy_cap): up to NW_ENERGY_EXTRA more iterations while the accepted
 *     iterate's total energy is above the bound the step's energy judge allows.
 * Deterministic on any thread count; nothing is allocated (state.h's nw_* scratch). */
#ifndef WEFT_CORE_NEWTON_H
#define WEFT_CORE_NEWTON_H
#include "bdf2.h"
#include "step_stats.h"

#define WC_NEWTON_STAGE1_EXTRA 6   /* TR-BDF2's stage 1: iterations past newton_iterations at most (the GPU's too) */
#define WC_NEWTON_STAGE1_MOVED 4   /* TR-BDF2's stage 1: solves after its held directions moved at most (the GPU's too) */
#define WC_NEWTON_STAGE1_MOVE_FROM 4   /* ... moved only from this many Newton iterations on (the GPU's too) */

/* 1 when the def asks for more than one Baraff-Witkin step (iterations > 1 or line search). */
int wc_newton_wanted(const wc_sim_def* d);

/* In the substep's preparation, after the first assembly and before friction: keeps the frozen
 * damping blocks (from s->se) and A's diagonal blocks and b (friction's terms are told apart by
 * them later). */
void wc_newton_capture(wc_state* s);

/* After the first solve: the line search of the first step and the further iterations. On entry
 * s->dv is the first solve's solution w1 and s->A, s->b its system, friction included;
 * residual_scale is its residual's scale (wc_solve_result.scale: the larger of |S (b - A z)| and
 * the solver's floor; the iterations stop when the gradient is within the tolerance of it). On
 * return s->dv is the accepted w and, when want_r, s->r the constraint residual A dv - b of the
 * last linearisation (wc_contacts_end reads the contact impulses there). Solves are added to st.
 * energy_cap (J): the energy guard's bound (HUGE_VAL: no guard). Returns OK unless the first
 * iterate itself is non-finite. */
wc_status wc_newton_iterate(wc_state* s, const wc_integ* ig, wc_solver_type solver, wc_compression compression,
                              double residual_scale, int want_r, double energy_cap, wc_step_stats* st, wc_diag* diag);

/* The incremental potential Phi(w) of the current substep (J), for tests; valid after
 * wc_newton_capture of the substep and before its positions advance. */
double wc_newton_potential(wc_state* s, const wc_integ* ig, const double* w);

/* The potential's spring terms over springs [lo, hi) (newton_springs.c): the sum in spring order
 * of k_t w/2 dl^2 - he/2 dv^T kv0_k dv, dl the extension at x, dv = vv_a - vv_b, kv0 the frozen
 * damping blocks (n_springs + 1 blocks: one of padding). vec: 1 = the AVX loop where the CPU has
 * it, 0 = the scalar loop; the same bits either way (tests/test_newton_springs.c). */
double wc_newton_spring_terms(const wc_model* m, const double* x, const double* vv, const double* kv0, double he,
                              double seam_scale, int lo, int hi, int vec);

/* For tests: friction's frozen terms (into s->nw_fa, s->nw_fb: what the friction pass added to A's
 * diagonal blocks and to b since wc_newton_capture, as wc_newton_iterate's start takes them; once
 * per prepared substep) and Newton's system at the iterate w: A into s->A, -grad Phi(w) into
 * s->nw_g, x(w) into s->nw_x. */
void wc_newton_debug_system(wc_state* s, const wc_integ* ig, const double* w, wc_compression compression);

#endif
