#include "bsr_rows.h"
#include <math.h>
#include <stddef.h>

void wc_bsr_rows_scalar(const int* row_start, const int* col, const double* val, int lo, int hi, const double* s,
                        double sign, const double* x, double* y) {
    for (int i = lo; i < hi; ++i) {
        double a0 = 0.0, a1 = 0.0, a2 = 0.0;
        for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
            const double* B = val + 9 * (size_t)k;
            const double* v = x + 3 * (size_t)col[k];
            a0 += B[0] * v[0] + B[1] * v[1] + B[2] * v[2];
            a1 += B[3] * v[0] + B[4] * v[1] + B[5] * v[2];
            a2 += B[6] * v[0] + B[7] * v[1] + B[8] * v[2];
        }
        double* o = y + 3 * (size_t)i;
        if (s) {
            const double* si = s + 3 * (size_t)i;
            o[0] = si[0] + sign * a0;
            o[1] = si[1] + sign * a1;
            o[2] = si[2] + sign * a2;
        } else {
            o[0] = sign * a0;
            o[1] = sign * a1;
            o[2] = sign * a2;
        }
    }
}

void wc_bsr_rows_f_scalar(const int* row_start, const int* col, const float* val, int lo, int hi, const double* s,
                          double sign, const double* x, double* y) {
    for (int i = lo; i < hi; ++i) {
        double a0 = 0.0, a1 = 0.0, a2 = 0.0;
        for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
            const float* B = val + 9 * (size_t)k;
            const double* v = x + 3 * (size_t)col[k];
            a0 += (double)B[0] * v[0] + (double)B[1] * v[1] + (double)B[2] * v[2];
            a1 += (double)B[3] * v[0] + (double)B[4] * v[1] + (double)B[5] * v[2];
            a2 += (double)B[6] * v[0] + (double)B[7] * v[1] + (double)B[8] * v[2];
        }
        double* o = y + 3 * (size_t)i;
        const double* si = s ? s + 3 * (size_t)i : NULL;
        o[0] = (si ? si[0] : 0.0) + sign * a0;
        o[1] = (si ? si[1] : 0.0) + sign * a1;
        o[2] = (si ? si[2] : 0.0) + sign * a2;
    }
}

/* The float-vector kernel's arithmetic lane by lane: a row's blocks alternate between two sets of
 * accumulators (the row's 1st, 3rd, ... blocks and its 2nd, 4th, ...), each of one 8-lane
 * register for block rows 0 and 1 (B[0..7] times (x0 x1 x2 x0 x1 x2 x3 x3)) and one 4-lane
 * register for row 2 (B[6..9], B[9] the next block's first or the padding, times x4; x3 = 0).
 * The two sets are added, then each row's lanes folded pairwise as rows_fx_avx2's horizontal
 * adds do. */
