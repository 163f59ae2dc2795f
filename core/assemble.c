/* Backward-Euler system assembly by rows (formulas in assemble.h). Row i only reads its incident
 * springs (pattern.row_spring*) and writes its own blocks and entries, so rows run in parallel
 * without atomics and the result does not depend on the thread count.
 * For a spring with end blocks kx, kv (dF_a/dx_a, dF_a/dv_a) and J = h kv + h^2 kx:
 *   A(i,i) -= J at both ends, A(i,j) += J (since dF_i/dx_j = -dF_i/dx_i),
 *   (dF/dx v)_i = kx (v_i - v_j). */
#include "assemble.h"
#include "vec3.h"

/* A spring's share of row i's right-hand side: f0 += sign f, kv_acc += kx (v_i - v_j). */
static inline void spring_rhs(const wc_spring_eval* e, double sign, const double* vi, const double* vj, double* f0,
                              double* kv_acc) {
    v3_axpy(f0, sign, e->f);
    double dvij[3];
    v3_sub(dvij, vi, vj);
    m3_mulv_add(kv_acc, e->kx, dvij);
}

/* Row i's right-hand side b_i = h (f0 + h kv_acc), and the force f0 where asked. */
static inline void row_rhs(double h, int i, const double* f0, const double* kv_acc, double* b, double* f_total) {
    double* bi = b + 3 * i;
    for (int q = 0; q < 3; ++q) bi[q] = h * (f0[q] + h * kv_acc[q]);
    if (f_total) v3_copy(f_total + 3 * i, f0);
}

/* Row i of the system: the scalar loops. */
static void assemble_row(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                         int i, double* A_val, double* b, double* f_total) {
    const wc_bsr_pattern* p = &m->pattern;
    const wc_spring* sp = m->springs;
    const double h2 = h * h;
    /* clear the row's blocks; the diagonal starts at M */
    for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k) m3_zero(A_val + 9 * k);
    double* D = A_val + 9 * p->diag[i];
    m3_identity(D, m->mass[i]);
    double f0[3], kv_acc[3] = {0, 0, 0};
    v3_copy(f0, f_ext + 3 * i);
    const double* vi = v + 3 * i;
    for (int k = p->row_spring_start[i]; k < p->row_spring_start[i + 1]; ++k) {
        int s = p->row_spring[k];
        const wc_spring_eval* e = se + s;
        int j = p->row_spring_sign[k] > 0 ? sp[s].b : sp[s].a;
        double J[9];
        for (int q = 0; q < 9; ++q) J[q] = h * e->kv[q] + h2 * e->kx[q];
        m3_axpy(D, -1.0, J);
        m3_axpy(A_val + 9 * p->row_spring_block[k], 1.0, J);
        spring_rhs(e, (double)p->row_spring_sign[k], vi, v + 3 * j, f0, kv_acc);
    }
    row_rhs(h, i, f0, kv_acc, b, f_total);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_ASSEMBLE_AVX 1
/* The same 4 doubles at a time (lane 3 unused), products and sums as the scalar loops', no FMA:
 * the same bits. Each spring's J = h kv + h^2 kx and its two block updates (D - J, A_ij + J) on
 * entries 0-3, 4-7, then 8 alone; D - J is D + (-1) J exactly. The right-hand side: f0 += sign f
 * and kv_acc += kx (v_i - v_j) as rows 0, 1, 2 of kx times d_0, d_1, d_2 summed in m3_mulv_add's
 * order, which is its columns because a spring's kx is exactly symmetric (forces.c builds u_r u_q
 * and u_q u_r from the same product). Loads of 4 from a 3-vector stay inside the spring's record
 * (f[3] is kx[0], kx[9] is kv[0]); the particles' vectors are read 3 at a time (the last one's
 * 4th double is past the array). */
