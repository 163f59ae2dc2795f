/* The multigrid setup's innermost product on rotation levels (two coarse nodes per aggregate, so
 * P's, T's and the coarse rows hold pairs of 3x3 blocks): z += M [T0 T1] or z += M^T [T0 T1],
 * z and T each two consecutive row-major 3x3 blocks (18 doubles), M one 3x3 block. It serves
 * T = A P, the next level's P^T T and the prolongator's A P_tent.
 * On x86-64 CPUs with AVX2 and FMA a vector version (each block row in one register), chosen
 * once at run time; elsewhere the scalar 3x3 products. The two round differently (fused
 * multiply-adds). */
#ifndef WEFT_CORE_BLOCK_PAIR_H
#define WEFT_CORE_BLOCK_PAIR_H

/* o += a^T b (3x3, row-major; o may not alias a or b: restrict lets the compiler keep a and b in
 * registers in registers) */
static inline void m3_tmul_add(double* restrict o, const double* restrict a, const double* restrict b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) o[3 * r + c] += a[r] * b[c] + a[3 + r] * b[3 + c] + a[6 + r] * b[6 + c];
}

/* o += a b (o may not alias a or b) */
static inline void m3_mul_add(double* restrict o, const double* restrict a, const double* restrict b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            o[3 * r + c] += a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}

typedef void (*wc_pair_fn)(double* restrict z, const double* restrict M, const double* restrict T);

typedef struct wc_pair_kernels {
    wc_pair_fn mul_add;  /* z += M [T0 T1] */
    wc_pair_fn tmul_add; /* z += M^T [T0 T1] */
} wc_pair_kernels;

/* The kernels for this CPU (the vector ones where it has AVX2 and FMA). */
wc_pair_kernels wc_pair_kernels_get(void);
/* By name, for tests: the scalar ones, and the vector ones (NULL members where none). */
wc_pair_kernels wc_pair_kernels_scalar(void);
wc_pair_kernels wc_pair_kernels_vector(void);

#endif
