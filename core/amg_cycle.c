/* One symmetric V-cycle of the multigrid hierarchy (amg.h): smoothing (Chebyshev in D^-1 A on
 * [lambda_max / ratio, lambda_max], or weighted block Jacobi), restriction by P^T, the coarse
 * correction, prolongation by P, the same smoothing again; the coarsest level is solved with its
 * dense Cholesky factor (or smoothed, when it could not be coarsened enough). With
 * wc_amg_opts.single every level's operator and P are read from their float copies
 * (amg_single.c), every sum in double; D^-1 stays double. With single_x too (and AVX2 + FMA) the
 * row products read each iterate's float shadow xf, written wherever x is, and sum in float
 * (wc_bsr_rows_fx); everything else stays double.
 * Threads: with Chebyshev smoothing a level's sweep before the coarse correction (smoothing,
 * residual, restriction) is one parallel region and the sweep after it another, with barriers
 * between the phases, instead of a region per kernel (a V-cycle of the suit's three levels: 4
 * regions and 26 barriers where it had 36 regions; docs/bench/threads.md). */
#include <string.h>
#include "amg.h"
#include "bsr_rows.h"
#include "vec3.h"

/* The float-vector row kernel where level L runs on a float shadow of its iterate (opts.single_x),
 * else NULL. Every level does or none (a prolongation reads the coarse level's shadow when that
 * level has one, prolong_rows). */
static wc_bsr_rows_fx_fn fx_kernel(const wc_amg* a, const wc_amg_level* L) {
    return a->opts.single && a->opts.single_x && L->xf && L->val_f ? wc_bsr_rows_fx_vector() : NULL;
}

/* xf_i = x_i rounded (the 4th float stays 0). Where x_i was just stored, the loops pass the values
 * they stored (put_f3): reading them back 16 bytes at a time from two 8-byte stores still in
 * flight is not forwarded, a stall a node that cost the V-cycle about a fifth of its time. */
static inline void put_f3(float* xf, double x0, double x1, double x2) {
    xf[0] = (float)x0;
    xf[1] = (float)x1;
    xf[2] = (float)x2;
}

static inline void put_f(float* xf, const double* x) { put_f3(xf, x[0], x[1], x[2]); }

/* t = r - A x (the level's BSR part; residual() adds the couplings); t = r when x is NULL. With fx
 * the product reads x's shadow L->xf. */
static void residual_bsr(const wc_amg_level* L, int single, wc_bsr_rows_fx_fn fx, const double* r, const double* x,
                         double* t, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        if (x && fx) fx(L->row_start, L->col, L->val_f, lo, hi, r, -1.0, L->xf, t, NULL);
        else if (x && single) wc_bsr_rows_f(L->row_start, L->col, L->val_f, lo, hi, r, -1.0, x, t);
        else if (x) wc_bsr_rows(L->row_start, L->col, L->val, lo, hi, r, -1.0, x, t);
        else if (hi > lo) memcpy(t + 3 * (size_t)lo, r + 3 * (size_t)lo, sizeof(double) * 3 * (size_t)(hi - lo));
    }
}

/* t = r - A x with the couplings' terms (amg_cross.c). */
static void residual(const wc_amg_level* L, int single, wc_bsr_rows_fx_fn fx, const double* r, const double* x,
                     double* t, wc_par* par) {
    residual_bsr(L, single, fx, r, x, t, par);
    if (x && L->cross && L->cross->n_terms > 0) wc_amg_cross_mul_add(L->cross, -1.0, x, t, L->n, par);
}

/* x += w D^-1 t (x is overwritten when `set`); xf (or NULL) its shadow. */
static void jacobi(const wc_amg_level* L, double w, const double* t, double* x, float* xf, int set, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double d[3], xn[3];
            wc_amg_dinv(L, i, t, d);
            for (int c = 0; c < 3; ++c) {
                xn[c] = set ? d[c] * w : x[3 * i + c] + w * d[c];
                x[3 * i + c] = xn[c];
            }
            if (xf) put_f3(xf + 4 * i, xn[0], xn[1], xn[2]);
        }
    }
}

/* rc_I = sum over P^T's entries s of coarse node I of P_s^T t_row(s), for I in lo..hi-1. */
static void restrict_rows(const wc_amg_level* L, const double* t, double* rc, int lo, int hi) {
    for (int I = lo; I < hi; ++I) {
        double acc[3] = {0, 0, 0};
        for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
            const double* P = L->p_val + 9 * (size_t)L->pt_entry[s];
            const double* v = t + 3 * L->pt_row[s];
            acc[0] += P[0] * v[0] + P[3] * v[1] + P[6] * v[2];
            acc[1] += P[1] * v[0] + P[4] * v[1] + P[7] * v[2];
            acc[2] += P[2] * v[0] + P[5] * v[1] + P[8] * v[2];
        }
        v3_copy(rc + 3 * I, acc);
    }
}

