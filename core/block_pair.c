#include "block_pair.h"
#include <stddef.h>
#include "vec3.h"

static void mul_add_scalar(double* restrict z, const double* restrict M, const double* restrict T) {
    m3_mul_add(z, M, T);
    m3_mul_add(z + 9, M, T + 9);
}

static void tmul_add_scalar(double* restrict z, const double* restrict M, const double* restrict T) {
    m3_tmul_add(z, M, T);
    m3_tmul_add(z + 9, M, T + 9);
}

wc_pair_kernels wc_pair_kernels_scalar(void) {
    wc_pair_kernels k = {mul_add_scalar, tmul_add_scalar};
    return k;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

/* Row r of the product: sum_c M'(r, c) T(c, :) for both blocks, M' = M or M^T; lane 3 of each
 * row register is the next element (T[18] is not read: the last row is loaded masked) and is
 * never stored. */
__attribute__((target("avx2,fma"))) static inline void pair_avx2(double* restrict z, const double* restrict M,
                                                                 const double* restrict T, int transposed) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    const __m256d a0 = _mm256_loadu_pd(T), a1 = _mm256_loadu_pd(T + 3), a2 = _mm256_loadu_pd(T + 6);
    const __m256d b0 = _mm256_loadu_pd(T + 9), b1 = _mm256_loadu_pd(T + 12), b2 = _mm256_maskload_pd(T + 15, m3);
    for (int r = 0; r < 3; ++r) {
        const double m0 = transposed ? M[r] : M[3 * r];
        const double m1 = transposed ? M[3 + r] : M[3 * r + 1];
        const double m2 = transposed ? M[6 + r] : M[3 * r + 2];
        const __m256d c0 = _mm256_set1_pd(m0), c1 = _mm256_set1_pd(m1), c2 = _mm256_set1_pd(m2);
        const __m256d s0 = _mm256_fmadd_pd(c2, a2, _mm256_fmadd_pd(c1, a1, _mm256_mul_pd(c0, a0)));
        const __m256d s1 = _mm256_fmadd_pd(c2, b2, _mm256_fmadd_pd(c1, b1, _mm256_mul_pd(c0, b0)));
        double* z0 = z + 3 * r;
        double* z1 = z + 9 + 3 * r;
        _mm256_maskstore_pd(z0, m3, _mm256_add_pd(_mm256_maskload_pd(z0, m3), s0));
        _mm256_maskstore_pd(z1, m3, _mm256_add_pd(_mm256_maskload_pd(z1, m3), s1));
    }
}

__attribute__((target("avx2,fma"))) static void mul_add_avx2(double* restrict z, const double* restrict M,
                                                             const double* restrict T) {
    pair_avx2(z, M, T, 0);
}

__attribute__((target("avx2,fma"))) static void tmul_add_avx2(double* restrict z, const double* restrict M,
                                                              const double* restrict T) {
    pair_avx2(z, M, T, 1);
}

wc_pair_kernels wc_pair_kernels_vector(void) {
    wc_pair_kernels k = {NULL, NULL};
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        k.mul_add = mul_add_avx2;
        k.tmul_add = tmul_add_avx2;
    }
    return k;
}
#else
wc_pair_kernels wc_pair_kernels_vector(void) {
    wc_pair_kernels k = {NULL, NULL};
    return k;
}
#endif

wc_pair_kernels wc_pair_kernels_get(void) {
    wc_pair_kernels v = wc_pair_kernels_vector();
    return v.mul_add ? v : wc_pair_kernels_scalar();
}
