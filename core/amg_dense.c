/* The coarsest level's dense Cholesky factor and its solve (amg.h, wc_amg.coarse_L).
 *
 * The factor is stored transposed, as U = L^T in the upper triangle of a row-major d x d array
 * (M[k * d + i] = L[i][k], i >= k), so that the column of L that step j computes, and the
 * columns k < j that it reads, are contiguous rows. Column j's entries are then computed for
 * many rows i at once (AVX, four lanes a register, sixteen a block), each lane still doing the
 * scalar recurrence
 *
 *     t = A[i][j];  for k = 0 .. j - 1: t -= L[i][k] * L[j][k];  L[i][j] = t / L[j][j]
 *
 * in the same order, with a separate multiply and subtract (no fused multiply-add), so the AVX
 * and scalar paths give the same bits as each other and as the row-major factor this replaced
 * (tests/test_amg_dense.c). The forward solve likewise runs over rows in blocks; the backward
 * solve is a row of U per unknown, a scalar sum in the original order. On the 16 x 16 sheet
 * (72 coarse nodes, 216 unknowns) the factor was 78 % of a setup's time in the row-major form
 * (docs/bench/cpu_levers_sheet32.md). */
#include <immintrin.h>
#include <math.h>
#include "amg.h"

int wc_amg_dense_vec(void) { return __builtin_cpu_supports("avx"); }

/* t[ii] -= U[k][i0 + ii] * b_k for k in [k0, k1), ii in [0, w): rows i0 .. i0 + w - 1 */
static void block_scalar(const double* M, int d, int i0, int w, int k0, int k1, const double* b, double* t) {
    for (int ii = 0; ii < w; ++ii) {
        double s = t[ii];
        for (int k = k0; k < k1; ++k) s -= M[(size_t)k * d + i0 + ii] * b[k];
        t[ii] = s;
    }
}

/* the same for w = 16, four AVX registers of accumulators; b[k] at stride bs */
__attribute__((target("avx"))) static void block16_avx(const double* M, int d, int i0, int k0, int k1, const double* b,
                                                       size_t bs, double* t) {
    __m256d a0 = _mm256_loadu_pd(t), a1 = _mm256_loadu_pd(t + 4), a2 = _mm256_loadu_pd(t + 8),
            a3 = _mm256_loadu_pd(t + 12);
    for (int k = k0; k < k1; ++k) {
        const double* u = M + (size_t)k * d + i0;
        const __m256d bk = _mm256_broadcast_sd(b + (size_t)k * bs);
        __m256d p0 = _mm256_mul_pd(_mm256_loadu_pd(u), bk);
        __m256d p1 = _mm256_mul_pd(_mm256_loadu_pd(u + 4), bk);
        __m256d p2 = _mm256_mul_pd(_mm256_loadu_pd(u + 8), bk);
        __m256d p3 = _mm256_mul_pd(_mm256_loadu_pd(u + 12), bk);
        a0 = _mm256_sub_pd(a0, p0);
        a1 = _mm256_sub_pd(a1, p1);
        a2 = _mm256_sub_pd(a2, p2);
        a3 = _mm256_sub_pd(a3, p3);
    }
    _mm256_storeu_pd(t, a0);
    _mm256_storeu_pd(t + 4, a1);
    _mm256_storeu_pd(t + 8, a2);
    _mm256_storeu_pd(t + 12, a3);
}

/* the same for w = 4, one register */
__attribute__((target("avx"))) static void block4_avx(const double* M, int d, int i0, int k0, int k1, const double* b,
                                                      size_t bs, double* t) {
    __m256d a0 = _mm256_loadu_pd(t);
    for (int k = k0; k < k1; ++k) {
        const __m256d p0 = _mm256_mul_pd(_mm256_loadu_pd(M + (size_t)k * d + i0), _mm256_broadcast_sd(b + (size_t)k * bs));
        a0 = _mm256_sub_pd(a0, p0);
    }
    _mm256_storeu_pd(t, a0);
}

/* t[0 .. w) -= sum over k in [k0, k1) of U[k][i0 ..] * b[k * bs], each lane in ascending k */
static void block_update(const double* M, int d, int i0, int w, int k0, int k1, const double* b, size_t bs, double* t,
                         int vec) {
    int done = 0;
    if (vec && w == 16) {
        block16_avx(M, d, i0, k0, k1, b, bs, t);
        return;
    }
    if (vec)
        for (; done + 4 <= w; done += 4) block4_avx(M, d, i0 + done, k0, k1, b, bs, t + done);
    for (int ii = done; ii < w; ++ii) {
        double s = t[ii];
        for (int k = k0; k < k1; ++k) s -= M[(size_t)k * d + i0 + ii] * b[(size_t)k * bs];
        t[ii] = s;
    }
}

void wc_amg_dense_factor(double* M, int d, int vec) {
    double scale = 0.0;
    for (int i = 0; i < d; ++i) scale = fmax(scale, fabs(M[(size_t)i * d + i]));
    for (int i = 1; i < d; ++i) /* the lower triangle is the operator: copy it into the upper */
        for (int j = 0; j < i; ++j) M[(size_t)j * d + i] = M[(size_t)i * d + j];
    for (int j = 0; j < d; ++j) {
        double* Uj = M + (size_t)j * d; /* row j of U: column j of L */
        double s = Uj[j];
        for (int k = 0; k < j; ++k) s -= M[(size_t)k * d + j] * M[(size_t)k * d + j];
        if (!(s > 1e-14 * scale)) { /* decouple the unknown: its row and column of L */
            for (int k = 0; k < j; ++k) M[(size_t)k * d + j] = 0.0;
            s = 1.0;
            for (int i = j + 1; i < d; ++i) Uj[i] = 0.0;
        }
        const double ljj = sqrt(s);
        Uj[j] = ljj;
        /* column j below the diagonal: L[i][j] = (A[i][j] - sum_k L[i][k] L[j][k]) / L[j][j], the
         * multipliers L[j][k] = M[k * d + j] at stride d */
        for (int i0 = j + 1; i0 < d; i0 += 16) {
            const int w = d - i0 < 16 ? d - i0 : 16;
            double* t = Uj + i0;
            block_update(M, d, i0, w, 0, j, M + j, (size_t)d, t, vec);
            for (int ii = 0; ii < w; ++ii) t[ii] /= ljj;
        }
    }
}

void wc_amg_dense_solve(const double* M, int d, const double* r, double* y, double* x, int vec) {
    /* L y = r: y_i = (r_i - sum_{k < i} L[i][k] y_k) / L[i][i], k ascending; by blocks of 16
     * rows, the columns before the block at once, then the block's triangle */
    for (int i0 = 0; i0 < d; i0 += 16) {
        const int w = d - i0 < 16 ? d - i0 : 16;
        double t[16];
        for (int ii = 0; ii < w; ++ii) t[ii] = r[i0 + ii];
        block_update(M, d, i0, w, 0, i0, y, 1, t, vec);
        for (int ii = 0; ii < w; ++ii) {
            const int i = i0 + ii;
            block_scalar(M, d, i, 1, i0, i, y, t + ii);
            y[i] = t[ii] / M[(size_t)i * d + i];
        }
    }
    /* L^T x = y: x_i = (y_i - sum_{k > i} L[k][i] x_k) / L[i][i], k ascending: row i of U */
    for (int i = d - 1; i >= 0; --i) {
        const double* Ui = M + (size_t)i * d;
        double s = y[i];
        for (int k = i + 1; k < d; ++k) s -= Ui[k] * x[k];
        x[i] = s / Ui[i];
    }
}
