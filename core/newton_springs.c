/* The incremental potential's spring terms over a range of springs (newton.h,
 * wc_newton_spring_terms): sum over k of k_t w/2 dl^2 - he/2 dv^T D0_k dv, the springs' elastic
 * energy at x(w) and the frozen damping's quadratic term at v(w).
 *
 * The AVX loop computes each spring's 3-vectors 4 doubles at a time (lane 3 unused) with the
 * scalar loop's products and sums in its order, no FMA, so each spring's term has the scalar's
 * bits, and adds the terms in spring order: the same sum. Its two horizontal sums are
 * (p_0 + p_1) + p_2, as v3_dot's. D0 dv is taken by columns (rows 0, 1, 2 of D0 times dv_0,
 * dv_1, dv_2, summed in m3_mulv's order): the same numbers because every D0 block is exactly
 * symmetric (-d u_r u_q builds u_r u_q and u_q u_r from one product; a seam's is -d I). Loads of
 * 4 from a particle's 3-vector read 3 (the last particle's 4th double is past the array); the
 * third row's 4th lane is the next block's first entry (nw_kv0 has one block of padding). */
#include "newton.h"
#include <math.h>
#include "forces.h"
#include "vec3.h"

static double term_scalar(const wc_model* m, const wc_spring* sp, const double* x, const double* vv,
                          const double* kv, double he, double seam_scale) {
    double L[3], dv[3], Kd[3];
    v3_sub(L, x + 3 * sp->a, x + 3 * sp->b);
    double dl = wc_spring_extension(sp, v3_norm(L), seam_scale);
    v3_sub(dv, vv + 3 * sp->a, vv + 3 * sp->b);
    m3_mulv(Kd, kv, dv);
    return 0.5 * m->material.k[sp->type] * sp->w * dl * dl - 0.5 * he * v3_dot(dv, Kd);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_NEWTON_SPRINGS_AVX 1
__attribute__((target("avx"))) static inline __m256d load3(const double* a) {
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a)), _mm_load_sd(a + 2), 1);
}
/* (p_0 + p_1) + p_2 of p = a * b, as v3_dot */
__attribute__((target("avx"))) static inline double dot3(__m256d a, __m256d b) {
    const __m256d p = _mm256_mul_pd(a, b);
    const __m128d lo = _mm256_castpd256_pd128(p);
    const __m128d s01 = _mm_add_sd(lo, _mm_unpackhi_pd(lo, lo));
    return _mm_cvtsd_f64(_mm_add_sd(s01, _mm256_extractf128_pd(p, 1)));
}
__attribute__((target("avx"))) static double terms_avx(const wc_model* m, const double* x, const double* vv,
                                                      const double* kv0, double he, double seam_scale, int lo,
                                                      int hi) {
    const wc_spring* springs = m->springs;
    const double* k = m->material.k;
    const double hhe = 0.5 * he;
    double acc = 0.0;
    for (int s = lo; s < hi; ++s) {
        const wc_spring* sp = &springs[s];
        const double* kv = kv0 + 9 * (size_t)s;
        if (sp->type == WC_SPRING_SEAM) {
            acc += term_scalar(m, sp, x, vv, kv, he, seam_scale);
            continue;
        }
        const int a = sp->a, b = sp->b;
        const __m256d L = _mm256_sub_pd(load3(x + 3 * a), load3(x + 3 * b));
        const double dl = sqrt(dot3(L, L)) - sp->rest;
        const __m256d D = _mm256_sub_pd(load3(vv + 3 * a), load3(vv + 3 * b));
        double dv[4];
        _mm256_storeu_pd(dv, D);
        const __m256d Kd =
            _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(kv), _mm256_broadcast_sd(dv)),
                                        _mm256_mul_pd(_mm256_loadu_pd(kv + 3), _mm256_broadcast_sd(dv + 1))),
                          _mm256_mul_pd(_mm256_loadu_pd(kv + 6), _mm256_broadcast_sd(dv + 2)));
        acc += 0.5 * k[sp->type] * sp->w * dl * dl - hhe * dot3(D, Kd);
    }
    return acc;
}
#endif

double wc_newton_spring_terms(const wc_model* m, const double* x, const double* vv, const double* kv0, double he,
                              double seam_scale, int lo, int hi, int vec) {
#ifdef WC_NEWTON_SPRINGS_AVX
    if (vec && __builtin_cpu_supports("avx")) return terms_avx(m, x, vv, kv0, he, seam_scale, lo, hi);
#else
    (void)vec;
#endif
    double acc = 0.0;
    for (int s = lo; s < hi; ++s) acc += term_scalar(m, &m->springs[s], x, vv, kv0 + 9 * (size_t)s, he, seam_scale);
    return acc;
}