void wc_bsr_rows_fx_scalar(const int* row_start, const int* col, const float* val, int lo, int hi, const double* s,
                           double sign, const float* x4, double* y, float* y4) {
    static const int spread[8] = {0, 1, 2, 0, 1, 2, 3, 3};
    for (int i = lo; i < hi; ++i) {
        float a[2][8] = {{0}}, c[2][4] = {{0}};
        for (int k = row_start[i]; k < row_start[i + 1]; ++k) {
            const int e = (k - row_start[i]) & 1;
            const float* B = val + 9 * (size_t)k;
            const float* v = x4 + 4 * (size_t)col[k];
            for (int l = 0; l < 8; ++l) a[e][l] = fmaf(B[l], v[spread[l]], a[e][l]);
            for (int l = 0; l < 4; ++l) c[e][l] = fmaf(B[6 + l], v[l], c[e][l]);
        }
        float p[8], q[4];
        for (int l = 0; l < 8; ++l) p[l] = a[0][l] + a[1][l];
        for (int l = 0; l < 4; ++l) q[l] = c[0][l] + c[1][l];
        const float r[3] = {(p[0] + p[1]) + (p[2] + 0.0f), (p[3] + p[4]) + (p[5] + p[6]), (q[0] + q[1]) + (q[2] + q[3])};
        double* o = y + 3 * (size_t)i;
        for (int d = 0; d < 3; ++d) o[d] = s ? fma(sign, (double)r[d], s[3 * (size_t)i + d]) : sign * (double)r[d];
        if (y4)
            for (int d = 0; d < 4; ++d) y4[4 * (size_t)i + d] = d < 3 ? (float)o[d] : 0.0f;
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_BSR_ROWS_AVX2 1

/* o = si + sign (sum of a0's lanes, a1's, a2's) (si NULL: 0 +) */
__attribute__((target("avx2,fma"))) static inline void row_store(__m256d a0, __m256d a1, __m256d a2, const double* si,
                                                                 double sign, double* o) {
    /* (sum a0, sum a1) and (sum a2, sum a2) */
    const __m256d h01 = _mm256_hadd_pd(a0, a1), h22 = _mm256_hadd_pd(a2, a2);
    const __m128d r01 = _mm_add_pd(_mm256_castpd256_pd128(h01), _mm256_extractf128_pd(h01, 1));
    const __m128d r22 = _mm_add_pd(_mm256_castpd256_pd128(h22), _mm256_extractf128_pd(h22, 1));
    const __m128d g = _mm_set1_pd(sign);
    if (si) {
        _mm_storeu_pd(o, _mm_fmadd_pd(g, r01, _mm_loadu_pd(si)));
        o[2] = si[2] + sign * _mm_cvtsd_f64(r22);
    } else {
        _mm_storeu_pd(o, _mm_mul_pd(g, r01));
        o[2] = sign * _mm_cvtsd_f64(r22);
    }
}

/* Each block row times x_j in one register (lane 3 zero: x_j is loaded masked to 3 lanes, so the
 * block's next element read in lane 3 of the third row is multiplied by 0), accumulated over the
 * row's blocks; the three registers' lanes are summed at the row's end. */
__attribute__((target("avx2,fma"))) static void rows_avx2(const int* row_start, const int* col, const double* val,
                                                           int lo, int hi, const double* s, double sign,
                                                           const double* x, double* y) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int i = lo; i < hi; ++i) {
        __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
        const int k1 = row_start[i + 1];
        for (int k = row_start[i]; k < k1; ++k) {
            const double* B = val + 9 * (size_t)k;
            const __m256d v = _mm256_maskload_pd(x + 3 * (size_t)col[k], m3);
            a0 = _mm256_fmadd_pd(_mm256_loadu_pd(B), v, a0);
            a1 = _mm256_fmadd_pd(_mm256_loadu_pd(B + 3), v, a1);
            a2 = _mm256_fmadd_pd(_mm256_maskload_pd(B + 6, m3), v, a2);
        }
        row_store(a0, a1, a2, s ? s + 3 * (size_t)i : NULL, sign, y + 3 * (size_t)i);
    }
}

/* The same with single-precision blocks: each block row's 4 floats (the third row's 4th is the
 * next block's first, or the array's padding: WC_BSR_F_PAD) widened to doubles in the load. */
__attribute__((target("avx2,fma"))) static void rows_f_avx2(const int* row_start, const int* col, const float* val,
                                                             int lo, int hi, const double* s, double sign,
                                                             const double* x, double* y) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int i = lo; i < hi; ++i) {
        __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
        const int k1 = row_start[i + 1];
        for (int k = row_start[i]; k < k1; ++k) {
            const float* B = val + 9 * (size_t)k;
            const __m256d v = _mm256_maskload_pd(x + 3 * (size_t)col[k], m3);
            a0 = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(B)), v, a0);
            a1 = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(B + 3)), v, a1);
            a2 = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(B + 6)), v, a2);
        }
        row_store(a0, a1, a2, s ? s + 3 * (size_t)i : NULL, sign, y + 3 * (size_t)i);
    }
}

/* Float blocks times the float vector: per block, x_j's 4 floats broadcast to both halves of a
 * register, spread to (x0 x1 x2 x0 x1 x2 0 0) against block rows 0-1 (B[0..7]: 8-wide FMA), and x_j
 * itself against row 2 (B[6..9]: 4-wide; B[6], B[7] meet zeros in the first, B[9] the 4th float's
 * zero in the second). Two blocks an iteration into two sets of accumulators (half the loop's
 * overhead, two FMA latency chains); about 8 instructions a block where rows_f_avx2 takes 14. */
__attribute__((target("avx2,fma"))) static inline void fx_block(const float* B, const float* v, __m256i spread,
                                                                __m256* a, __m128* c) {
    const __m256 w = _mm256_broadcast_ps((const __m128*)v);
    *a = _mm256_fmadd_ps(_mm256_loadu_ps(B), _mm256_permutevar8x32_ps(w, spread), *a);
    *c = _mm_fmadd_ps(_mm_loadu_ps(B + 6), _mm256_castps256_ps128(w), *c);
}

