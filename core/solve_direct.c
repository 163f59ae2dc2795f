/* Direct solve of the projected system with CHOLMOD (Cholesky, SuiteSparse 5.x).
 *
 * K = P = S A S + I - S as a scalar (3n x 3n) symmetric matrix, upper triangle stored (stype 1),
 * compressed columns. Its pattern is FIXED: every entry of every 3x3 block (i, j), i <= j, of the
 * model's pattern (the lower half of diagonal blocks left out), explicit zeros kept, so the
 * symbolic analysis (cholmod_analyze, default orderings) is done once at create and every solve
 * only rewrites K->x in place and refactorises numerically (cholmod_factorize reuses the symbolic
 * factor). Column 3j + b holds, in ascending row order: for each block (j, i) of row j with
 * i < j (ranks r = 0 .. nl-1, nl = diag[j] - row_start[j]) rows 3i .. 3i+2 at offset 3r, then
 * rows 3j .. 3j+b of the diagonal block at offset 3nl. Only the upper blocks of A are read
 * (through pattern.transpose), so A is taken as symmetric.
 *
 * Allocation: create allocates K, the factor, the right-hand side and, through a warm-up
 * factorisation and solve of the identity on the same pattern, the factor's numeric storage and
 * cholmod_solve2's X/Y/E workspaces, which later solves reuse. Inside a solve only
 * cholmod_factorize itself may allocate and free temporary workspace (CHOLMOD's internal
 * permuted copy of K and supernodal update buffers, through SuiteSparse's malloc, which cannot
 * be routed to the wc_allocator without global state).
 *
 * Threads: CHOLMOD 3 (SuiteSparse 5.x) opens OpenMP regions of its own inside the supernodal
 * factorisation, each with a compile-time num_threads(CHOLMOD_OMP_NUM_THREADS) = 4 whatever the
 * machine or the solver's thread count: thousands of small fork-joins per factorisation, which
 * cost several times the factorisation itself on cloth-sized systems (measured in
 * docs/design/solver.md, "Linear solvers"). So every CHOLMOD call runs with the calling thread's
 * max-active-levels at 0 (cholmod_serial_begin: a per-thread setting since OpenMP 5.0, restored
 * after the call, so neither the host's other threads nor Weft's own regions see it). The dense
 * supernodal work still goes through the BLAS, whose threads are the host's to set (the `weft`
 * CLI sets OpenBLAS's to --threads).
 *
 * Each solver owns its cholmod_common (no shared state); CHOLMOD printing is off (print = 0, no
 * error handler) and its status is translated: NOT_POSDEF -> WC_ERROR_FACTORIZATION (dv is
 * left at the projected initial guess), OUT_OF_MEMORY -> WC_ERROR_OUT_OF_MEMORY, anything else
 * failing -> WC_ERROR_FACTORIZATION. */
#include <suitesparse/cholmod.h>
#include <math.h>
#include "solve_direct.h"
#include "solve_pcg.h"
#include "vec3.h"

struct wcs_direct {
    cholmod_common cc;
    int started;            /* cholmod_start succeeded: cholmod_finish is due */
    cholmod_sparse* K;      /* (3n x 3n) upper triangle of P, fixed pattern */
    cholmod_factor* L;      /* symbolic from create, numeric after each factorisation */
    cholmod_dense* B;       /* (3n x 1) right-hand side S (b - A z) */
    cholmod_dense* X;       /* (3n x 1) solution y, allocated by the warm-up solve */
    cholmod_dense* Y;       /* cholmod_solve2 workspaces */
    cholmod_dense* E;
};

/* Begin / end a stretch of CHOLMOD calls whose own OpenMP regions run on the calling thread alone
 * (see the top of the file). */
static int cholmod_serial_begin(void) {
#ifdef _OPENMP
    int saved = omp_get_max_active_levels();
    omp_set_max_active_levels(0);
    return saved;
#else
    return 0;
#endif
}

static void cholmod_serial_end(int saved) {
#ifdef _OPENMP
    omp_set_max_active_levels(saved);
#else
    (void)saved;
#endif
}

static int factorize(wcs_direct* d) {
    int saved = cholmod_serial_begin();
    int ok = cholmod_factorize(d->K, d->L, &d->cc);
    cholmod_serial_end(saved);
    return ok;
}

