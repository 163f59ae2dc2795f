/* The steps of the modified PCG on the workspace's vectors (r residual, c direction, q = S A c,
 * t preconditioned residual): each over a range, which PCG's loop (solve_pcg.c) runs inside its
 * one region an iteration, and as a region of its own, as the Lanczos estimate of rho (solve_rho.c)
 * runs them with the block-diagonal preconditioner. Private to the solvers. */
#ifndef WEFT_CORE_SOLVE_PCG_STEPS_H
#define WEFT_CORE_SOLVE_PCG_STEPS_H
#include "solve_kernels.h"

/* Chunks [c0, c1) (WCS_CHUNK rows each): q = S q, and c . q per chunk into slot `slot` of
 * s->partial (wcs_sum adds a slot up in chunk order). */
void wcs_pcg_filter_dot_chunks(wc_solver* s, const wc_filter* f, const double* c, double* q, int c0, int c1,
                               int slot);
/* Chunks [c0, c1): dv += alpha c (dv may be NULL), r -= alpha q (alpha 0 skips both), r . r per
 * chunk into slot rr_slot; with jacobi also t = D~^{-1} r (s->Dinv) and r . t into delta_slot. */
void wcs_pcg_update_chunks(wc_solver* s, double alpha, double* dv, int jacobi, int c0, int c1, int rr_slot,
                           int delta_slot);
/* Rows [lo, hi): c = S (t + beta c). */
void wcs_pcg_direction_rows(wc_solver* s, const wc_filter* f, double beta, int lo, int hi);

/* The same steps, each a parallel region of its own (slots 0 and 1). */
/* q = S q; returns c . q. */
double wcs_pcg_filter_dot(wc_solver* s, const wc_filter* f, const double* c, double* q, wc_par* par);
/* The update with the block diagonal: *delta = r . t, *rr = r . r. */
void wcs_pcg_update(wc_solver* s, double alpha, double* dv, double* delta, double* rr, wc_par* par);
/* c = S (t + beta c). */
void wcs_pcg_direction(wc_solver* s, const wc_filter* f, double beta, wc_par* par);

/* PCG's preconditioner other than D~^{-1} (wcs_pcg_run): s->t = M^{-1} s->r, called between
 * parallel regions. Returns 1 when it also set *rr = r . r and *delta = r . t (summed its own way:
 * the direct solver's, over all 3n values in order); 0: PCG sums them per chunk. */
typedef int (*wcs_pcg_precond_fn)(wc_solver* s, double* rr, double* delta, wc_par* par);

#endif
