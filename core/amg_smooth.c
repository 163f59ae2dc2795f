/* The Chebyshev smoother's node updates (amg_cycle.c chebyshev_part) in AVX2: each node's
 * D^-1 t from its block inverse's padded columns (wc_amg_level.DinvT), then d and x, in the scalar
 * loops' operations and order, with no fused multiply-add: the same bits (tests/test_amg_smooth.c).
 * The scalar loops spent about 60 instructions a node on level 0 (m3_mulv, three lanes one at a
 * time), about 9 % of the suit's step. */
#include "amg.h"

#include <string.h>

/* DinvT's rows [lo, hi) from Dinv: each 3x3 block by columns, a column per 4 doubles, lane 3 zero
 * (group 2: node i's two blocks, to i & ~1 and i | 1, one after the other). */
void wc_amg_dinv_columns(wc_amg_level* L, int lo, int hi) {
    if (!L->DinvT) return;
    const int g = L->group;
    for (int i = lo; i < hi; ++i)
        for (int q = 0; q < g; ++q) {
            const double* m = L->Dinv + 9 * ((size_t)g * i + q);
            double* c = L->DinvT + 12 * ((size_t)g * i + q);
            for (int j = 0; j < 3; ++j) {
                c[4 * j] = m[j];
                c[4 * j + 1] = m[3 + j];
                c[4 * j + 2] = m[6 + j];
                c[4 * j + 3] = 0.0;
            }
        }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

/* m3_mulv from the padded columns c: (c0 v0 + c1 v1) + c2 v2 per lane, m3_mulv's order. */
__attribute__((target("avx2"), always_inline)) static inline __m256d cols_times(const double* c, const double* v) {
    const __m256d p0 = _mm256_mul_pd(_mm256_loadu_pd(c), _mm256_broadcast_sd(v));
    const __m256d p1 = _mm256_mul_pd(_mm256_loadu_pd(c + 4), _mm256_broadcast_sd(v + 1));
    const __m256d p2 = _mm256_mul_pd(_mm256_loadu_pd(c + 8), _mm256_broadcast_sd(v + 2));
    return _mm256_add_pd(_mm256_add_pd(p0, p1), p2);
}

/* wc_amg_dinv's (D^-1 t)_i: group 2 is m3_mulv then m3_mulv_add, o + (the second product). */
__attribute__((target("avx2"), always_inline)) static inline __m256d dinv_node(const double* DT, int g, int i,
                                                                              const double* t) {
    if (g == 1) return cols_times(DT + 12 * (size_t)i, t + 3 * (size_t)i);
    const int b = i & ~1;
    const double* c = DT + 24 * (size_t)i;
    return _mm256_add_pd(cols_times(c, t + 3 * (size_t)b), cols_times(c + 12, t + 3 * (size_t)b + 3));
}

/* Three doubles in and out of a register's lanes 0-2 (lane 3 zero on the way in): two plain
 * accesses each, not the masked moves, whose stores AMD's cores run as a slow sequence. */
__attribute__((target("avx2"), always_inline)) static inline __m256d load3(const double* p) {
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(p)), _mm_load_sd(p + 2), 1);
}
__attribute__((target("avx2"), always_inline)) static inline void store3(double* p, __m256d v) {
    _mm_storeu_pd(p, _mm256_castpd256_pd128(v));
    _mm_store_sd(p + 2, _mm256_extractf128_pd(v, 1));
}

/* The loop for one group and mode (constants once inlined: no tests in the loop). */
__attribute__((target("avx2"), always_inline)) static inline void nodes_body(const double* DT, int g, int mode,
                                                                            const double* t, double* d, double* x,
                                                                            float* xf, int lo, int hi, double c1,
                                                                            double c2) {
    const __m256d vc1 = _mm256_set1_pd(c1), vc2 = _mm256_set1_pd(c2);
    for (int i = lo; i < hi; ++i) {
        const __m256d e = dinv_node(DT, g, i, t);
        double* di = d + 3 * (size_t)i;
        double* xi = x + 3 * (size_t)i;
        __m256d dc, xn;
        if (mode == 2) dc = _mm256_add_pd(_mm256_mul_pd(vc1, load3(di)), _mm256_mul_pd(vc2, e));
        else dc = _mm256_mul_pd(e, vc2);
        store3(di, dc);
        xn = mode == 0 ? dc : _mm256_add_pd(load3(xi), dc);
        store3(xi, xn);
        if (xf) _mm_storeu_ps(xf + 4 * (size_t)i, _mm_blend_ps(_mm256_cvtpd_ps(xn), _mm_setzero_ps(), 8));
    }
}

/* The first step (mode 0: x = d, 1: x += d, with d = D^-1 t c2) or a later one (mode 2:
 * d = c1 d + c2 D^-1 t; x += d) on nodes [lo, hi); xf (or NULL): x's float shadow, 4th float 0. */
__attribute__((target("avx2"))) static void cheb_nodes_avx2(const wc_amg_level* L, const double* t, double* d,
                                                          double* x, float* xf, int lo, int hi, double c1,
                                                          double c2, int mode) {
    const double* DT = L->DinvT;
    if (L->group == 1) {
        if (mode == 0) nodes_body(DT, 1, 0, t, d, x, xf, lo, hi, c1, c2);
        else if (mode == 1) nodes_body(DT, 1, 1, t, d, x, xf, lo, hi, c1, c2);
        else nodes_body(DT, 1, 2, t, d, x, xf, lo, hi, c1, c2);
    } else {
        if (mode == 0) nodes_body(DT, 2, 0, t, d, x, xf, lo, hi, c1, c2);
        else if (mode == 1) nodes_body(DT, 2, 1, t, d, x, xf, lo, hi, c1, c2);
        else nodes_body(DT, 2, 2, t, d, x, xf, lo, hi, c1, c2);
    }
}

wc_amg_cheb_nodes_fn wc_amg_cheb_nodes_kernel(void) {
    return __builtin_cpu_supports("avx2") ? cheb_nodes_avx2 : NULL;
}
#else
wc_amg_cheb_nodes_fn wc_amg_cheb_nodes_kernel(void) { return NULL; }
#endif