/* X = A^-1 B through the factor; 0 when CHOLMOD fails. */
static int solve_factor(wcs_direct* d) {
    int saved = cholmod_serial_begin();
    int ok = cholmod_solve2(CHOLMOD_A, d->L, d->B, NULL, &d->X, NULL, &d->Y, &d->E, &d->cc);
    cholmod_serial_end(saved);
    return ok;
}

static wc_status translate(int cholmod_status) {
    if (cholmod_status == CHOLMOD_OUT_OF_MEMORY) return WC_ERROR_OUT_OF_MEMORY;
    return WC_ERROR_FACTORIZATION;
}

/* K->x = upper blocks of P (A NULL: the identity). */
static void fill_values(wc_solver* s, const double* A, const wc_filter* f, wc_par* par) {
    const wc_bsr_pattern* p = &s->m->pattern;
    const int* Kp = (const int*)s->direct->K->p;
    double* Kx = (double*)s->direct->K->x;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(s->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int j = lo; j < hi; ++j) {
            int nl = p->diag[j] - p->row_start[j];
            for (int r = 0; r <= nl; ++r) {
                int k = p->row_start[j] + r, i = p->col[k];
                double P[9];
                if (A) wcs_project_block(f, i, j, A + 9 * (size_t)p->transpose[k], P);
                else m3_identity(P, i == j ? 1.0 : 0.0);
                for (int b = 0; b < 3; ++b) {
                    int base = Kp[3 * j + b] + 3 * r, na = (i == j) ? b + 1 : 3;
                    for (int a = 0; a < na; ++a) Kx[base + a] = P[3 * a + b];
                }
            }
        }
    }
}

wc_status wcs_direct_create(wc_solver* s, wc_diag* diag) {
    const wc_bsr_pattern* p = &s->m->pattern;
    wcs_direct* d = WC_NEW(&s->alloc, wcs_direct, 1);
    if (!d) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "direct solver state");
    s->direct = d;
    if (!cholmod_start(&d->cc)) return wc_fail(diag, WC_ERROR_FACTORIZATION, "cholmod_start failed");
    d->started = 1;
    d->cc.print = 0;
    d->cc.error_handler = NULL;
    d->cc.quick_return_if_not_posdef = 1;
    d->cc.final_ll = 1;   /* simplicial factors LL' too (an LDL' would accept indefinite matrices) */

    const int n = s->n;
    const size_t N = 3 * (size_t)n;
    size_t nnz = 0;
    for (int j = 0; j < n; ++j) nnz += 9 * (size_t)(p->diag[j] - p->row_start[j]) + 6;
    if (nnz > (size_t)0x7fffffff)
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "direct solver: %zu matrix entries exceed int indices", nnz);
    d->K = cholmod_allocate_sparse(N, N, nnz, 1, 1, 1, CHOLMOD_REAL, &d->cc);
    d->B = cholmod_zeros(N, 1, CHOLMOD_REAL, &d->cc);
    if (!d->K || !d->B)
        return wc_fail(diag, translate(d->cc.status), "direct solver: allocating a %zu x %zu matrix (%zu entries)",
                       N, N, nnz);
    int* Kp = (int*)d->K->p;
    int* Ki = (int*)d->K->i;
    Kp[0] = 0;
    for (int j = 0; j < n; ++j) {
        int nl = p->diag[j] - p->row_start[j];
        for (int b = 0; b < 3; ++b) {
            int col = 3 * j + b, base = Kp[col];
            for (int r = 0; r < nl; ++r) {
                int i = p->col[p->row_start[j] + r];
                for (int a = 0; a < 3; ++a) Ki[base + 3 * r + a] = 3 * i + a;
            }
            for (int a = 0; a <= b; ++a) Ki[base + 3 * nl + a] = 3 * j + a;
            Kp[col + 1] = base + 3 * nl + b + 1;
        }
    }

    int saved = cholmod_serial_begin();
    d->L = cholmod_analyze(d->K, &d->cc);
    cholmod_serial_end(saved);
    if (!d->L || d->cc.status < CHOLMOD_OK)
        return wc_fail(diag, translate(d->cc.status), "direct solver: cholmod_analyze failed (status %d)",
                       d->cc.status);
    /* warm-up on the identity: allocates the numeric factor and the solve workspaces now */
    wc_par one;
    wc_par_init(&one, 1);
    fill_values(s, NULL, NULL, &one);
    if (!factorize(d) || d->cc.status != CHOLMOD_OK || !solve_factor(d) || d->cc.status != CHOLMOD_OK)
        return wc_fail(diag, translate(d->cc.status), "direct solver: warm-up factorisation failed (status %d)",
                       d->cc.status);
    wc_log(diag, WC_LOG_DEBUG, "direct solver: %zu x %zu, %zu entries, factor %s, nnz(L) %.0f", N, N, nnz,
           d->L->is_super ? "supernodal" : "simplicial", d->cc.lnz);
    return WC_OK;
}

