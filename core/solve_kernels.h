/* Private to the linear solvers (solver.c and the solve_*.c it dispatches to): the wc_solver
 * workspace and the kernels every solver shares. Not part of the core's contract.
 *
 * Notation: P = S A S + I - S is the projected (filtered) matrix, D~ its block diagonal
 * (D~_i = S_i A_ii S_i + I - S_i), z the prescribed velocity change. Every iterate dv lies in the
 * affine space z + range(S); the projected residual of dv is S (b - A dv).
 *
 * Reductions (dot products, norms) are summed over fixed chunks of WCS_CHUNK particles, each chunk
 * sequentially, and the chunk sums in chunk order: the result does not depend on the thread count
 * (wc_par_dot is deterministic only for a given count), so a solve is bit-identical on any number
 * of threads. */
#ifndef WEFT_CORE_SOLVE_KERNELS_H
#define WEFT_CORE_SOLVE_KERNELS_H
#include "amg.h"
#include "coupling.h"
#include "solve.h"

#define WCS_CHUNK 256           /* particles per reduction chunk */

typedef struct wcs_direct wcs_direct;   /* CHOLMOD state, solve_direct.c */

struct wc_solver {
    const wc_model* m;          /* pattern source; must outlive the solver */
    wc_allocator alloc;
    wc_solver_opts opts;
    int n;                      /* particles */
    int n_chunks;               /* ceil(n / WCS_CHUNK) */
    double* partial;            /* (3 n_chunks) per-chunk partial sums, three reductions at a time */
    double* Dinv;               /* (n x 9) D~_i^{-1}, rebuilt by every iterative solve */
    double* r;                  /* (n x 3) residual S (b - A dv) */
    double* c;                  /* (n x 3) PCG search direction (also of the rho estimate) */
    double* q;                  /* (n x 3) PCG S A c; scratch */
    double* t;                  /* (n x 3) PCG preconditioned residual; Jacobi/Chebyshev second iterate */
    double rho;                 /* cached estimate of wc_solver_estimate_rho */
    int rho_valid;
    wcs_direct* direct;         /* NULL unless the direct solver was analysed at create */
    wc_amg* amg;                /* NULL unless opts.preconditioner is AMG */
    struct wcs_ic* ic;          /* NULL unless opts.preconditioner is IC0 (precond_ic.h) */
    double residual_floor;      /* wc_solver_set_residual_floor (0: none) */
    const wc_coupling* coupling; /* wc_solver_set_coupling (NULL: none) */
    wc_coupling_rows* coupling_rows; /* the couplings' row index, room for set_coupling's capacity */
    int coupling_rows_ok;       /* the index holds this solve's couplings (wc_solve builds it at its
                                   start and drops it at its end): their product runs on the threads */
};

/* Rows [lo, hi) of chunk c. */
static inline void wcs_chunk_rows(const wc_solver* s, int c, int* lo, int* hi) {
    *lo = c * WCS_CHUNK;
    *hi = *lo + WCS_CHUNK < s->n ? *lo + WCS_CHUNK : s->n;
}
/* Sum of the chunk partials partial[slot * n_chunks + c] in chunk order. */
double wcs_sum(const wc_solver* s, int slot);

/* out = S_i Aij S_j, plus (I - S_i) when i == j: block (i, j) of P. */
void wcs_project_block(const wc_filter* f, int i, int j, const double* Aij, double* out);
/* s->Dinv = D~^{-1} per particle (identity where D~_i is singular or not finite). */
void wcs_build_precond(wc_solver* s, const double* A, const wc_filter* f, wc_par* par);
/* y = A x and y = b - A x with the couplings' off-diagonal blocks (coupling.h) added: the
 * operator every solver iterates on. */
void wcs_mul(wc_solver* s, const double* A, const double* x, double* y, wc_par* par);
void wcs_residual(wc_solver* s, const double* A, const double* b, const double* x, double* y, wc_par* par);
/* out = S (b - A x); returns ||out||^2. out must not alias x. */
double wcs_filtered_residual(wc_solver* s, const double* A, const double* b, const wc_filter* f, const double* x,
                             double* out, wc_par* par);
/* dv_i = z_i + S_i dv_i for every constrained particle (free ones unchanged). */
void wcs_project(const wc_filter* f, double* dv, wc_par* par);
/* 1 when all 3n values are finite. */
int wcs_all_finite(const double* v, int n);
/* dv = z (components of z that are not finite become 0). */
void wcs_fallback(const wc_filter* f, double* dv, int n);

#endif
