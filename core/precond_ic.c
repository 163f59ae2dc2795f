/* Block IC(0) of the projected matrix (precond_ic.h). */
#include <math.h>
#include <string.h>
#include "bsr_rows.h"
#include "precond_ic.h"
#include "solve_kernels.h"
#include "vec3.h"

wc_status wcs_ic_create(wcs_ic** out, const wc_bsr_pattern* p, const wc_allocator* a) {
    *out = NULL;
    wcs_ic* ic = WC_NEW(a, wcs_ic, 1);
    if (!ic) return WC_ERROR_OUT_OF_MEMORY;
    ic->p = p;
    ic->F = WC_NEW(a, double, 9 * (size_t)p->n_blocks);
    ic->Dinv = WC_NEW(a, double, 9 * (size_t)p->n_rows);
    ic->DinvT = WC_NEW(a, double, 12 * (size_t)p->n_rows);
    if (!ic->F || !ic->Dinv || !ic->DinvT) {
        wcs_ic_destroy(ic, a);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    *out = ic;
    return WC_OK;
}

void wcs_ic_destroy(wcs_ic* ic, const wc_allocator* a) {
    if (!ic) return;
    wc_free(a, ic->F);
    wc_free(a, ic->Dinv);
    wc_free(a, ic->DinvT);
    wc_free(a, ic);
}

/* o -= a b */
static inline void m3_mul_sub(double* o, const double* a, const double* b) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            o[3 * i + j] -= a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}

/* D symmetrised in place; its inverse in Dinv when its Cholesky pivots exceed 1e-12 x ref's
 * diagonal (the pivot block before the updates). 1 on success. */
static int pivot(double* D, const double* ref, double* Dinv) {
    double a01 = 0.5 * (D[1] + D[3]), a02 = 0.5 * (D[2] + D[6]), a12 = 0.5 * (D[5] + D[7]);
    D[1] = D[3] = a01;
    D[2] = D[6] = a02;
    D[5] = D[7] = a12;
    const double tol = 1e-12;
    double p0 = D[0];
    if (!(p0 > tol * fabs(ref[0])) || !isfinite(p0)) return 0;
    double minor2 = D[0] * D[4] - a01 * a01, p1 = minor2 / p0;
    if (!(p1 > tol * fabs(ref[4])) || !isfinite(p1)) return 0;
    double det = m3_inverse(Dinv, D), p2 = det / minor2;
    return p2 > tol * fabs(ref[8]) && isfinite(p2);
}

/* Row i of the factor (precond_ic.h) with the 3x3 kernels MUL (G = a b) and MUL_SUB (o -= a b);
 * 0 at a pivot that is not SPD. Expanded twice below: with the scalar kernels and with AVX's, which
 * do the same operations in the same order, so both give the same bits. */
#define IC_FACTOR_BODY(MUL, MUL_SUB)                                                                        \
    const wc_bsr_pattern* p = ic->p;                                                                        \
    const int* rs = p->row_start;                                                                           \
    const int* col = p->col;                                                                                \
    double* F = ic->F;                                                                                      \
    for (int i = 0; i < p->n_rows; ++i) {                                                                   \
        const int d = p->diag[i], end = rs[i + 1];                                                          \
        /* row i's upper blocks: P's (the diagonal shifted) */                                              \
        for (int b = d; b < end; ++b) wcs_project_block(f, i, col[b], A + 9 * (size_t)b, F + 9 * (size_t)b); \
        double ref[9];                                                                                      \
        memcpy(ref, F + 9 * (size_t)d, sizeof ref);                                                         \
        if (alpha != 0.0)                                                                                   \
            for (int k = 0; k < 9; k += 4) F[9 * (size_t)d + k] += alpha * fabs(ref[k]);                    \
        /* each lower neighbour k (ascending): L_ik = U_ki^T, and (i, j) -= L_ik D_k^{-1} U_kj */           \
        for (int b = rs[i]; b < d; ++b) {                                                                   \
            const int k = col[b], bki = p->transpose[b];                                                    \
            const double* Uki = F + 9 * (size_t)bki;                                                        \
            double* Lik = F + 9 * (size_t)b;                                                                \
            for (int r = 0; r < 3; ++r)                                                                     \
                for (int c = 0; c < 3; ++c) Lik[3 * r + c] = Uki[3 * c + r];                                \
            double G[12]; /* L_ik D_k^{-1} (rows 0..2 in G[0..8]; G[9..11] spare for 4-wide stores) */      \
            MUL(G, Lik, ic->Dinv + 9 * (size_t)k);                                                          \
            /* merge row k's blocks from (k, i) on with row i's from (i, i) on */                           \
            int bk = bki, bi = d;                                                                           \
            const int ek = rs[k + 1];                                                                       \
            while (bk < ek && bi < end) {                                                                   \
                if (col[bk] < col[bi]) ++bk;                                                                \
                else if (col[bk] > col[bi]) ++bi;                                                           \
                else {                                                                                      \
                    MUL_SUB(F + 9 * (size_t)bi, G, F + 9 * (size_t)bk);                                     \
                    ++bk;                                                                                   \
                    ++bi;                                                                                   \
                }                                                                                           \
            }                                                                                               \
        }                                                                                                   \
        if (!pivot(F + 9 * (size_t)d, ref, ic->Dinv + 9 * (size_t)i)) return 0;                             \
    }                                                                                                       \
    return 1;

