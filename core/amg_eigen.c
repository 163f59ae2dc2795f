/* The largest eigenvalue of D^-1 A on one multigrid level (amg.h), the Chebyshev smoother's and
 * the prolongator smoothing's bound; rebuilt by every setup (but those that reuse the last one's,
 * wc_amg_opts.bound_reuse) from a fixed start vector (wc_amg_start_vector), so an estimate depends
 * on its system only (snapshots restore bit-exactly).
 * Two estimators, both lower bounds of lambda_max (a Rayleigh quotient, a Ritz value), times
 * WC_AMG_SAFETY:
 *   - Lanczos (wc_amg_opts.lanczos = 1, the default): k steps of the symmetric Lanczos process
 *     for the pencil (A, D) in the D inner product (D^-1 A is self-adjoint there), then the
 *     largest eigenvalue of the k x k tridiagonal (Sturm bisection). Its error falls like
 *     exp(-4 k sqrt(gap)) where the power method's falls like (lambda_2 / lambda_1)^(2k).
 *   - power iterations (lanczos = 0): the Rayleigh quotient (w . A w) / (w . D w) of
 *     w <- D^-1 A w.
 * Sums per chunk of WC_AMG_CHUNK rows, added in chunk order (the same on any thread count). */
#include <math.h>
#include <string.h>
#include "amg.h"
#include "bsr_rows.h"
#include "vec3.h"

/* t = A w on the chunk's rows; returns (w . A w) and adds (w . D w) into *den, unless den is NULL
 * (D: the block diagonal, 3x3 or the pair's 6x6); next = D^-1 t on the chunk, t in L->t (chunks
 * hold whole pairs). */
static double chunk_apply(const wc_amg_level* L, int lo, int hi, int pair_blocks, const double* w, double* next,
                          double* den) {
    double num = 0.0, dsum = 0.0;
    const double* xw = L->cross && L->cross->n_terms > 0 ? L->cross->y : NULL; /* apply_all's X w */
    wc_bsr_rows(L->row_start, L->col, L->val, lo, hi, xw, 1.0, w, L->t);
    for (int i = lo; i < hi; ++i) {
        const double* t = L->t + 3 * i;
        num += v3_dot(w + 3 * i, t);
        if (L->group == 1) m3_mulv(next + 3 * i, L->Dinv + 9 * i, t);
        if (!den) continue;
        double dw[3] = {0, 0, 0};
        wc_amg_d_mulv_add(L, i, pair_blocks, w, dw);
        dsum += v3_dot(w + 3 * i, dw);
    }
    if (L->group == 2)
        for (int i = lo; i < hi; ++i) wc_amg_dinv(L, i, L->t, next + 3 * i);
    if (den) *den += dsum;
    return num;
}

static void chunk_bounds(const wc_amg_level* L, int c, int* lo, int* hi) {
    *lo = c * WC_AMG_CHUNK;
    *hi = *lo + WC_AMG_CHUNK < L->n ? *lo + WC_AMG_CHUNK : L->n;
}

/* One thread's share of apply_all (inside a region): the couplings' terms scaled by w (a barrier
 * after), then its chunks' rows of next = D^-1 A w and their sums of w . A w (partial[3c]) and
 * w . D w (partial[3c + 1], when `den`). */
