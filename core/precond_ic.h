/* Block incomplete Cholesky, IC(0), of the projected matrix P = S A S + I - S (solve_kernels.h) on
 * the model's own 3x3 block pattern (bsr.h): PCG's WC_PRECOND_IC0 (solve.h). Private to the
 * solvers.
 *
 * The factor is the block LDL^T form  M = (D + L) D^{-1} (D + L^T),  L strictly lower with the
 * lower triangle's pattern of P, D block diagonal, computed row by row (up-looking, the IKJ
 * variant of ILU(0) made symmetric): row i's upper blocks start as P's and each lower neighbour
 * k < i (ascending) subtracts (U_ki^T D_k^{-1}) U_kj from every block (i, j), j >= i, that row k
 * also holds (fill outside the pattern dropped); D_i is the diagonal block that remains. One pass
 * over the blocks, no allocation: the factor lives in an array of the pattern's size, allocated
 * once per model. The 3x3 products (L_ik D_k^{-1} and the updates) run in AVX registers, a block
 * row per register, with separate products and sums in the scalar code's order: the same bits
 * (docs/bench/precond_by_size.md, "Where the small cloths' frame goes").
 *
 * Breakdown (Manteuffel 1980): a pivot D_i that is not symmetric positive definite (a 3x3
 * Cholesky pivot <= 1e-12 x P's own diagonal, or not finite) restarts the factorisation of
 * P + alpha diag(P), alpha = 1e-3, then x 4 each retry (8 at most); when every shift fails the
 * factor drops its off-diagonal blocks and is the filtered block diagonal of block Jacobi
 * (identity where D~_i is singular). PCG needs M symmetric positive definite, and every D_i
 * kept is.
 *
 * Applied: t = M^{-1} r, a forward sweep (D + L) w = r and a backward one
 * (I + D^{-1} L^T) t = w, in place in t: each off-diagonal block read once per sweep, one 3x3
 * product per row per sweep. Where the CPU has AVX2 and FMA the row stays in registers: its sum of
 * blocks as bsr_rows.c's kernel (FMA per lane), the three lane sums at once, r - sum, and D_i^{-1}
 * from its padded columns (DinvT) in three broadcasts with m3_mulv's products and sums, no FMA
 * (docs/bench/precond_by_size.md). Sequential (a triangular solve): the iterations around it run on
 * the threads, the sweeps on one. PCG filters the result into its direction (c = S (t + beta c)),
 * so the preconditioner it applies is S M^{-1} S, symmetric and positive definite on range(S). */
#ifndef WEFT_CORE_PRECOND_IC_H
#define WEFT_CORE_PRECOND_IC_H
#include "alloc.h"
#include "bsr.h"
#include "filter.h"
#include "status.h"

#define WCS_IC_MAX_SHIFTS 8

typedef struct wcs_ic {
    const wc_bsr_pattern* p;    /* the model's pattern; must outlive the factor */
    double* F;                  /* (n_blocks x 9) block (i, j): U_ij = (D + L^T)_ij for j >= i (the
                                   diagonal block is D_i), L_ij = U_ji^T for j < i */
    double* Dinv;               /* (n_rows x 9) D_i^{-1} */
    double* DinvT;              /* (n_rows x 12) D_i^{-1} by columns, each padded to 4 (lane 3 zero) */
    double shift;               /* alpha of the last setup (0: none needed) */
    int jacobi;                 /* the last setup fell back to the block diagonal */
    long setups;                /* setups since creation */
    long shifted;               /* setups that needed a shift */
    long fallbacks;             /* setups that fell back to the block diagonal */
} wcs_ic;

wc_status wcs_ic_create(wcs_ic** out, const wc_bsr_pattern* p, const wc_allocator* a);
void wcs_ic_destroy(wcs_ic* ic, const wc_allocator* a);
/* Factor P = S A S + I - S (A: the pattern's values, n_blocks x 9), with the breakdown rule above.
 * Returns the shift used (0: none; negative: the block-diagonal fallback). */
double wcs_ic_setup(wcs_ic* ic, const double* A, const wc_filter* f);
/* One factorisation of P + alpha diag(P): 1 when every pivot is SPD (the factor is complete), 0 at
 * the first pivot that is not (the factor is then partial). Exposed for the tests. */
int wcs_ic_factor(wcs_ic* ic, const double* A, const wc_filter* f, double alpha);
/* The same with the scalar 3x3 products (wcs_ic_factor uses AVX's where the CPU has it, the same
 * operations in the same order: the tests check both give the same bits). */
int wcs_ic_factor_scalar(wcs_ic* ic, const double* A, const wc_filter* f, double alpha);
/* t = M^{-1} r (t may alias r): the rows in AVX2 registers where the CPU has AVX2 and FMA, else
 * scalar. */
void wcs_ic_apply(const wcs_ic* ic, const double* r, double* t);
/* The same with scalar row sums (exposed for the tests: both paths give the same t to rounding). */
void wcs_ic_apply_scalar(const wcs_ic* ic, const double* r, double* t);

#endif