/* The same from P's float copy. */
static void restrict_rows_f(const wc_amg_level* L, const double* t, double* rc, int lo, int hi) {
    for (int I = lo; I < hi; ++I) {
        double acc[3] = {0, 0, 0};
        for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
            const float* P = L->p_val_f + 9 * (size_t)L->pt_entry[s];
            const double* v = t + 3 * L->pt_row[s];
            acc[0] += (double)P[0] * v[0] + (double)P[3] * v[1] + (double)P[6] * v[2];
            acc[1] += (double)P[1] * v[0] + (double)P[4] * v[1] + (double)P[7] * v[2];
            acc[2] += (double)P[2] * v[0] + (double)P[5] * v[1] + (double)P[8] * v[2];
        }
        v3_copy(rc + 3 * I, acc);
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_RESTRICT_AVX2 1
/* The same with AVX2 + FMA: P_s^T t = sum_q (row q of P_s) t_q, each row in one register (the
 * third loaded masked to 3 lanes), accumulated over the entries; lane 3 is never stored. */
__attribute__((target("avx2,fma"))) static void restrict_rows_avx2(const wc_amg_level* L, const double* t, double* rc,
                                                                    int lo, int hi) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int I = lo; I < hi; ++I) {
        __m256d acc = _mm256_setzero_pd();
        for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
            const double* P = L->p_val + 9 * (size_t)L->pt_entry[s];
            const double* v = t + 3 * L->pt_row[s];
            acc = _mm256_fmadd_pd(_mm256_loadu_pd(P), _mm256_broadcast_sd(v), acc);
            acc = _mm256_fmadd_pd(_mm256_loadu_pd(P + 3), _mm256_broadcast_sd(v + 1), acc);
            acc = _mm256_fmadd_pd(_mm256_maskload_pd(P + 6, m3), _mm256_broadcast_sd(v + 2), acc);
        }
        double* o = rc + 3 * (size_t)I;
        _mm_storeu_pd(o, _mm256_castpd256_pd128(acc));
        o[2] = _mm_cvtsd_f64(_mm256_extractf128_pd(acc, 1));
    }
}

/* The same from P's float copy (each row's 4 floats widened in the load; the 4th lands in lane 3,
 * never stored; the array's padding, WC_BSR_F_PAD, covers the last entry's). */
__attribute__((target("avx2,fma"))) static void restrict_rows_f_avx2(const wc_amg_level* L, const double* t,
                                                                      double* rc, int lo, int hi) {
    for (int I = lo; I < hi; ++I) {
        __m256d acc = _mm256_setzero_pd();
        for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
            const float* P = L->p_val_f + 9 * (size_t)L->pt_entry[s];
            const double* v = t + 3 * L->pt_row[s];
            acc = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(P)), _mm256_broadcast_sd(v), acc);
            acc = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(P + 3)), _mm256_broadcast_sd(v + 1), acc);
            acc = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(P + 6)), _mm256_broadcast_sd(v + 2), acc);
        }
        double* o = rc + 3 * (size_t)I;
        _mm_storeu_pd(o, _mm256_castpd256_pd128(acc));
        o[2] = _mm_cvtsd_f64(_mm256_extractf128_pd(acc, 1));
    }
}
#endif

/* The restriction's row kernel: AVX2 + FMA where the CPU has them (the sums round differently by
 * a few ulps). */
static void (*restrict_kernel(int single))(const wc_amg_level*, const double*, double*, int, int) {
#ifdef WC_RESTRICT_AVX2
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
        return single ? restrict_rows_f_avx2 : restrict_rows_avx2;
#endif
    return single ? restrict_rows_f : restrict_rows;
}

/* rc = P^T t */
static void restrict_(const wc_amg_level* L, const wc_amg_level* N, int single, const double* t, double* rc,
                      wc_par* par) {
    void (*rows)(const wc_amg_level*, const double*, double*, int, int) = restrict_kernel(single);
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        rows(L, t, rc, lo, hi);
    }
}

/* x += P xc on rows [lo, hi): with fxn (the coarse level N runs on shadows) P times xc's shadow
 * N->xf; xf (or NULL): x's shadow, written. */