void wcs_direct_destroy(wc_solver* s) {
    wcs_direct* d = s->direct;
    if (!d) return;
    if (d->started) {
        cholmod_free_dense(&d->E, &d->cc);
        cholmod_free_dense(&d->Y, &d->cc);
        cholmod_free_dense(&d->X, &d->cc);
        cholmod_free_dense(&d->B, &d->cc);
        cholmod_free_factor(&d->L, &d->cc);
        cholmod_free_sparse(&d->K, &d->cc);
        cholmod_finish(&d->cc);
    }
    wc_free(&s->alloc, d);
    s->direct = NULL;
}

/* t = P^{-1} r through the current factor; 0 when CHOLMOD's solve failed. */
static int apply_factor(wc_solver* s, const double* r, double* t) {
    wcs_direct* d = s->direct;
    const size_t N = 3 * (size_t)s->n;
    double* rhs = (double*)d->B->x;
    for (size_t k = 0; k < N; ++k) rhs[k] = r[k];
    if (!solve_factor(d) || d->cc.status < CHOLMOD_OK) return 0;
    const double* y = (const double*)d->X->x;
    for (size_t k = 0; k < N; ++k) t[k] = y[k];
    return 1;
}

/* PCG's preconditioner (solve_pcg_steps.h) with this factor: t = P^{-1} r (t = r where CHOLMOD's
 * solve fails), r . r and r . t summed over the 3n values in order. */
static int precond_direct(wc_solver* s, double* rr, double* delta, wc_par* par) {
    const double* r = s->r;
    double* t = s->t;
    double acc_r = 0.0, acc_d = 0.0;
    (void)par;
    for (int k = 0; k < 3 * s->n; ++k) acc_r += r[k] * r[k];
    if (!apply_factor(s, r, t))
        for (int k = 0; k < 3 * s->n; ++k) t[k] = r[k];
    for (int k = 0; k < 3 * s->n; ++k) acc_d += r[k] * t[k];
    *rr = acc_r;
    *delta = acc_d;
    return 1;
}

wc_status wcs_solve_direct(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                             wc_par* par, wc_solve_result* res) {
    wcs_direct* d = s->direct;
    const size_t N = 3 * (size_t)s->n;
    wc_status st = WC_OK;
    fill_values(s, A, f, par);
    int ok = factorize(d);
    if (!ok || d->cc.status != CHOLMOD_OK || d->L->minor < d->L->n) {
        st = (ok && d->cc.status >= CHOLMOD_OK) ? WC_ERROR_FACTORIZATION : translate(d->cc.status);
    } else if (wc_coupling_active(s->coupling) > 0) {
        /* couplings outside the pattern (coupling.h): PCG on the whole system, preconditioned
           by this factor of its in-pattern part */
        return wcs_pcg_run(s, A, b, f, dv, par, res, precond_direct);
    } else {
        double* rhs = (double*)d->B->x;
        for (size_t k = 0; k < N; ++k) rhs[k] = s->r[k];
        if (!solve_factor(d) || d->cc.status < CHOLMOD_OK) {
            st = translate(d->cc.status);
        } else {
            const double* y = (const double*)d->X->x;
            for (size_t k = 0; k < N; ++k) dv[k] = y[k];
            wcs_project(f, dv, par);   /* dv = z + S y (free particles: z = 0, S = I) */
        }
    }
    res->iterations = 1;
    if (st == WC_OK && !wcs_all_finite(dv, s->n)) st = WC_ERROR_FACTORIZATION;
    if (st != WC_OK && !wcs_all_finite(dv, s->n)) wcs_fallback(f, dv, s->n);
    res->residual = sqrt(wcs_filtered_residual(s, A, b, f, dv, s->q, par)) / res->scale;
    res->converged = st == WC_OK;
    return st;
}