__attribute__((target("avx"))) static inline __m256d load3(const double* a) {
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a)), _mm_load_sd(a + 2), 1);
}
__attribute__((target("avx"))) static inline void store3(double* o, __m256d x) {
    _mm_storeu_pd(o, _mm256_castpd256_pd128(x));
    _mm_store_sd(o + 2, _mm256_extractf128_pd(x, 1));
}
__attribute__((target("avx"))) static void assemble_row_avx(const wc_model* m, const wc_spring_eval* se,
                                                           const double* f_ext, const double* v, double h, int i,
                                                           double* A_val, double* b, double* f_total) {
    /* the pattern's arrays in locals: the stores to A_val and b could alias m's fields, which the
       loop would otherwise load again at every spring */
    const wc_bsr_pattern* p = &m->pattern;
    const wc_spring* sp = m->springs;
    const int *row_spring = p->row_spring, *row_block = p->row_spring_block;
    const signed char* row_sign = p->row_spring_sign;
    const int k0 = p->row_spring_start[i], k1 = p->row_spring_start[i + 1];
    const double h2 = h * h;
    const __m256d vh = _mm256_set1_pd(h), vh2 = _mm256_set1_pd(h2), zero = _mm256_setzero_pd();
    for (int k = p->row_start[i], k_end = p->row_start[i + 1]; k < k_end; ++k) {
        double* o = A_val + 9 * (size_t)k;
        _mm256_storeu_pd(o, zero);
        _mm256_storeu_pd(o + 4, zero);
        o[8] = 0.0;
    }
    double* D = A_val + 9 * p->diag[i];
    D[0] = D[4] = D[8] = m->mass[i];
    __m256d f0 = load3(f_ext + 3 * i), kv_acc = zero;
    const double* vi = v + 3 * i;
    for (int k = k0; k < k1; ++k) {
        int s = row_spring[k];
        const wc_spring_eval* e = se + s;
        int j = row_sign[k] > 0 ? sp[s].b : sp[s].a;
        const __m256d j0 = _mm256_add_pd(_mm256_mul_pd(vh, _mm256_loadu_pd(e->kv)), _mm256_mul_pd(vh2, _mm256_loadu_pd(e->kx)));
        const __m256d j1 =
            _mm256_add_pd(_mm256_mul_pd(vh, _mm256_loadu_pd(e->kv + 4)), _mm256_mul_pd(vh2, _mm256_loadu_pd(e->kx + 4)));
        const double j8 = h * e->kv[8] + h2 * e->kx[8];
        _mm256_storeu_pd(D, _mm256_sub_pd(_mm256_loadu_pd(D), j0)); /* in memory, as A_ij: the same */
        _mm256_storeu_pd(D + 4, _mm256_sub_pd(_mm256_loadu_pd(D + 4), j1)); /* order if they were one block */
        D[8] -= j8;
        double* o = A_val + 9 * (size_t)row_block[k];
        _mm256_storeu_pd(o, _mm256_add_pd(_mm256_loadu_pd(o), j0));
        _mm256_storeu_pd(o + 4, _mm256_add_pd(_mm256_loadu_pd(o + 4), j1));
        o[8] += j8;
        const double* vj = v + 3 * j;
        f0 = _mm256_add_pd(f0, _mm256_mul_pd(_mm256_set1_pd((double)row_sign[k]), _mm256_loadu_pd(e->f)));
        const __m256d t = _mm256_add_pd(_mm256_mul_pd(_mm256_loadu_pd(e->kx), _mm256_set1_pd(vi[0] - vj[0])),
                                        _mm256_mul_pd(_mm256_loadu_pd(e->kx + 3), _mm256_set1_pd(vi[1] - vj[1])));
        kv_acc = _mm256_add_pd(kv_acc, _mm256_add_pd(t, _mm256_mul_pd(_mm256_loadu_pd(e->kx + 6), _mm256_set1_pd(vi[2] - vj[2]))));
    }
    /* row_rhs: b_i = h (f0 + h kv_acc) */
    store3(b + 3 * i, _mm256_mul_pd(vh, _mm256_add_pd(f0, _mm256_mul_pd(vh, kv_acc))));
    if (f_total) store3(f_total + 3 * i, f0);
}
#endif

static void assemble(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                     wc_par* par, double* A_val, double* b, double* f_total, int vec) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(m->n_particles, wc_par_tid(), wc_par_nt(), &lo, &hi);
#ifdef WC_ASSEMBLE_AVX
        if (vec)
            for (int i = lo; i < hi; ++i) assemble_row_avx(m, se, f_ext, v, h, i, A_val, b, f_total);
        else
#endif
            for (int i = lo; i < hi; ++i) assemble_row(m, se, f_ext, v, h, i, A_val, b, f_total);
    }
}

void wc_assemble(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                 wc_par* par, double* A_val, double* b, double* f_total) {
#ifdef WC_ASSEMBLE_AVX
    const int vec = __builtin_cpu_supports("avx");
#else
    const int vec = 0;
#endif
    assemble(m, se, f_ext, v, h, par, A_val, b, f_total, vec);
}

void wc_assemble_scalar(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                        wc_par* par, double* A_val, double* b, double* f_total) {
    assemble(m, se, f_ext, v, h, par, A_val, b, f_total, 0);
}