static void prolong_rows(const wc_amg_level* L, const wc_amg_level* N, int single, wc_bsr_rows_fx_fn fxn,
                         const double* xc, double* x, float* xf, int lo, int hi) {
    if (fxn) {
        fxn(L->p_start, L->p_col, L->p_val_f, lo, hi, x, 1.0, N->xf, x, xf);
        return;
    }
    if (single) wc_bsr_rows_f(L->p_start, L->p_col, L->p_val_f, lo, hi, x, 1.0, xc, x);
    else wc_bsr_rows(L->p_start, L->p_col, L->p_val, lo, hi, x, 1.0, xc, x);
    if (xf)
        for (int i = lo; i < hi; ++i) put_f(xf + 4 * i, x + 3 * i);
}

static void prolong(const wc_amg_level* L, const wc_amg_level* N, int single, wc_bsr_rows_fx_fn fxn, const double* xc,
                    double* x, float* xf, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        prolong_rows(L, N, single, fxn, xc, x, xf, lo, hi);
    }
}

/* The parts of a level's sweep run by each thread of one region (vcycle), on its rows [lo, hi) of
 * the same fixed ranges as the kernels above, with the same sums per row: the same bits on any
 * thread count, with barriers where a phase reads what other threads wrote (and before x changes
 * while others may still read it). */

/* t = r - A x with the couplings' terms on rows [lo, hi): residual() per thread. A merged level
 * (amg_merge.c) reads its one float matrix; otherwise a list level's terms are scaled first (every
 * thread's share, then a barrier). */
static void residual_part(const wc_amg_level* L, int single, wc_bsr_rows_fx_fn fx, const double* r, const double* x,
                          double* t, int lo, int hi) {
    const wc_amg_cross* X = L->cross && L->cross->n_terms > 0 ? L->cross : NULL;
    if (X && X->m_blocks > 0 && single) { /* B + X merged (amg_merge.c): one pass */
        if (fx) fx(X->m_start, X->m_col, X->m_val_f, lo, hi, r, -1.0, L->xf, t, NULL);
        else wc_bsr_rows_f(X->m_start, X->m_col, X->m_val_f, lo, hi, r, -1.0, x, t);
        return;
    }
    if (X && wc_amg_cross_as_terms(X)) {
        int q0, q1;
        wc_par_range(X->n_terms, wc_par_tid(), wc_par_nt(), &q0, &q1);
        wc_amg_cross_scale(X, -1.0, x, q0, q1);
        WC_PAR_BARRIER();
    }
    if (fx) fx(L->row_start, L->col, L->val_f, lo, hi, r, -1.0, L->xf, t, NULL);
    else if (single) wc_bsr_rows_f(L->row_start, L->col, L->val_f, lo, hi, r, -1.0, x, t);
    else wc_bsr_rows(L->row_start, L->col, L->val, lo, hi, r, -1.0, x, t);
    if (X) wc_amg_cross_rows_add(X, -1.0, x, t, L->n, lo, hi);
}

/* chebyshev() per thread: `steps` matrix products, x from zero when `zero` (else x must be
 * complete: a barrier before); nodes: the node updates' kernel (NULL: the scalar loops). */
static void chebyshev_part(wc_amg_level* L, int single, wc_bsr_rows_fx_fn fx, wc_amg_cheb_nodes_fn nodes,
                           double ratio, int steps, const double* r, double* x, int zero, double* d, int lo, int hi) {
    float* xf = fx ? L->xf : NULL;
    const double b = L->bound, a = b / ratio;
    const double theta = 0.5 * (b + a), delta = 0.5 * (b - a), sigma = theta / delta;
    double rho = 1.0 / sigma;
    const double* t = r; /* the residual at x = 0 */
    if (!zero) {
        residual_part(L, single, fx, r, x, L->t, lo, hi);
        t = L->t;
        WC_PAR_BARRIER(); /* t complete (a pair's D^-1 reads both rows), x read */
    }
    const double inv_theta = 1.0 / theta;
    if (nodes) nodes(L, t, d, x, xf, lo, hi, 0.0, inv_theta, zero ? 0 : 1);
    else for (int i = lo; i < hi; ++i) { /* d = D^-1 t / theta; x = d, or x += d */
        double e[3], xn[3];
        wc_amg_dinv(L, i, t, e);
        for (int c = 0; c < 3; ++c) {
            const double dc = e[c] * inv_theta;
            d[3 * i + c] = dc;
            xn[c] = zero ? dc : x[3 * i + c] + dc;
            x[3 * i + c] = xn[c];
        }
        if (xf) put_f3(xf + 4 * i, xn[0], xn[1], xn[2]);
    }
    for (int k = 1; k < steps; ++k) {
        WC_PAR_BARRIER(); /* x complete */
        residual_part(L, single, fx, r, x, L->t, lo, hi);
        double rho_new = 1.0 / (2.0 * sigma - rho);
        double c1 = rho_new * rho, c2 = 2.0 * rho_new / delta;
        WC_PAR_BARRIER(); /* t complete, x read */
        if (nodes) nodes(L, L->t, d, x, xf, lo, hi, c1, c2, 2);
        else for (int i = lo; i < hi; ++i) { /* d = c1 d + c2 D^-1 t; x += d */
            double e[3], xn[3];
            wc_amg_dinv(L, i, L->t, e);
            for (int c = 0; c < 3; ++c) {
                const double dc = c1 * d[3 * i + c] + c2 * e[c];
                d[3 * i + c] = dc;
                xn[c] = x[3 * i + c] + dc;
                x[3 * i + c] = xn[c];
            }
            if (xf) put_f3(xf + 4 * i, xn[0], xn[1], xn[2]);
        }
        rho = rho_new;
    }
}

