/* The pair levels' setup products in single precision (amg.h, wc_amg_opts.single_setup): the
 * smoothed prolongator P = (I - w D^-1 A_F) P_tent, T = A P and the next level's operator P^T T,
 * from the V-cycle's float copies of A (level 0's rounded first, the coarse levels' made here),
 * P_tent's (tent_f, rounded by each QR) and D^-1 rounded as read, summed in float with 8-lane
 * FMAs. The V-cycle's float P and next-level operator are made directly; their double values
 * (what the cross restriction, the block diagonals, the eigenvalue estimates and the coarsest
 * factor read) are their widenings: no double products and no rounding pass. The products run
 * over the gather lists of amg_build.c (pr_*, ap_*, ptap_*), as amg_setup.c's double ones do.
 * Any P gives an SPD Galerkin operator when the V-cycle prolongs and restricts with that same P
 * (it does: p_val_f), so P's rounding only moves the coarse space a little.
 * Symmetry: P^T T is computed for the blocks (I, J) with J >= I & ~1 only, the others are the
 * transposes of those, and each pair's own 6x6 block (I, I + 1 of pair I / 2) is made symmetric
 * from its upper triangle, so the float operator is exactly symmetric: the V-cycle stays one
 * symmetric operator (its rounding is the float copies' already; docs/bench/amg_setup_float.md).
 * Layout in registers: one 8-float register per row r of a slot pair's two blocks, (block 0's row
 * r, 1 float of junk, block 1's row r, 1 of junk); each 3-float row of a block is loaded as 4 floats
 * (the 4th the next row's first, the next block's, or the arrays' padding: WC_BSR_F_PAD), and the
 * stores go in row order so that each junk float is overwritten by the next row's store, the last
 * row of a slot pair masked (its 4th float is another slot's, maybe another thread's). */
#include <string.h>
#include "amg.h"
#include "bsr_rows.h"
#include "clock.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

/* row q of a slot pair's two blocks at B (B[3q..], B[9 + 3q..]) in one register */
#define WC_F_ROWS(B, q) _mm256_loadu2_m128((B) + 9 + 3 * (q), (B) + 3 * (q))

/* a slot pair's three row registers to o (18 floats): block 0's rows, then block 1's, the last
 * masked */
__attribute__((target("avx2,fma"), always_inline)) static inline void pair_store_f(float* o, const __m256* z) {
    for (int r = 0; r < 3; ++r) _mm_storeu_ps(o + 3 * r, _mm256_castps256_ps128(z[r]));
    _mm_storeu_ps(o + 9, _mm256_extractf128_ps(z[0], 1));
    _mm_storeu_ps(o + 12, _mm256_extractf128_ps(z[1], 1));
    _mm_maskstore_ps(o + 15, _mm_setr_epi32(-1, -1, -1, 0), _mm256_extractf128_ps(z[2], 1));
}

/* z[r] += A's row r times [P0 P1] (A: 3x3 row-major, X: P's rows as WC_F_ROWS) */
#define WC_F_AP(z, A, x)                                                                           \
    for (int r = 0; r < 3; ++r) {                                                                  \
        z[r] = _mm256_fmadd_ps(_mm256_broadcast_ss((A) + 3 * r), x[0], z[r]);                      \
        z[r] = _mm256_fmadd_ps(_mm256_broadcast_ss((A) + 3 * r + 1), x[1], z[r]);                  \
        z[r] = _mm256_fmadd_ps(_mm256_broadcast_ss((A) + 3 * r + 2), x[2], z[r]);                  \
    }

/* T's rows lo..hi-1, the slots P^T T reads: (i, 2c), (i, 2c + 1) = sum A_ij P(j, c), two products
 * at a time into two sets of accumulators (two FMA latency chains), added at the end. */
