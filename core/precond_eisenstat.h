/* D-ILU preconditioned CG with Eisenstat's trick (Eisenstat 1981) on the projected matrix
 * P = S A S + I - S (solve_kernels.h): PCG's IC(0) path's alternative below 800 particles
 * (wc_solver_opts.ic_eisenstat). Private to the solvers.
 *
 * Split P = L + D_P + L^T (L strictly lower on the model's block pattern). The preconditioner is
 *     M = (D~ + L) D~^{-1} (D~ + L^T)
 * whose off-diagonal blocks are P's own: only the block diagonal D~ is computed. D-ILU (mode 0):
 * D~_i = P_ii - sum_{k<i} P_ik D~_k^{-1} P_ki, so diag(M) = diag(P); symmetric block Gauss-Seidel
 * (mode 1): D~ = D_P. With D~_i = C_i C_i^T (3x3 Cholesky) the system is scaled once per setup,
 *     L~ = C^{-1} L C^{-T},   K~ = C^{-1} D_P C^{-T} - 2 I,
 * and CG runs on  P^ = (I + L~)^{-1} (C^{-1} P C^{-T}) (I + L~^T)^{-1}  (M's symmetric split),
 * whose product is Eisenstat's: t = (I + L~^T)^{-1} c, P^ c = t + (I + L~)^{-1} (c + K~ t): two
 * unit triangular sweeps and a block-diagonal product, in place of IC(0)'s product of P plus its
 * two sweeps with D^{-1}. The iterate is kept as y = sum alpha_k t_k, so the correction is
 * e = C^{-T} y (no sweep at the end).
 *
 * The filter: P's blocks are S_i A_ij S_j (plus I - S_i on the diagonal), so D~, L~ and K~ keep
 * range(S) and null(S) apart; the right-hand side S (b - A dv) lies in range(S), so every iterate
 * does too (to rounding: the correction is projected), and CG on P^ is Baraff & Witkin's filtered
 * PCG with S M^{-1} S in exact arithmetic.
 *
 * Stopping: CG watches ||r^|| (r^ = (I + L~)^{-1} C^{-1} r, r = S (b - A dv)); when it falls below
 * tolerance x scale x ||r^_0|| / ||r_0||, the true residual is computed and the solve stops when
 * that meets the tolerance, else the target on ||r^|| is lowered by their ratio and CG goes on.
 * Serial (the sweeps are), no allocation after create; the same bits at any thread count. */
#ifndef WEFT_CORE_PRECOND_EISENSTAT_H
#define WEFT_CORE_PRECOND_EISENSTAT_H
#include "alloc.h"
#include "bsr.h"
#include "filter.h"
#include "status.h"

struct wc_solver;
struct wc_solve_result;
struct wc_par;

typedef struct wcs_eis {
    const wc_bsr_pattern* p;    /* the model's pattern; must outlive this */
    double* F;                  /* (n_blocks x 9) L~ (lower), L~^T (upper), K~_i on the diagonal */
    double* Dt;                 /* (n_rows x 9) D~ */
    double* Ci;                 /* (n_rows x 9) C_i^{-1}, lower triangular */
    double* y;                  /* (n_rows x 3) sum alpha t */
    double* dv0;                /* (n_rows x 3) the guess the correction is added to */
    int mode;                   /* 0: D-ILU, 1: symmetric block Gauss-Seidel (D~ = D_P) */
    int gs;                     /* the last setup fell back to D~ = D_P (a D-ILU pivot not SPD) */
    long setups, fallbacks, checks;
} wcs_eis;

wc_status wcs_eis_create(wcs_eis** out, const wc_bsr_pattern* p, const wc_allocator* a);
void wcs_eis_destroy(wcs_eis* e, const wc_allocator* a);
/* Scale P (A: the pattern's values) for this->mode: 1 on success, 0 when no D~ is SPD (mode 0
 * falls back to D_P first); the caller then uses another preconditioner. */
int wcs_eis_setup(wcs_eis* e, const double* A, const wc_filter* f);
/* o = P^ x (o, t: n x 3; t gets (I + L~^T)^{-1} x); returns x . o. Exposed for the tests. */
double wcs_eis_product(const wcs_eis* e, const double* x, double* t, double* o);
/* The same with scalar rows (wcs_eis_product runs AVX2's where the CPU has it: the same to rounding). */
double wcs_eis_product_scalar(const wcs_eis* e, const double* x, double* t, double* o);
/* o = M^{-1} r through the scaled factors: C^{-T} (I + L~^T)^{-1} (I + L~)^{-1} C^{-1} r, w scratch
 * (n x 3). Exposed for the tests (against M built densely from P). */
void wcs_eis_apply(const wcs_eis* e, const double* r, double* w, double* o);
/* CG on P^ from dv (the setup done): dv gets the solution, res its iterations and residual as
 * wcs_pcg_run's. WC_ERROR_SOLVER_DIVERGED on a non-finite value or c . P^ c <= 0 (dv then holds
 * the guess it started from). */
wc_status wcs_eis_run(struct wc_solver* s, wcs_eis* e, const double* A, const double* b, const wc_filter* f,
                      double* dv, struct wc_par* par, struct wc_solve_result* res);

#endif
