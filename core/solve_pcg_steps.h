/* The steps of the modified PCG (solve_pcg.c) on the workspace's vectors (r residual, c direction,
 * q = S A c, t preconditioned residual), shared with the Lanczos estimate of rho (solve_rho.c),
 * which runs the same steps with the block-diagonal preconditioner. Private to the solvers. */
#ifndef WEFT_CORE_SOLVE_PCG_STEPS_H
#define WEFT_CORE_SOLVE_PCG_STEPS_H
#include "solve_kernels.h"

/* q = S q; returns c . q. */
double wcs_pcg_filter_dot(wc_solver* s, const wc_filter* f, const double* c, double* q, wc_par* par);
/* dv += alpha c (dv may be NULL), r -= alpha q (alpha 0 skips both), then t = D~^{-1} r with the
 * block-diagonal preconditioner s->Dinv; *delta = r . t, *rr = r . r. */
void wcs_pcg_update(wc_solver* s, double alpha, double* dv, double* delta, double* rr, wc_par* par);
/* c = S (t + beta c). */
void wcs_pcg_direction(wc_solver* s, const wc_filter* f, double beta, wc_par* par);

/* An update step with some preconditioner in place of D~^{-1} (wcs_pcg_update's contract). */
typedef void (*wcs_pcg_update_fn)(wc_solver* s, double alpha, double* dv, double* delta, double* rr, wc_par* par);

#endif
