/* The spectral radius Chebyshev accelerates with (solve_rho.c): Lanczos through PCG's steps.
 * Private to the solvers; wc_rho_from_lanczos (solve.h) is its public part. */
#ifndef WEFT_CORE_SOLVE_RHO_H
#define WEFT_CORE_SOLVE_RHO_H
#include "solve_kernels.h"

#define WCS_RHO_ITERATIONS 20   /* Lanczos steps of the estimate */

/* rho of I - gamma D~^{-1} P for this system; s->Dinv must be built. Uses s->r, c, q, t as
 * scratch. */
double wcs_estimate_rho(wc_solver* s, const double* A, const wc_filter* f, wc_par* par);

#endif
