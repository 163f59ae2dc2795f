/* Linear solvers for the filtered backward-Euler system A dv = b with constraints (S, z):
 * the projected SPD system (S A S + I - S) y = S (b - A z), dv = z + S y.
 *   PCG        modified PCG of Baraff & Witkin section 5.3, filtered block-diagonal (3x3 inverse)
 *              preconditioner, stops at the relative tolerance or the iteration cap.
 *   JACOBI     block Jacobi on the projected system.
 *   CHEBYSHEV  Chebyshev-accelerated block Jacobi (Wang 2015): one matrix sweep per iteration, no
 *              dot products (the residual is measured only every check_every iterations).
 *   DIRECT     CHOLMOD: analysed once per model (fixed pattern), factorised per solve. The exact
 *              reference for the others.
 * Residual reported by every solver: ||S (b - A dv)||_2 / ||S (b - A z)||_2 (0 when the
 * denominator is 0). Iterative solvers watch for divergence (non-finite values, residual above
 * divergence_factor x the initial one) and return WC_ERROR_SOLVER_DIVERGED. */
#ifndef WEFT_CORE_SOLVE_H
#define WEFT_CORE_SOLVE_H
#include "diag.h"
#include "filter.h"
#include "model.h"
#include "par.h"

typedef enum wc_solver_type {
    WC_SOLVER_PCG = 0,
    WC_SOLVER_JACOBI = 1,
    WC_SOLVER_CHEBYSHEV = 2,
    WC_SOLVER_DIRECT = 3,
    WC_SOLVER_COUNT = 4
} wc_solver_type;

/* PCG's preconditioner. */
typedef enum wc_precond_type {
    WC_PRECOND_BLOCK_JACOBI = 0, /* filtered 3x3 block diagonal D~^{-1} */
    WC_PRECOND_AMG = 1,          /* smoothed-aggregation multigrid V-cycle (amg.h) */
    WC_PRECOND_IC0 = 2,          /* block incomplete Cholesky IC(0) of the filtered matrix on its own
                                    pattern (precond_ic.h); core only, not in the plugin's ABI */
    WC_PRECOND_COUNT = 3
} wc_precond_type;

const char* wc_precond_name(wc_precond_type t);        /* "block_jacobi", "amg", "ic0" */
int wc_precond_from_name(const char* name);            /* -1 when unknown */

const char* wc_solver_name(wc_solver_type t);          /* "pcg", "jacobi", "chebyshev", "direct" */
int wc_solver_from_name(const char* name);             /* -1 when unknown */

typedef struct wc_solver_opts {
    wc_solver_type type;        /* PCG */
    wc_precond_type preconditioner; /* PCG's preconditioner (BLOCK_JACOBI) */
    double tolerance;           /* relative residual to stop at (1e-4); 0 runs max_iterations */
    int max_iterations;         /* iteration cap (300) */
    int check_every;            /* Jacobi/Chebyshev: residual measured every this many iterations (10) */
    double chebyshev_rho;       /* spectral radius of the sweep I - gamma D~^-1 P (solve_rho.c); 0 = estimate */
    double chebyshev_gamma;     /* under-relaxation of each Jacobi sweep (0.9) */
    int chebyshev_delay;        /* plain Jacobi iterations before acceleration starts (10) */
    double divergence_factor;   /* residual above this x the initial residual means divergence (1e3) */
} wc_solver_opts;

wc_solver_opts wc_default_solver_opts(void);

typedef struct wc_solve_result {
    wc_status status;         /* OK, SOLVER_DIVERGED, FACTORIZATION (direct: not positive definite) */
    wc_solver_type solver;      /* which solver ran */
    int iterations;             /* 1 for direct */
    int converged;              /* residual <= tolerance (direct: always when status is OK) */
    double residual;            /* relative: ||S (b - A dv)||_2 / scale */
    double residual0;           /* ||S (b - A z)||_2, absolute */
    double scale;               /* what residual and the tolerance are relative to: the larger of
                                   residual0 and the solver's floor (wc_solver_set_residual_floor) */
    double setup_ms;            /* wall time spent building the preconditioner for this solve */
} wc_solve_result;

typedef struct wc_solver wc_solver;   /* workspace: vectors, preconditioner, CHOLMOD analysis */

/* Allocate everything a solve needs for this model (nothing is allocated per solve; m must outlive
 * the solver). The direct solver's symbolic analysis is done here when opts->type is DIRECT or
 * want_direct is set. */
wc_status wc_solver_create(wc_solver** out, const wc_model* m, const wc_solver_opts* opts, int want_direct,
                             const wc_allocator* alloc, wc_diag* diag);
void wc_solver_destroy(wc_solver* s);
/* The multigrid's rotations (amg.h) are taken about these positions (n x 3, metres), read at
 * every solve's setup; the array must outlive the solver (the state's x). NULL (or never set):
 * the model's rest positions. No effect without the multigrid or its rotations. */
void wc_solver_set_positions(wc_solver* s, const double* x);

/* hold 1: the solves that follow have matrices close to the last one's (a substep's Newton
 * solves after its first), so the multigrid may reuse that solve's eigenvalue estimates
 * (amg.h, wc_amg_opts.bound_reuse; a solve that fails on them is redone with fresh ones);
 * hold 0 (the default): every solve estimates afresh. No effect without the multigrid. */