__attribute__((target("avx2,fma"))) static void ap_rows_f(wc_amg_level* L, int lo, int hi) {
    const float *A0 = L->val_f, *P0 = L->p_val_f;
    for (int i = lo; i < hi; ++i)
        for (int s = L->t_read[i]; s < L->t_start[i + 1]; s += 2) {
            __m256 z[3], w[3];
            for (int r = 0; r < 3; ++r) z[r] = w[r] = _mm256_setzero_ps();
            int m = L->ap_start[s / 2];
            const int end = L->ap_start[s / 2 + 1];
            for (; m + 1 < end; m += 2) {
                const float* A = A0 + 9 * (size_t)L->ap_src[2 * m];
                const float* P = P0 + 9 * (size_t)L->ap_src[2 * m + 1];
                const float* B = A0 + 9 * (size_t)L->ap_src[2 * m + 2];
                const float* Q = P0 + 9 * (size_t)L->ap_src[2 * m + 3];
                const __m256 x[3] = {WC_F_ROWS(P, 0), WC_F_ROWS(P, 1), WC_F_ROWS(P, 2)};
                WC_F_AP(z, A, x);
                const __m256 y[3] = {WC_F_ROWS(Q, 0), WC_F_ROWS(Q, 1), WC_F_ROWS(Q, 2)};
                WC_F_AP(w, B, y);
            }
            if (m < end) {
                const float* A = A0 + 9 * (size_t)L->ap_src[2 * m];
                const float* P = P0 + 9 * (size_t)L->ap_src[2 * m + 1];
                const __m256 x[3] = {WC_F_ROWS(P, 0), WC_F_ROWS(P, 1), WC_F_ROWS(P, 2)};
                WC_F_AP(z, A, x);
            }
            for (int r = 0; r < 3; ++r) z[r] = _mm256_add_ps(z[r], w[r]);
            pair_store_f(L->t_val_f + 9 * (size_t)s, z);
        }
}

/* The next level's rows 2a, 2a + 1 for pairs lo..hi-1, blocks (I, J), J >= I = 2a: row I + h's slot
 * pair at J += P(i, I + h)^T [T(i, J) T(i, J + 1)] over P^T's rows i (ptap_* lists). */
__attribute__((target("avx2,fma"))) static void ptap_rows_f(const wc_amg_level* L, wc_amg_level* N, int lo, int hi) {
    for (int a = lo; a < hi; ++a) {
        const int I = 2 * a, c0 = N->row_start[I], d0 = N->row_start[I + 1];
        int s0 = c0;
        while (N->col[s0] < I) ++s0;
        for (int s = s0; s < d0; s += 2) {
            __m256 z[2][3];
            for (int r = 0; r < 3; ++r) z[0][r] = z[1][r] = _mm256_setzero_ps();
            for (int m = L->ptap_start[s / 2]; m < L->ptap_start[s / 2 + 1]; ++m) {
                const float* P = L->p_val_f + 9 * (size_t)L->ptap_src[2 * m]; /* P(i, I), P(i, I + 1) */
                const float* T = L->t_val_f + 9 * (size_t)L->ptap_src[2 * m + 1];
                const __m256 x[3] = {WC_F_ROWS(T, 0), WC_F_ROWS(T, 1), WC_F_ROWS(T, 2)};
                for (int h = 0; h < 2; ++h)
                    for (int r = 0; r < 3; ++r) /* row r of P_h^T: column r of P_h */
                        for (int q = 0; q < 3; ++q)
                            z[h][r] = _mm256_fmadd_ps(_mm256_broadcast_ss(P + 9 * h + 3 * q + r), x[q], z[h][r]);
            }
            pair_store_f(N->val_f + 9 * (size_t)s, z[0]);
            pair_store_f(N->val_f + 9 * (size_t)(s - c0 + d0), z[1]);
        }
    }
}

/* Pairs lo..hi-1 of N: the blocks left of the pair's columns as the transposes of their mirror
 * blocks (written by ptap_rows_f for other pairs; N->mirror, built with the pattern), the pair's
 * 6x6 block symmetric from its upper triangle, then the rows widened into N->val. */