/* x = L^-T L^-1 r on the coarsest level (amg_dense.c). */
static void coarse_solve(wc_amg* a, const double* r, double* x) {
    wc_amg_dense_solve(a->coarse_L, a->coarse_dofs, r, a->coarse_y, x, wc_amg_dense_vec());
}

static void vcycle(wc_amg* a, int l, const double* r, double* x, wc_par* par) {
    wc_amg_level* L = &a->lev[l];
    const int single = a->opts.single && L->val_f;
    const wc_bsr_rows_fx_fn fx = fx_kernel(a, L);
    float* xf = fx ? L->xf : NULL; /* written wherever x is: the level above's prolongation reads it */
    if (l == a->n_levels - 1) {
        if (a->coarse_dense) {
            coarse_solve(a, r, x);
            if (xf)
                for (int i = 0; i < L->n; ++i) put_f(xf + 4 * i, x + 3 * i);
            return;
        }
        const double w = 1.0 / L->bound;
        jacobi(L, w, r, x, xf, 1, par);
        for (int s = 1; s < WC_AMG_COARSE_SWEEPS; ++s) {
            residual(L, single, fx, r, x, L->t, par);
            jacobi(L, w, L->t, x, xf, 0, par);
        }
        return;
    }
    wc_amg_level* N = &a->lev[l + 1];
    const double w = a->opts.smooth_weight / L->bound;
    if (a->opts.chebyshev) { /* two regions a level, barriers between the phases */
        const double ratio = a->opts.chebyshev_ratio;
        const int sweeps = a->opts.sweeps;
        void (*rows)(const wc_amg_level*, const double*, double*, int, int) = restrict_kernel(single);
        const wc_bsr_rows_fx_fn fxn = fx_kernel(a, N); /* N's iterate has a shadow */
        const wc_amg_cheb_nodes_fn nodes = a->opts.smooth_vector && L->DinvT ? wc_amg_cheb_nodes_kernel() : NULL;
        WC_PAR_REGION(par)
        { /* pre-smoothing, residual, restriction */
            int lo, hi, c0, c1;
            wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
            wc_par_range(N->n, wc_par_tid(), wc_par_nt(), &c0, &c1);
            chebyshev_part(L, single, fx, nodes, ratio, sweeps, r, x, 1, L->ev_scratch, lo, hi);
            WC_PAR_BARRIER();
            residual_part(L, single, fx, r, x, L->t, lo, hi);
            WC_PAR_BARRIER();
            rows(L, L->t, N->r, c0, c1);
        }
        vcycle(a, l + 1, N->r, N->x, par);
        WC_PAR_REGION(par)
        { /* prolongation, post-smoothing */
            int lo, hi;
            wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
            prolong_rows(L, N, single, fxn, N->x, x, xf, lo, hi);
            WC_PAR_BARRIER();
            chebyshev_part(L, single, fx, nodes, ratio, sweeps, r, x, 0, L->ev_scratch, lo, hi);
        }
        return;
    }
    jacobi(L, w, r, x, xf, 1, par);
    for (int s = 1; s < a->opts.sweeps; ++s) {
        residual(L, single, fx, r, x, L->t, par);
        jacobi(L, w, L->t, x, xf, 0, par);
    }
    residual(L, single, fx, r, x, L->t, par);
    restrict_(L, N, single, L->t, N->r, par);
    vcycle(a, l + 1, N->r, N->x, par);
    prolong(L, N, single, fx_kernel(a, N), N->x, x, xf, par);
    for (int s = 0; s < a->opts.sweeps; ++s) {
        residual(L, single, fx, r, x, L->t, par);
        jacobi(L, w, L->t, x, xf, 0, par);
    }
}

void wc_amg_apply(wc_amg* a, const double* r, double* z, wc_par* par) { vcycle(a, 0, r, z, par); }
