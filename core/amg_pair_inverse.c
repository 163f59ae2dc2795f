/* The block diagonal's inverses (amg_setup.c's diagonal): 3x3 blocks, and a pair level's 6x6
 * blocks (amg.h, wc_amg_opts.pair_blocks) by Gauss-Jordan with partial pivoting, one matrix at a
 * time or four at once in AVX2 lanes (one matrix a lane, each lane the scalar one's operations in
 * its order: the same bits; docs/bench/amg_setup_scalar.md). */
#include <math.h>
#include <string.h>
#include "amg.h"
#include "vec3.h"

void wc_amg_block_inverse(double* Di, const double* Aii) {
    if (m3_inverse(Di, Aii) == 0.0 || !isfinite(Di[0])) {
        double tr = (Aii[0] + Aii[4] + Aii[8]) / 3.0;
        m3_identity(Di, tr > 0 && isfinite(tr) ? 1.0 / tr : 1.0);
    }
}

int wc_amg_inverse6(double* M) {
    double inv[36] = {0}, scale = 0.0;
    for (int r = 0; r < 6; ++r) {
        inv[7 * r] = 1.0;
        scale = fmax(scale, fabs(M[7 * r]));
    }
    for (int c = 0; c < 6; ++c) {
        int piv = c;
        for (int r = c + 1; r < 6; ++r)
            if (fabs(M[6 * r + c]) > fabs(M[6 * piv + c])) piv = r;
        if (!(fabs(M[6 * piv + c]) > 1e-13 * scale)) return 0;
        if (piv != c)
            for (int q = 0; q < 6; ++q) {
                double t = M[6 * c + q];
                M[6 * c + q] = M[6 * piv + q];
                M[6 * piv + q] = t;
                t = inv[6 * c + q];
                inv[6 * c + q] = inv[6 * piv + q];
                inv[6 * piv + q] = t;
            }
        double d = 1.0 / M[6 * c + c];
        for (int q = 0; q < 6; ++q) {
            M[6 * c + q] *= d;
            inv[6 * c + q] *= d;
        }
        for (int r = 0; r < 6; ++r) {
            if (r == c || M[6 * r + c] == 0.0) continue;
            double f = M[6 * r + c];
            for (int q = 0; q < 6; ++q) {
                M[6 * r + q] -= f * M[6 * c + q];
                inv[6 * r + q] -= f * inv[6 * c + q];
            }
        }
    }
    for (int q = 0; q < 36; ++q)
        if (!isfinite(inv[q])) return 0;
    memcpy(M, inv, sizeof inv);
    return 1;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

int wc_amg_inverse6_vec(void) { return __builtin_cpu_supports("avx2"); }

/* wc_amg_inverse6 per lane. Differences that change no bit of a lane's result: M's columns left of
 * the pivot column are neither swapped nor updated (no later step reads them: the pivots and the
 * factors come from columns c' > c); a lane's skipped row update (its factor exactly 0) is computed
 * and then blended away; a lane past a failed pivot computes on and is reported failed. */
__attribute__((target("avx2"))) unsigned wc_amg_inverse6_x4(double* M) {
    __m256d m[36], inv[36];
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
    const __m256d absmask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7fffffffffffffffLL));
    __m256d scale = zero, bad = zero;
    for (int k = 0; k < 36; ++k) {
        m[k] = _mm256_loadu_pd(M + 4 * k);
        inv[k] = k % 7 == 0 ? one : zero;
    }
    /* fmax(scale, |M_rr|): MAXPD returns its second operand when the first is NaN */
    for (int r = 0; r < 6; ++r) scale = _mm256_max_pd(_mm256_and_pd(m[7 * r], absmask), scale);
    const __m256d tiny = _mm256_mul_pd(_mm256_set1_pd(1e-13), scale);
    for (int c = 0; c < 6; ++c) {
        __m256d best = _mm256_and_pd(m[6 * c + c], absmask), piv = _mm256_set1_pd(c);
        for (int r = c + 1; r < 6; ++r) {
            const __m256d a = _mm256_and_pd(m[6 * r + c], absmask), gt = _mm256_cmp_pd(a, best, _CMP_GT_OQ);
            best = _mm256_blendv_pd(best, a, gt);
            piv = _mm256_blendv_pd(piv, _mm256_set1_pd(r), gt);
        }
        bad = _mm256_or_pd(bad, _mm256_cmp_pd(best, tiny, _CMP_NGT_UQ));
        for (int r = c + 1; r < 6; ++r) {
            const __m256d sw = _mm256_cmp_pd(piv, _mm256_set1_pd(r), _CMP_EQ_OQ);
            if (_mm256_testz_pd(sw, sw)) continue;
            for (int q = c; q < 6; ++q) {
                const __m256d t = m[6 * c + q];
                m[6 * c + q] = _mm256_blendv_pd(t, m[6 * r + q], sw);
                m[6 * r + q] = _mm256_blendv_pd(m[6 * r + q], t, sw);
            }
            for (int q = 0; q < 6; ++q) {
                const __m256d t = inv[6 * c + q];
                inv[6 * c + q] = _mm256_blendv_pd(t, inv[6 * r + q], sw);
                inv[6 * r + q] = _mm256_blendv_pd(inv[6 * r + q], t, sw);
            }
        }
        const __m256d d = _mm256_div_pd(one, m[6 * c + c]);
        for (int q = c; q < 6; ++q) m[6 * c + q] = _mm256_mul_pd(m[6 * c + q], d);
        for (int q = 0; q < 6; ++q) inv[6 * c + q] = _mm256_mul_pd(inv[6 * c + q], d);
        for (int r = 0; r < 6; ++r) {
            if (r == c) continue;
            const __m256d f = m[6 * r + c], live = _mm256_cmp_pd(f, zero, _CMP_NEQ_UQ);
            if (_mm256_testz_pd(live, live)) continue;
            for (int q = c + 1; q < 6; ++q)
                m[6 * r + q] = _mm256_blendv_pd(m[6 * r + q], _mm256_sub_pd(m[6 * r + q], _mm256_mul_pd(f, m[6 * c + q])), live);
            for (int q = 0; q < 6; ++q)
                inv[6 * r + q] = _mm256_blendv_pd(inv[6 * r + q], _mm256_sub_pd(inv[6 * r + q], _mm256_mul_pd(f, inv[6 * c + q])), live);
        }
    }
    /* isfinite: |x| <= DBL_MAX (false for inf and NaN) */
    const __m256d big = _mm256_set1_pd(1.7976931348623157e308);
    for (int k = 0; k < 36; ++k) {
        bad = _mm256_or_pd(bad, _mm256_cmp_pd(_mm256_and_pd(inv[k], absmask), big, _CMP_NLE_UQ));
        _mm256_storeu_pd(M + 4 * k, inv[k]);
    }
    return ~(unsigned)_mm256_movemask_pd(bad) & 15u;
}
#else
int wc_amg_inverse6_vec(void) { return 0; }
unsigned wc_amg_inverse6_x4(double* M) {
    unsigned ok = 0;
    for (int l = 0; l < 4; ++l) {
        double one[36];
        for (int k = 0; k < 36; ++k) one[k] = M[4 * k + l];
        if (wc_amg_inverse6(one)) ok |= 1u << l;
        for (int k = 0; k < 36; ++k) M[4 * k + l] = one[k];
    }
    return ok;
}
#endif

