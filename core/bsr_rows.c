#include "bsr_rows.h"
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

wc_bsr_rows_f_fn wc_bsr_rows_f_vector(void) {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? rows_f_avx2 : NULL;
}

wc_bsr_rows_fn wc_bsr_rows_vector(void) {
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") ? rows_avx2 : NULL;
}
#else
wc_bsr_rows_fn wc_bsr_rows_vector(void) { return NULL; }
wc_bsr_rows_f_fn wc_bsr_rows_f_vector(void) { return NULL; }
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
