/* The modified PCG of Baraff & Witkin on the projected system (solve_pcg.c). Private to the
 * solvers. */
#ifndef WEFT_CORE_SOLVE_PCG_H
#define WEFT_CORE_SOLVE_PCG_H
#include "solve_pcg_steps.h"

/* PCG with the options' preconditioner (block Jacobi, the multigrid or IC(0)), built here and timed in
 * res->setup_ms. On entry dv is the projected initial guess and res->residual0, res->scale are
 * set (solver.c's start of a solve). */
wc_status wcs_solve_pcg(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                        wc_par* par, wc_solve_result* res);
/* The PCG iterations alone, preconditioned by `precond` (built by the caller; NULL: the block
 * diagonal s->Dinv): how the direct solver runs PCG with its factor. Same entry conditions. */
wc_status wcs_pcg_run(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv, wc_par* par,
                      wc_solve_result* res, wcs_pcg_precond_fn precond);

#endif
