/* The steps of the modified PCG on the workspace's vectors (r residual, c direction, q = S A c,
 * t preconditioned residual), one parallel region each, as the Lanczos estimate of rho
 * (solve_rho.c) runs them with the block-diagonal preconditioner; PCG's own loop (solve_pcg.c)
 * runs the same arithmetic with an iteration's steps in one region. Private to the solvers. */
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

/* PCG's preconditioner other than D~^{-1} (wcs_pcg_run): s->t = M^{-1} s->r, called between
 * parallel regions. Returns 1 when it also set *rr = r . r and *delta = r . t (summed its own way:
 * the direct solver's, over all 3n values in order); 0: PCG sums them per chunk. */
typedef int (*wcs_pcg_precond_fn)(wc_solver* s, double* rr, double* delta, wc_par* par);

#endif