void wc_solver_hold_bounds(wc_solver* s, int hold);
/* carry 1: the solve that follows is a substep's first, whose matrix is near an earlier
 * substep's (the same cloth a step on), so the multigrid may take the estimates of an earlier
 * substep's fresh setup (amg.h, wc_amg_opts.bound_carry; a solve that fails on them is redone
 * with fresh ones); carry 0 (the default): no carrying. The estimates are state: get/set carry
 * them through a snapshot (the solver's history, as the rho cache), invalidate drops them (a
 * rollback, a reset). No effect without the multigrid. */
void wc_solver_carry_bounds(wc_solver* s, int carry);
void wc_solver_invalidate_bounds(wc_solver* s);
struct wc_amg_bounds;
void wc_solver_bounds_get(const wc_solver* s, struct wc_amg_bounds* b);
void wc_solver_bounds_set(wc_solver* s, const struct wc_amg_bounds* b);
/* hold 1: the solves that follow differ from the last one in a few rows (a substep's friction
 * passes), so the multigrid refreshes its finest level only and keeps the coarse levels of its
 * last full setup (amg.h, wc_amg.hold_coarse; a solve that fails on them is redone fresh);
 * hold 0 (the default): full setups. No effect without the multigrid. */
void wc_solver_hold_coarse(wc_solver* s, int hold);

/* The residual's floor (absolute, the units of S (b - A z); >= 0, finite; 0, the default: none):
 * solves stop at tolerance x max(||S (b - A z)||, floor) instead of tolerance x ||S (b - A z)||.
 * A relative tolerance alone asks a cloth at rest (its forces balanced, its right-hand side
 * near zero) to resolve rounding noise; the step sets the floor each substep to the impulse
 * gravity gives the unpinned particles in it, h ||M g||, so a solve always resolves dv to
 * tolerance x (g h) or better. Invalid values are ignored. */
void wc_solver_set_residual_floor(wc_solver* s, double floor);
double wc_solver_residual_floor(const wc_solver* s);
/* The relative tolerance later solves stop at (finite, >= 0; invalid values are ignored), and the
 * one in force: the options' until set (Newton's inexact first solve sets and restores it). */
void wc_solver_set_tolerance(wc_solver* s, double tolerance);
double wc_solver_tolerance(const wc_solver* s);

/* Off-pattern couplings (coupling.h) that every later solve adds to A's product (NULL: none; the
 * list must outlive its use; its diagonal blocks are the caller's, in A). The iterative solvers
 * iterate on A plus them; the direct solver factorises A (their diagonal blocks included) and,
 * when a term is active, runs PCG preconditioned by that factor on the whole system. The
 * multigrid preconditioner carries up to `capacity` active terms through its hierarchy (amg.h,
 * wc_amg_set_coupling; allocated here). */
struct wc_coupling;
wc_status wc_solver_set_coupling(wc_solver* s, const struct wc_coupling* c, int capacity, wc_diag* diag);

/* Solve with solver `type` (its options from create, tolerance etc.). dv: (n x 3), on input the
 * initial guess (projected to z + S dv), on output the solution. Never leaves non-finite values
 * in dv: on divergence dv holds the last finite iterate or z. */
wc_status wc_solve(wc_solver* s, wc_solver_type type, const double* A_val, const double* b, const wc_filter* f,
                     double* dv, wc_par* par, wc_solve_result* res);

/* Estimate the spectral radius of the filtered, under-relaxed (chebyshev_gamma) block-Jacobi
 * iteration matrix for this system, as Chebyshev uses it: 20 Lanczos steps (as many matrix
 * sweeps as power iterations, much closer), extrapolated upwards and capped at 0.9995 (see
 * solve_rho.c); used by Chebyshev when chebyshev_rho is 0; cached until
 * wc_solver_invalidate_rho. */
double wc_solver_estimate_rho(wc_solver* s, const double* A_val, const wc_filter* f, wc_par* par);
void wc_solver_invalidate_rho(wc_solver* s);
/* The rho above from the coefficients of k (<= 20) CG steps on the projected, block-Jacobi
 * preconditioned system (alpha_j, beta_j as PCG computes them): the Lanczos tridiagonal's extreme
 * Ritz values, lambda_min extrapolated when k = 20, capped at 0.9995. Shared with the GPU
 * backend, which runs the CG steps in its own passes. */
double wc_rho_from_lanczos(const double* alpha, const double* beta, int k, double gamma);
/* Chebyshev's weight for iteration k (solve_jacobi.c): 1 before `delay`, then
 * 2 / (2 - rho^2) and 4 / (4 - rho^2 omega_{k-1}) (omega: the previous weight). */
double wc_chebyshev_omega(int k, int delay, double rho, double omega);
/* The cached estimate, for snapshots of a state (it changes later solves): returns 1 and sets
 * *rho when one is cached, else 0. wc_solver_set_rho_cache puts one back (valid 0: none). */
int wc_solver_rho_cache(const wc_solver* s, double* rho);
void wc_solver_set_rho_cache(wc_solver* s, int valid, double rho);

#endif