static int factor_scalar(wcs_ic* ic, const double* A, const wc_filter* f, double alpha) {
    IC_FACTOR_BODY(m3_mul, m3_mul_sub)
}

/* DinvT: each D_i^{-1} by columns, a column per 4 doubles (lane 3 zero), for the AVX2 sweeps. */
static void transpose_dinv(wcs_ic* ic) {
    for (int i = 0; i < ic->p->n_rows; ++i) {
        const double* m = ic->Dinv + 9 * (size_t)i;
        double* c = ic->DinvT + 12 * (size_t)i;
        for (int j = 0; j < 3; ++j) {
            c[4 * j] = m[j];
            c[4 * j + 1] = m[3 + j];
            c[4 * j + 2] = m[6 + j];
            c[4 * j + 3] = 0.0;
        }
    }
}

int wcs_ic_factor_scalar(wcs_ic* ic, const double* A, const wc_filter* f, double alpha) {
    const int ok = factor_scalar(ic, A, f, alpha);
    if (ok) transpose_dinv(ic); /* a partial factor is set up again or replaced */
    return ok;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define IC_AVX __attribute__((target("avx")))
/* Rows of a 3x3 block in registers (lane 3 zero): the last row masked, so nothing past the block
 * is read. */
#define IC_M3 _mm256_setr_epi64x(-1, -1, -1, 0)
/* Row r of a b from b's rows: (a_r0 b_0 + a_r1 b_1) + a_r2 b_2, each lane as m3_mul's sum (no FMA:
 * the same rounding as the scalar kernel's separate products and additions). */
IC_AVX static inline __m256d row_times(const double* a, __m256d b0, __m256d b1, __m256d b2) {
    const __m256d p0 = _mm256_mul_pd(_mm256_broadcast_sd(a), b0), p1 = _mm256_mul_pd(_mm256_broadcast_sd(a + 1), b1);
    return _mm256_add_pd(_mm256_add_pd(p0, p1), _mm256_mul_pd(_mm256_broadcast_sd(a + 2), b2));
}
/* o = a b, o with room for 12 doubles (each row stored 4 wide, in row order) */
IC_AVX static inline void m3_mul_avx(double* o, const double* a, const double* b) {
    const __m256d b0 = _mm256_loadu_pd(b), b1 = _mm256_loadu_pd(b + 3), b2 = _mm256_maskload_pd(b + 6, IC_M3);
    for (int r = 0; r < 3; ++r) _mm256_storeu_pd(o + 3 * r, row_times(a + 3 * r, b0, b1, b2));
}
/* o -= a b, as m3_mul_sub: o_rj - ((a_r0 b_0j + a_r1 b_1j) + a_r2 b_2j) */
IC_AVX static inline void m3_mul_sub_avx(double* o, const double* a, const double* b) {
    const __m256i m3 = IC_M3;
    const __m256d b0 = _mm256_loadu_pd(b), b1 = _mm256_loadu_pd(b + 3), b2 = _mm256_maskload_pd(b + 6, m3);
    for (int r = 0; r < 3; ++r) {
        const __m256d t = row_times(a + 3 * r, b0, b1, b2);
        _mm256_maskstore_pd(o + 3 * r, m3, _mm256_sub_pd(_mm256_maskload_pd(o + 3 * r, m3), t));
    }
}
IC_AVX static int factor_avx(wcs_ic* ic, const double* A, const wc_filter* f, double alpha) {
    IC_FACTOR_BODY(m3_mul_avx, m3_mul_sub_avx)
}
static int have_avx(void) { return __builtin_cpu_supports("avx"); }
#else
static int factor_avx(wcs_ic* ic, const double* A, const wc_filter* f, double alpha) {
    return factor_scalar(ic, A, f, alpha);
}
static int have_avx(void) { return 0; }
#endif

int wcs_ic_factor(wcs_ic* ic, const double* A, const wc_filter* f, double alpha) {
    const int ok = have_avx() ? factor_avx(ic, A, f, alpha) : factor_scalar(ic, A, f, alpha);
    if (ok) transpose_dinv(ic); /* a partial factor is set up again or replaced */
    return ok;
}

/* The fallback: no off-diagonal blocks, D_i = D~_i (identity where singular), as block Jacobi. */
static void factor_diagonal(wcs_ic* ic, const double* A, const wc_filter* f) {
    const wc_bsr_pattern* p = ic->p;
    memset(ic->F, 0, sizeof(double) * 9 * (size_t)p->n_blocks);
    for (int i = 0; i < p->n_rows; ++i) {
        double* D = ic->F + 9 * (size_t)p->diag[i];
        wcs_project_block(f, i, i, A + 9 * (size_t)p->diag[i], D);
        if (m3_inverse(ic->Dinv + 9 * (size_t)i, D) == 0.0) {
            m3_identity(ic->Dinv + 9 * (size_t)i, 1.0);
            m3_identity(D, 1.0);
        }
    }
    transpose_dinv(ic);
}

double wcs_ic_setup(wcs_ic* ic, const double* A, const wc_filter* f) {
    ++ic->setups;
    ic->jacobi = 0;
    double alpha = 0.0;
    for (int attempt = 0; attempt <= WCS_IC_MAX_SHIFTS; ++attempt) {
        if (wcs_ic_factor(ic, A, f, alpha)) {
            ic->shift = alpha;
            if (alpha > 0.0) ++ic->shifted;
            return alpha;
        }
        alpha = alpha == 0.0 ? 1e-3 : 4.0 * alpha;
    }
    factor_diagonal(ic, A, f);
    ic->jacobi = 1;
    ic->shift = -1.0;
    ++ic->fallbacks;
    return -1.0;
}

void wcs_ic_apply_scalar(const wcs_ic* ic, const double* r, double* t) {
    const wc_bsr_pattern* p = ic->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    const double* F = ic->F;
    const int n = p->n_rows;
    for (int i = 0; i < n; ++i) { /* (D + L) w = r, w in t */
        double s[3];
        const int range[2] = {rs[i], p->diag[i]};
        wc_bsr_rows_scalar(range, col, F, 0, 1, r + 3 * (size_t)i, -1.0, t, s);
        m3_mulv(t + 3 * (size_t)i, ic->Dinv + 9 * (size_t)i, s);
    }
    for (int i = n - 1; i >= 0; --i) { /* (I + D^{-1} L^T) t = w */
        double s[3], d[3];
        const int range[2] = {p->diag[i] + 1, rs[i + 1]};
        wc_bsr_rows_scalar(range, col, F, 0, 1, NULL, 1.0, t, s);
        m3_mulv(d, ic->Dinv + 9 * (size_t)i, s);
        v3_sub(t + 3 * (size_t)i, t + 3 * (size_t)i, d);
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
/* The row's sum over blocks [k0, k1) of F_k x_{col k}: each block row in one register (lane 3
 * zero, as bsr_rows.c's kernel), multiply-added per lane, then the lanes summed pairwise,
 * (l0 + l1) + (l2 + l3), all three rows at once: the sums in lanes 0..2, lane 3 zero. */
__attribute__((target("avx2,fma"))) static inline __m256d row_sum(const double* F, const int* col, int k0, int k1,
                                                                   const double* x, __m256i m3) {
    __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
    for (int k = k0; k < k1; ++k) {
        const double* B = F + 9 * (size_t)k;
        const __m256d v = _mm256_maskload_pd(x + 3 * (size_t)col[k], m3);
        a0 = _mm256_fmadd_pd(_mm256_loadu_pd(B), v, a0);
        a1 = _mm256_fmadd_pd(_mm256_loadu_pd(B + 3), v, a1);
        a2 = _mm256_fmadd_pd(_mm256_maskload_pd(B + 6, m3), v, a2);
    }
    const __m256d h01 = _mm256_hadd_pd(a0, a1); /* a0 l0+l1, a1 l0+l1, a0 l2+l3, a1 l2+l3 */
    const __m256d h2 = _mm256_hadd_pd(a2, _mm256_setzero_pd()); /* a2 l0+l1, 0, a2 l2+l3, 0 */
    return _mm256_add_pd(_mm256_permute2f128_pd(h01, h2, 0x20), _mm256_permute2f128_pd(h01, h2, 0x31));
}

/* D^{-1} v from its padded columns c (DinvT): (c0 v0 + c1 v1) + c2 v2 per lane, m3_mulv's order. */
__attribute__((target("avx2"))) static inline __m256d dinv_times(const double* c, __m256d v) {
    const __m256d p0 = _mm256_mul_pd(_mm256_loadu_pd(c), _mm256_permute4x64_pd(v, 0x00));
    const __m256d p1 = _mm256_mul_pd(_mm256_loadu_pd(c + 4), _mm256_permute4x64_pd(v, 0x55));
    const __m256d p2 = _mm256_mul_pd(_mm256_loadu_pd(c + 8), _mm256_permute4x64_pd(v, 0xaa));
    return _mm256_add_pd(_mm256_add_pd(p0, p1), p2);
}

/* The sweeps with each row's sums, r - sum, D^{-1} times it and the store in registers: the
 * scalar-per-row code's operations in its order (the same bits; tests/test_precond_ic.c). */
__attribute__((target("avx2,fma"))) static void apply_avx2(const wcs_ic* ic, const double* r, double* t) {
    const wc_bsr_pattern* p = ic->p;
    const int* rs = p->row_start;
    const int* col = p->col;
    const int* diag = p->diag;
    const double* F = ic->F;
    const double* DT = ic->DinvT;
    const int n = p->n_rows;
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    const __m256d minus = _mm256_set1_pd(-1.0);
    for (int i = 0; i < n; ++i) { /* (D + L) w = r, w in t */
        const __m256d s = row_sum(F, col, rs[i], diag[i], t, m3);
        const __m256d v = _mm256_add_pd(_mm256_maskload_pd(r + 3 * (size_t)i, m3), _mm256_mul_pd(minus, s));
        _mm256_maskstore_pd(t + 3 * (size_t)i, m3, dinv_times(DT + 12 * (size_t)i, v));
    }
    for (int i = n - 1; i >= 0; --i) { /* (I + D^{-1} L^T) t = w */
        const __m256d d = dinv_times(DT + 12 * (size_t)i, row_sum(F, col, diag[i] + 1, rs[i + 1], t, m3));
        double* ti = t + 3 * (size_t)i;
        _mm256_maskstore_pd(ti, m3, _mm256_sub_pd(_mm256_maskload_pd(ti, m3), d));
    }
}

static int have_avx2(void) { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
#else
static void apply_avx2(const wcs_ic* ic, const double* r, double* t) { wcs_ic_apply_scalar(ic, r, t); }
static int have_avx2(void) { return 0; }
#endif

void wcs_ic_apply(const wcs_ic* ic, const double* r, double* t) {
    if (have_avx2()) apply_avx2(ic, r, t);
    else wcs_ic_apply_scalar(ic, r, t);
}