__attribute__((target("avx2,fma"))) static void mirror_widen(wc_amg_level* N, int lo, int hi) {
    float* V = N->val_f;
    for (int I = 2 * lo; I < 2 * hi; ++I)
        for (int slot = N->row_start[I]; slot < N->row_start[I + 1] && N->col[slot] < (I & ~1); ++slot) {
            const float* src = V + 9 * (size_t)N->mirror[slot];
            float* dst = V + 9 * (size_t)slot;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) dst[3 * r + c] = src[3 * c + r];
        }
    for (int a = lo; a < hi; ++a) {
        const int I = 2 * a;
        float* B[2][2] = {{V + 9 * (size_t)N->diag[I], V + 9 * (size_t)N->pair_blk[I]},
                          {V + 9 * (size_t)N->pair_blk[I + 1], V + 9 * (size_t)N->diag[I + 1]}};
        for (int u = 0; u < 6; ++u)     /* row u of the 6x6 */
            for (int v = 0; v < u; ++v) /* (u, v) = (v, u) */
                B[u / 3][v / 3][3 * (u % 3) + v % 3] = B[v / 3][u / 3][3 * (v % 3) + u % 3];
    }
    const size_t k0 = 9 * (size_t)N->row_start[2 * lo], k1 = 9 * (size_t)N->row_start[2 * hi];
    size_t k = k0;
    for (; k + 4 <= k1; k += 4) _mm256_storeu_pd(N->val + k, _mm256_cvtps_pd(_mm_loadu_ps(V + k)));
    for (; k < k1; ++k) N->val[k] = (double)V[k];
}

/* The smoothed prolongator's units (aggregates' rows: L->group of them) lo..hi-1 in float (amg_setup.c's
 * WC_PROLONG_ROWS, the same formula): per entry pair e of row i, Z = sum A_ik P_tent(k) over the
 * strong blocks k of pr_src (and the weak blocks' sum times P_tent(i) on the row's own pair), then
 * P_e = -w D^-1 Z (D^-1 couples a pair's two rows, which share their columns) + P_tent on the
 * own pair, into p_val_f, and p_val its widening. */
__attribute__((target("avx2,fma"))) static void prolong_rows_f(wc_amg_level* L, float w, int lo, int hi) {
    const float* A0 = L->val_f;
    const int g = L->group;
    for (int u = lo; u < hi; ++u) {
        const int b = g * u, len = L->p_start[b + 1] - L->p_start[b];
        float Wk[2][9] = {{0}}, D[2][2][9]; /* the weak blocks' sums; -w D^-1's blocks (row i, block j) */
        int weak[2] = {0, 0};
        for (int i = b; i < b + g; ++i) {
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
                if (L->a_to_p[k] < 0) {
                    for (int q = 0; q < 9; ++q) Wk[i - b][q] += A0[9 * (size_t)k + q];
                    weak[i - b] = 1;
                }
            for (int j = 0; j < g; ++j)
                for (int q = 0; q < 9; ++q) D[i - b][j][q] = (float)(-(double)w * L->Dinv[9 * (size_t)g * i + 9 * j + q]);
        }
        for (int off = 0; off < len; off += 2) {
            __m256 Z[2][3];
            for (int i = b; i < b + g; ++i) {
                const int e = L->p_start[i] + off;
                __m256* z = Z[i - b];
                for (int r = 0; r < 3; ++r) z[r] = _mm256_setzero_ps();
                for (int m = L->pr_start[e / 2]; m < L->pr_start[e / 2 + 1]; ++m) {
                    const int k = L->pr_src[m];
                    const float* A = A0 + 9 * (size_t)k;
                    const float* T = L->tent_f + 18 * (size_t)L->col[k];
                    const __m256 x[3] = {WC_F_ROWS(T, 0), WC_F_ROWS(T, 1), WC_F_ROWS(T, 2)};
                    WC_F_AP(z, A, x);
                }
                if (weak[i - b] && e == L->p_self[i]) {
                    const float* T = L->tent_f + 18 * (size_t)i;
                    const __m256 x[3] = {WC_F_ROWS(T, 0), WC_F_ROWS(T, 1), WC_F_ROWS(T, 2)};
                    WC_F_AP(z, Wk[i - b], x);
                }
            }
            for (int i = b; i < b + g; ++i) { /* rows r of [P_e P_e+1] = sum_j (-w D_ij) rows of Z_j */
                const int e = L->p_start[i] + off;
                __m256 o[3];
                for (int r = 0; r < 3; ++r) o[r] = _mm256_setzero_ps();
                for (int j = 0; j < g; ++j) WC_F_AP(o, D[i - b][j], Z[j]);
                if (e == L->p_self[i]) {
                    const float* T = L->tent_f + 18 * (size_t)i;
                    for (int r = 0; r < 3; ++r) o[r] = _mm256_add_ps(o[r], WC_F_ROWS(T, r));
                }
                pair_store_f(L->p_val_f + 9 * (size_t)e, o);
            }
        }
        const size_t k0 = 9 * (size_t)L->p_start[b], k1 = 9 * (size_t)L->p_start[b + g];
        size_t k = k0;
        for (; k + 4 <= k1; k += 4) _mm256_storeu_pd(L->p_val + k, _mm256_cvtps_pd(_mm_loadu_ps(L->p_val_f + k)));
        for (; k < k1; ++k) L->p_val[k] = (double)L->p_val_f[k];
    }
}
#define WC_SETUP_F 1
#endif