static void apply_part(wc_amg_level* L, int pair_blocks, const double* w, double* next, int den) {
    int n_chunks = (L->n + WC_AMG_CHUNK - 1) / WC_AMG_CHUNK;
    const wc_amg_cross* X = L->cross && L->cross->n_terms > 0 ? L->cross : NULL;
    if (X && wc_amg_cross_as_terms(X)) { /* the couplings' terms scaled by w (amg_cross.c), all before their rows */
        int q0, q1;
        wc_par_range(X->n_terms, wc_par_tid(), wc_par_nt(), &q0, &q1);
        wc_amg_cross_scale(X, 1.0, w, q0, q1);
        WC_PAR_BARRIER();
    }
    int c0, c1;
    wc_par_range(n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
    for (int c = c0; c < c1; ++c) {
        int lo, hi;
        chunk_bounds(L, c, &lo, &hi);
        if (X) { /* the chunk's rows of X w */
            memset(X->y + 3 * (size_t)lo, 0, sizeof(double) * 3 * (size_t)(hi - lo));
            wc_amg_cross_rows_add(X, 1.0, w, X->y, L->n, lo, hi);
        }
        double d = 0.0;
        L->partial[3 * c] = chunk_apply(L, lo, hi, pair_blocks, w, next, den ? &d : NULL);
        L->partial[3 * c + 1] = d;
    }
}

/* Sum of the chunks' partial[3c + slot] in chunk order. */
static double chunk_sum(const wc_amg_level* L, int slot) {
    int n_chunks = (L->n + WC_AMG_CHUNK - 1) / WC_AMG_CHUNK;
    double s = 0.0;
    for (int c = 0; c < n_chunks; ++c) s += L->partial[3 * c + slot];
    return s;
}

/* next = D^-1 A w over all rows, chunks in parallel; *num = w . A w and *den = w . D w (not
 * computed when den is NULL), summed in chunk order (the same on any thread count). */
static void apply_all(wc_amg_level* L, int pair_blocks, const double* w, double* next, wc_par* par, double* num,
                      double* den) {
    WC_PAR_REGION(par) apply_part(L, pair_blocks, w, next, den != NULL);
    *num = chunk_sum(L, 0);
    if (den) *den = chunk_sum(L, 1);
}

static double power_iterations(wc_amg_level* L, int iterations, int pair_blocks, wc_par* par) {
    wc_amg_start_vector(L->ev, L->n);
    double lambda = 0.0;
    for (int it = 0; it < iterations; ++it) {
        const double* w = L->ev;
        double* next = L->x;
        double num, den;
        apply_all(L, pair_blocks, w, next, par, &num, &den);
        double q = den > 0 ? num / den : 0.0;
        if (!(q > 0) || !isfinite(q)) break;
        lambda = q;
        /* the next iterate, scaled to stay near unit size (w's scale is arbitrary) */
        double scale = 1.0 / (lambda * sqrt(den / (3.0 * L->n)));
        if (!isfinite(scale) || !(scale > 0)) scale = 1.0;
        for (int k = 0; k < 3 * L->n; ++k) L->ev[k] = next[k] * scale;
    }
    return lambda;
}

/* Number of eigenvalues below s of the symmetric tridiagonal (alpha, beta) of size k (Sturm). */
static int sturm_count(const double* alpha, const double* beta, int k, double s) {
    int count = 0;
    double q = 1.0;
    for (int j = 0; j < k; ++j) {
        double b2 = j > 0 ? beta[j - 1] * beta[j - 1] : 0.0;
        q = alpha[j] - s - (j > 0 ? b2 / q : 0.0);
        if (q == 0.0) q = -1e-300 * (fabs(alpha[j]) + 1.0);
        if (q < 0) ++count;
    }
    return count;
}

/* Largest eigenvalue of the k x k symmetric tridiagonal, by bisection inside Gershgorin's bounds. */
static double tridiagonal_max(const double* alpha, const double* beta, int k) {
    double lo = INFINITY, hi = -INFINITY;
    for (int j = 0; j < k; ++j) {
        double r = (j > 0 ? fabs(beta[j - 1]) : 0.0) + (j + 1 < k ? fabs(beta[j]) : 0.0);
        lo = fmin(lo, alpha[j] - r);
        hi = fmax(hi, alpha[j] + r);
    }
    for (int it = 0; it < 100 && hi - lo > 1e-12 * fmax(fabs(hi), fabs(lo)); ++it) {
        double mid = 0.5 * (lo + hi);
        if (sturm_count(alpha, beta, k, mid) < k) lo = mid; /* an eigenvalue at or above mid */
        else hi = mid;
    }
    return lo;
}

/* Lanczos in the D inner product: v (L->ev) D-normalised, w = D^-1 A v (L->x), alpha = v . A v,
 * w -= alpha v + beta_prev v_prev (v_prev: L->ev_scratch), beta = |w|_D, v_prev <- v,
 * v <- w / beta. All steps in one parallel region: every thread adds the chunks' sums itself (in
 * chunk order, so all take the same branches) and updates the vectors on its chunks' rows, with
 * barriers where a phase reads other threads' rows or sums. */
typedef struct lanczos_run {
    wc_amg_level* L;
    int steps, pair_blocks;
    int k;                              /* Ritz values found (thread 0's) */
    double alpha[WC_AMG_MAX_LANCZOS], beta[WC_AMG_MAX_LANCZOS];
} lanczos_run;

static void lanczos_part(lanczos_run* run) {
    wc_amg_level* L = run->L;
    const int pair_blocks = run->pair_blocks, tid = wc_par_tid();
    int n_chunks = (L->n + WC_AMG_CHUNK - 1) / WC_AMG_CHUNK, c0, c1;
    wc_par_range(n_chunks, tid, wc_par_nt(), &c0, &c1);
    const int r0 = c0 * WC_AMG_CHUNK, r1 = c1 * WC_AMG_CHUNK < L->n ? c1 * WC_AMG_CHUNK : L->n; /* my rows */
    double alpha[WC_AMG_MAX_LANCZOS], beta[WC_AMG_MAX_LANCZOS];
    double *v = L->ev, *w = L->x, *vp = L->ev_scratch;
    if (r1 > r0) {
        wc_amg_start_vector_rows(v, r0, r1);
        memset(vp + 3 * (size_t)r0, 0, sizeof(double) * 3 * (size_t)(r1 - r0));
    }
    double beta_prev = 0.0;
    int k = 0;
    for (int j = 0; j < run->steps; ++j) {
        WC_PAR_BARRIER(); /* v complete; the last sums read */
        /* w . D w only for the start vector: the later v are D-normalised */
        apply_part(L, pair_blocks, v, w, j == 0);
        WC_PAR_BARRIER();
        double num = chunk_sum(L, 0);
        if (j == 0) { /* the start vector was not normalised: scale v, w and the sums */
            double den = chunk_sum(L, 1);
            if (!(den > 0) || !isfinite(den)) {
                k = 0;
                break;
            }
            double scale = 1.0 / sqrt(den);
            num *= scale * scale;
            for (int q = 3 * r0; q < 3 * r1; ++q) {
                v[q] *= scale;
                w[q] *= scale;
            }
        }
        double a = num; /* v . A v with |v|_D = 1 */
        if (!isfinite(a)) break;
        alpha[k++] = a;
        if (j + 1 == run->steps) break;
        /* w -= a v + beta_prev vp; beta = |w|_D (its D w per row, as chunk_apply's dw) */
        for (int c = c0; c < c1; ++c) { /* (chunks hold whole pairs) */
            int lo, hi;
            chunk_bounds(L, c, &lo, &hi);
            for (int q = 3 * lo; q < 3 * hi; ++q) w[q] -= a * v[q] + beta_prev * vp[q];
            double s = 0.0;
            for (int i = lo; i < hi; ++i) {
                double dw[3] = {0, 0, 0};
                wc_amg_d_mulv_add(L, i, pair_blocks, w, dw);
                s += v3_dot(w + 3 * i, dw);
            }
            L->partial[3 * c + 2] = s;
        }
        WC_PAR_BARRIER();
        double b = sqrt(chunk_sum(L, 2));
        if (!(b > 1e-12 * fabs(a)) || !isfinite(b)) break; /* an invariant subspace: alpha is exact */
        beta[k - 1] = b;
        beta_prev = b;
        /* vp <- v, v <- w / b (w is overwritten by the next product) */
        double* tmp = vp;
        vp = v;
        v = tmp;
        for (int q = 3 * r0; q < 3 * r1; ++q) v[q] = w[q] / b;
    }
    if (tid == 0) {
        run->k = k;
        for (int j = 0; j < k; ++j) {
            run->alpha[j] = alpha[j];
            if (j + 1 < k) run->beta[j] = beta[j];
        }
    }
}

static double lanczos(wc_amg_level* L, int steps, int pair_blocks, wc_par* par) {
    lanczos_run run = {.L = L, .steps = steps > WC_AMG_MAX_LANCZOS ? WC_AMG_MAX_LANCZOS : steps,
                       .pair_blocks = pair_blocks};
    WC_PAR_REGION(par) lanczos_part(&run);
    return run.k > 0 ? tridiagonal_max(run.alpha, run.beta, run.k) : 0.0;
}

double wc_amg_eigen_estimate(wc_amg_level* L, int steps, int use_lanczos, int pair_blocks, wc_par* par) {
    return use_lanczos ? lanczos(L, steps, pair_blocks, par) : power_iterations(L, steps, pair_blocks, par);
}

/* ---- the estimates as state (amg.h, wc_amg.carry_bounds) -------------------------------------- */

void wc_amg_bounds_get(const wc_amg* a, wc_amg_bounds* b) {
    memset(b, 0, sizeof *b);
    if (!a || !a->est_valid) return;
    b->valid = 1;
    b->age = a->carry_age;
    b->terms = a->est_terms;
    for (int l = 0; l < a->n_levels; ++l) b->est[l] = a->lev[l].estimate;
}

void wc_amg_bounds_set(wc_amg* a, const wc_amg_bounds* b) {
    if (!a) return;
    wc_amg_bounds_invalidate(a);
    if (!b || !b->valid || b->age < 0) return;
    for (int l = 0; l < a->n_levels; ++l)
        if (!isfinite(b->est[l]) || b->est[l] < 0) return;
    for (int l = 0; l < a->n_levels; ++l) a->lev[l].estimate = b->est[l];
    a->carry_age = b->age;
    a->est_terms = b->terms;
    a->est_valid = 1;
}

void wc_amg_bounds_invalidate(wc_amg* a) {
    if (!a) return;
    a->est_valid = 0;
    a->carry_age = 0;
    a->est_terms = 0;
}