/* Pair a's 6x6 block (B plus the couplings' part, or + 0.0 without couplings), into lane l of
 * the lane-interleaved M (M[4 k + l]; lanes 1: M[k]). */
static void pair_block(const wc_amg_level* L, const double* cross, int a, double* M, int lanes, int l) {
    const int i0 = 2 * a, i1 = 2 * a + 1;
    const double* B[2][2] = {{L->val + 9 * (size_t)L->diag[i0], L->val + 9 * (size_t)L->pair_blk[i0]},
                             {L->val + 9 * (size_t)L->pair_blk[i1], L->val + 9 * (size_t)L->diag[i1]}};
    for (int p = 0; p < 2; ++p)
        for (int q = 0; q < 2; ++q)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    M[lanes * (6 * (3 * p + r) + 3 * q + c) + l] =
                        B[p][q][3 * r + c] + (cross ? cross[18 * (size_t)(i0 + p) + 9 * q + 3 * r + c] : 0.0);
}

/* Pair a's D^-1 rows from lane l of the inverse M (ok), else its two 3x3 inverses. */
static void pair_store(wc_amg_level* L, int a, const double* M, int lanes, int l, int ok) {
    const int i0 = 2 * a;
    double* D0 = L->Dinv + 18 * (size_t)i0; /* node i0's rows: [to i0 | to i1], then i1's */
    if (ok) {
        for (int p = 0; p < 2; ++p)
            for (int q = 0; q < 2; ++q)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c)
                        D0[18 * p + 9 * q + 3 * r + c] = M[lanes * (6 * (3 * p + r) + 3 * q + c) + l];
        return;
    }
    memset(D0, 0, 36 * sizeof(double));
    wc_amg_block_inverse(D0, L->val + 9 * (size_t)L->diag[i0]);
    wc_amg_block_inverse(D0 + 27, L->val + 9 * (size_t)L->diag[i0 + 1]);
}

void wc_amg_pair_inverses(wc_amg_level* L, const double* cross, int pair_blocks, int vec, int lo, int hi) {
    int a = lo;
    if (pair_blocks && vec)
        for (; a + 4 <= hi; a += 4) {
            double M[4 * 36];
            for (int l = 0; l < 4; ++l) pair_block(L, cross, a + l, M, 4, l);
            const unsigned ok = wc_amg_inverse6_x4(M);
            for (int l = 0; l < 4; ++l) pair_store(L, a + l, M, 4, l, (ok >> l) & 1u);
        }
    for (; a < hi; ++a) {
        double M[36];
        pair_block(L, cross, a, M, 1, 0);
        pair_store(L, a, M, 1, 0, pair_blocks && wc_amg_inverse6(M));
    }
}