/* 1 when the float path runs on level L (both functions below) */
static int takes_f(const wc_amg* a, const wc_amg_level* L) {
#ifdef WC_SETUP_F
    return a->opts.single_setup && a->opts.single && L->cpa == 2 && L->tent_f && L->val_f && L->p_val_f &&
           __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    (void)a;
    (void)L;
    return 0;
#endif
}

int wc_amg_prolongator_f(wc_amg* a, wc_amg_level* L, double w, wc_par* par) {
#ifdef WC_SETUP_F
    if (w == 0.0 || !takes_f(a, L)) return 0;
    if (!(L->f_fresh & 1)) wc_amg_round(L->val, L->val_f, 9 * (size_t)L->n_blocks, par);
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n / L->group, wc_par_tid(), wc_par_nt(), &lo, &hi);
        prolong_rows_f(L, (float)w, lo, hi);
    }
    L->f_fresh |= 3;
    return 1;
#else
    (void)a;
    (void)L;
    (void)w;
    (void)par;
    return 0;
#endif
}

int wc_amg_galerkin_f(wc_amg* a, wc_amg_level* L, wc_amg_level* N, wc_par* par) {
#ifdef WC_SETUP_F
    if (!takes_f(a, L) || !L->t_val_f || !N->val_f || N->group != 2 || !N->pair_blk || !N->mirror) return 0;
    const double t0 = wc_cpu_ms();
    if (!(L->f_fresh & 1)) wc_amg_round(L->val, L->val_f, 9 * (size_t)L->n_blocks, par);
    if (!(L->f_fresh & 2)) wc_amg_round(L->p_val, L->p_val_f, 9 * (size_t)L->p_start[L->n], par);
    L->f_fresh |= 3;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        ap_rows_f(L, lo, hi);
    }
    const double t1 = wc_cpu_ms();
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n / 2, wc_par_tid(), wc_par_nt(), &lo, &hi);
        ptap_rows_f(L, N, lo, hi);
    }
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n / 2, wc_par_tid(), wc_par_nt(), &lo, &hi);
        mirror_widen(N, lo, hi);
    }
    N->f_fresh |= 1;
    a->phase_ms[WC_AMG_PHASE_AP] += t1 - t0; /* with the rounding of A and P */
    a->phase_ms[WC_AMG_PHASE_PTAP] += wc_cpu_ms() - t1;
    return 1;
#else
    (void)a;
    (void)L;
    (void)N;
    (void)par;
    return 0;
#endif
}
