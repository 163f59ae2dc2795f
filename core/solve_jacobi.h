/* Block Jacobi and Chebyshev-accelerated block Jacobi on the projected system (solve_jacobi.c).
 * Private to the solvers. */
#ifndef WEFT_CORE_SOLVE_JACOBI_H
#define WEFT_CORE_SOLVE_JACOBI_H
#include "solve_kernels.h"

/* chebyshev 0: plain block Jacobi; 1: Chebyshev, its rho from the options or the cached estimate
 * (solve_rho.h). On entry dv is the projected initial guess and res->residual0, res->scale are set
 * (solver.c's start of a solve). */
wc_status wcs_solve_jacobi(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                           wc_par* par, wc_solve_result* res, int chebyshev);

#endif