/* rows_fx_avx2's loop, inlined once for each case of s and y4 (no tests in the loop) */
__attribute__((target("avx2,fma"), always_inline)) static inline void rows_fx_body(
    const int* row_start, const int* col, const float* val, int lo, int hi, const double* s, double sign,
    const float* x4, double* y, float* y4, const int has_s, const int has_y4) {
    const __m256i spread = _mm256_setr_epi32(0, 1, 2, 0, 1, 2, 3, 3);
    const __m256i row1 = _mm256_setr_epi32(3, 4, 5, 6, 6, 6, 6, 6);
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    const __m256d g = _mm256_set1_pd(sign);
    const __m128 z = _mm_setzero_ps();
    for (int i = lo; i < hi; ++i) {
        const int* cp = col + row_start[i];
        const float* B = val + 9 * (size_t)row_start[i];
        __m256 a0 = _mm256_setzero_ps(), a1 = _mm256_setzero_ps();
        __m128 c0 = _mm_setzero_ps(), c1 = _mm_setzero_ps();
        const int* const ce = col + row_start[i + 1];
        if ((ce - cp) & 1) { /* an odd count: the first block alone (into the first set) */
            fx_block(B, x4 + 4 * (size_t)cp[0], spread, &a0, &c0);
            ++cp;
            B += 9;
        }
        for (; cp < ce; cp += 2, B += 18) {
            fx_block(B, x4 + 4 * (size_t)cp[0], spread, &a1, &c1);
            fx_block(B + 9, x4 + 4 * (size_t)cp[1], spread, &a0, &c0);
        }
        const __m256 a = _mm256_add_ps(a0, a1);
        const __m128 c = _mm_add_ps(c0, c1);
        /* rows 0 and 1's partial sums as (a0 a1 a2 0) and (a3 a4 a5 a6 = 0), row 2's in c */
        const __m128 p = _mm_blend_ps(_mm256_castps256_ps128(a), z, 8);
        const __m128 q = _mm256_castps256_ps128(_mm256_permutevar8x32_ps(a, row1));
        const __m256d r = _mm256_cvtps_pd(_mm_hadd_ps(_mm_hadd_ps(p, q), _mm_hadd_ps(c, z)));
        const __m256d o = has_s ? _mm256_fmadd_pd(g, r, _mm256_maskload_pd(s + 3 * (size_t)i, m3)) : _mm256_mul_pd(g, r);
        double* yi = y + 3 * (size_t)i;
        _mm_storeu_pd(yi, _mm256_castpd256_pd128(o));
        _mm_store_sd(yi + 2, _mm256_extractf128_pd(o, 1));
        if (has_y4) _mm_storeu_ps(y4 + 4 * (size_t)i, _mm_blend_ps(_mm256_cvtpd_ps(o), z, 8));
    }
}

__attribute__((target("avx2,fma"))) static void rows_fx_avx2(const int* row_start, const int* col, const float* val,
                                                              int lo, int hi, const double* s, double sign,
                                                              const float* x4, double* y, float* y4) {
    if (lo >= hi) return;
    if (s && y4) rows_fx_body(row_start, col, val, lo, hi, s, sign, x4, y, y4, 1, 1);
    else if (s) rows_fx_body(row_start, col, val, lo, hi, s, sign, x4, y, NULL, 1, 0);
    else rows_fx_body(row_start, col, val, lo, hi, NULL, sign, x4, y, y4, 0, y4 != NULL);
}

wc_bsr_rows_fx_fn wc_bsr_rows_fx_vector(void) {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? rows_fx_avx2 : NULL;
}

wc_bsr_rows_f_fn wc_bsr_rows_f_vector(void) {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? rows_f_avx2 : NULL;
}

wc_bsr_rows_fn wc_bsr_rows_vector(void) {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? rows_avx2 : NULL;
}
#else
wc_bsr_rows_fn wc_bsr_rows_vector(void) { return NULL; }
wc_bsr_rows_f_fn wc_bsr_rows_f_vector(void) { return NULL; }
wc_bsr_rows_fx_fn wc_bsr_rows_fx_vector(void) { return NULL; }
#endif

void wc_bsr_rows(const int* row_start, const int* col, const double* val, int lo, int hi, const double* s,
                 double sign, const double* x, double* y) {
    wc_bsr_rows_fn f = wc_bsr_rows_vector();
    (f ? f : wc_bsr_rows_scalar)(row_start, col, val, lo, hi, s, sign, x, y);
}

void wc_bsr_rows_f(const int* row_start, const int* col, const float* val, int lo, int hi, const double* s,
                   double sign, const double* x, double* y) {
    wc_bsr_rows_f_fn f = wc_bsr_rows_f_vector();
    (f ? f : wc_bsr_rows_f_scalar)(row_start, col, val, lo, hi, s, sign, x, y);
}
