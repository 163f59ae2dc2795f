/* The multigrid hierarchy's values for one system (amg.h), rebuilt by every solve with no
 * allocation: the projected fine operator, block-diagonal inverses and Gershgorin bounds, the
 * smoothed prolongators, T = A P, the Galerkin operators P^T A P and the coarsest factor. */
#include <math.h>
#include <string.h>
#include "amg.h"
#include "clock.h"
#include "vec3.h"

/* o += a^T b (3x3, row-major; o may not alias a or b: restrict lets the compiler keep a and b in
 * registers: the Galerkin products 16.7 -> 13.4 ms per solve on the 100^2 sheet,
 * bench_amg_setup) */
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

/* Level 0: P^ = S A S + a (I - S), a_i = trace(A_ii) / 3 (amg.h). */
static void project_fine(wc_amg_level* L, const double* A, const wc_filter* f, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            const double* Si = f->S + 9 * i;
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int j = L->col[k];
                const double* Ak = A + 9 * (size_t)k;
                double* o = L->val + 9 * (size_t)k;
                if (f->ndof[i] == 0 && f->ndof[j] == 0) {
                    memcpy(o, Ak, 9 * sizeof(double));
                    continue;
                }
                double tmp[9];
                if (f->ndof[j] == 0) memcpy(tmp, Ak, sizeof tmp);
                else m3_mul(tmp, Ak, f->S + 9 * j);
                if (f->ndof[i] == 0) memcpy(o, tmp, sizeof tmp);
                else m3_mul(o, Si, tmp);
                if (i == j && f->ndof[i] != 0) {
                    double scale = (Ak[0] + Ak[4] + Ak[8]) / 3.0;
                    if (!(scale > 0) || !isfinite(scale)) scale = 1.0;
                    for (int q = 0; q < 9; ++q) o[q] += scale * (((q % 4) == 0 ? 1.0 : 0.0) - Si[q]);
                }
            }
        }
    }
}

/* Inverse block diagonal: 3x3 per node, or 6x6 per pair on a rotation level (amg.h; with
 * pair_blocks off, or when the pair's block is singular, the pair's two 3x3 inverses). */
static void diagonal(wc_amg_level* L, int pair_blocks, wc_par* par) {
    const double* cross = L->cross && L->cross->n_terms > 0 ? L->cross->dadd : NULL;
    if (L->group == 1) {
        WC_PAR_REGION(par)
        {
            int lo, hi;
            wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
            for (int i = lo; i < hi; ++i) {
                const double* B = L->val + 9 * (size_t)L->diag[i];
                double Bc[9];
                if (cross) { /* the couplings' part (amg_cross.c) */
                    for (int q = 0; q < 9; ++q) Bc[q] = B[q] + cross[9 * (size_t)i + q];
                    B = Bc;
                }
                wc_amg_block_inverse(L->Dinv + 9 * i, B);
            }
            wc_amg_dinv_columns(L, lo, hi);
        }
        return;
    }
    const int vec = pair_blocks && wc_amg_inverse6_vec();
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n / 2, wc_par_tid(), wc_par_nt(), &lo, &hi);
        wc_amg_pair_inverses(L, cross, pair_blocks, vec, lo, hi);
        wc_amg_dinv_columns(L, 2 * lo, 2 * hi);
    }
}

/* L (level l)->bound: the largest eigenvalue of D^-1 A (amg_eigen.c) x WC_AMG_SAFETY; fine: the
 * finest level (its iterations are wc_amg_opts.power_iterations, the coarse levels'
 * coarse_iterations). hold: the level's last estimate x bound_margin instead
 * (wc_amg_opts.bound_reuse); carry: the last estimate as it is, unless the level's couplings came
 * or went since (wc_amg.carry_bounds; x bound_margin there made the smoother weaker for nothing:
 * the flag's first solves took 5 % more iterations, docs/bench/suit_setup.md). Returns 1 when it
 * reused. */
static int largest_eigenvalue(wc_amg* a, int l, int fine, int hold, int carry, wc_par* par) {
    wc_amg_level* L = &a->lev[l];
    const wc_amg_opts* o = &a->opts;
    const int terms = L->cross && L->cross->n_terms > 0;
    int steps = fine ? o->power_iterations
                     : o->coarse_iterations > 0 ? o->coarse_iterations
                     : o->lanczos ? WC_AMG_COARSE_LANCZOS
                                  : WC_AMG_COARSE_POWER;
    if (fine && terms && steps < WC_AMG_CROSS_LANCZOS) steps = WC_AMG_CROSS_LANCZOS;
    const int reuse = hold || (carry && terms == (int)((a->est_terms >> l) & 1u));
    double lambda;
    if (reuse) {
        lambda = (hold ? o->bound_margin : 1.0) * L->estimate;
    } else {
        lambda = wc_amg_eigen_estimate(L, steps, o->lanczos, o->pair_blocks, par);
        L->estimate = lambda;
        a->est_terms = (a->est_terms & ~(1u << l)) | ((unsigned)terms << l);
    }
    L->bound = lambda > 0 ? WC_AMG_SAFETY * lambda : 2.0;
    /* seams (amg.h, WC_AMG_SEAM_BOUND): the power method misses their local modes; Lanczos finds
       them (tests/test_amg_setup.c, the sewn tube: 1.1 x its estimate >= 1.03 lambda_max where
       the power method's was 0.90), and the factor only weakened the smoother there (the sewn
       tube's 30 frames in test_sew: 443 PCG iterations with it, 315 without) */
    if (fine && !o->lanczos) L->bound *= a->fine_bound_scale;
    return reuse;
}

/* P = (I - w D^-1 A_F) P_tent: row i = P_tent's blocks of i (to the cpa coarse nodes of agg(i)),
 * minus w D_i^-1 A_ij P_tent(j) summed over the strong blocks; weak blocks are lumped onto the
 * diagonal of A_F, so they contribute w D_i^-1 A_ij P_tent(i). P_tent(i) is identity blocks
 * without rotations (tent NULL), else the QR's Q (amg_tent.c).
 * With P_tent, D^-1 is applied once per entry of P instead of once per block of A: row i's
 * entries first gather Z_e = sum A_ij P_tent(j) (the weak blocks summed before their one
 * product), then P_e = -w D_i^-1 Z_e (+ P_tent(i) on i's own aggregate); on a pair level rows
 * 2a and 2a + 1 share their columns and D^-1 couples them, so a pair's two rows go together.
 * 6.1 -> 3.4 ms per solve (with the restrict kernels) on the 100^2 sheet (bench_amg_setup). */
static void prolongator_plain(wc_amg_level* L, double w, wc_par* par) {
    static const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* row = L->p_val + 9 * (size_t)L->p_start[i];
            memset(row, 0, 9 * sizeof(double) * (size_t)(L->p_start[i + 1] - L->p_start[i]));
            memcpy(L->p_val + 9 * (size_t)L->p_self[i], eye, 9 * sizeof(double));
            if (w == 0.0) continue;
            double WD[9];
            for (int q = 0; q < 9; ++q) WD[q] = -w * L->Dinv[9 * i + q];
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int e = L->a_to_p[k] >= 0 ? L->a_to_p[k] : L->p_self[i];
                m3_mul_add(L->p_val + 9 * (size_t)e, WD, L->val + 9 * (size_t)k);
            }
        }
    }
}

/* Dead unknowns of a rotation level (amg.h): their Galerkin rows and columns are zero; the
 * block's mean live diagonal (or 1) on the diagonal decouples them. */
static void revive_dead(wc_amg_level* N, wc_par* par) {
    if (!N->dead) return;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int I = lo; I < hi; ++I) {
            const unsigned char* dd = N->dead + 3 * I;
            if (!dd[0] && !dd[1] && !dd[2]) continue;
            double* B = N->val + 9 * (size_t)N->diag[I];
            double sum = 0.0;
            int live = 0;
            for (int r = 0; r < 3; ++r)
                if (!dd[r]) {
                    sum += B[4 * r];
                    ++live;
                }
            double v = live && sum > 0 && isfinite(sum) ? sum / live : 1.0;
            for (int r = 0; r < 3; ++r)
                if (dd[r]) B[4 * r] = v;
            if (N->f_fresh & 1) /* the float operator came first (amg_setup_f.c): val its widening */
                for (int r = 0; r < 3; ++r)
                    if (dd[r]) B[4 * r] = N->val_f[9 * (size_t)N->diag[I] + 4 * r] = (float)v;
        }
    }
}

/* T = A P, then the next level's operator P^T T, with two coarse nodes per aggregate (cpa 2): P's,
 * T's and the next level's rows hold whole pairs (2a, 2a + 1), so every product fills a slot pair.
 * Each slot pair gathers its products from the lists of amg_build.c (ap_*, ptap_*: the order in
 * which a walk along the sorted rows meets them), sums them in registers from zero and is stored
 * once: no zeroing of the accumulators and no load and store per product, with the sums of the
 * walk bit for bit. */
static inline void pair_mul_add(double* restrict z, const double* restrict A, const double* restrict P) {
    m3_mul_add(z, A, P);
    m3_mul_add(z + 9, A, P + 9);
}

/* T's rows lo..hi-1, the slots P^T T reads (t_read on): (i, 2c), (i, 2c + 1) = sum A_ij P(j, c). */
static void pairs_ap_rows(wc_amg_level* L, int lo, int hi) {
    for (int i = lo; i < hi; ++i)
        for (int s = L->t_read[i]; s < L->t_start[i + 1]; s += 2) {
            double z[18] = {0};
            for (int m = L->ap_start[s / 2]; m < L->ap_start[s / 2 + 1]; ++m)
                pair_mul_add(z, L->val + 9 * (size_t)L->ap_src[2 * m], L->p_val + 9 * (size_t)L->ap_src[2 * m + 1]);
            memcpy(L->t_val + 9 * (size_t)s, z, sizeof z);
        }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
/* Six registers (rows 0-2 of a slot pair's two blocks, lane 3 the next element) += the rows of
 * C [X0 X1] with C's element (r, q) at C[cr * r + cq * q] (C = A: 3, 1; C = P^T: 1, 3), each row
 * sum formed (c0 x0, then two multiply-adds) before it is added to the register. */
#define WC_PAIR_ACC_AVX2(z, C, cr, cq, X)                                                               \
    do {                                                                                                \
        const __m256d x0 = _mm256_loadu_pd(X), x1 = _mm256_loadu_pd((X) + 3), x2 = _mm256_loadu_pd((X) + 6); \
        const __m256d y0 = _mm256_loadu_pd((X) + 9), y1 = _mm256_loadu_pd((X) + 12);                   \
        const __m256d y2 = _mm256_maskload_pd((X) + 15, m3);                                            \
        for (int r = 0; r < 3; ++r) {                                                                   \
            const __m256d c0 = _mm256_broadcast_sd((C) + (cr) * r), c1 = _mm256_broadcast_sd((C) + (cr) * r + (cq)); \
            const __m256d c2 = _mm256_broadcast_sd((C) + (cr) * r + 2 * (cq));                          \
            z[r] = _mm256_add_pd(z[r], _mm256_fmadd_pd(c2, x2, _mm256_fmadd_pd(c1, x1, _mm256_mul_pd(c0, x0)))); \
            z[3 + r] = _mm256_add_pd(z[3 + r], _mm256_fmadd_pd(c2, y2, _mm256_fmadd_pd(c1, y1, _mm256_mul_pd(c0, y0)))); \
        }                                                                                               \
    } while (0)

/* A slot pair's six row registers to o (18 doubles): rows in order, so each row's lane 3 is
 * overwritten by the next row's store; the last row masked. */
__attribute__((target("avx2,fma"), always_inline)) static inline void pair_store_avx2(double* o, const __m256d* z) {
    for (int r = 0; r < 5; ++r) _mm256_storeu_pd(o + 3 * r, z[r]);
    _mm256_maskstore_pd(o + 15, _mm256_setr_epi64x(-1, -1, -1, 0), z[5]);
}

__attribute__((target("avx2,fma"))) static void pairs_ap_rows_avx2(wc_amg_level* L, int lo, int hi) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int i = lo; i < hi; ++i)
        for (int s = L->t_read[i]; s < L->t_start[i + 1]; s += 2) {
            __m256d z[6];
            for (int r = 0; r < 6; ++r) z[r] = _mm256_setzero_pd();
            for (int m = L->ap_start[s / 2]; m < L->ap_start[s / 2 + 1]; ++m) {
                const double* A = L->val + 9 * (size_t)L->ap_src[2 * m];
                const double* P = L->p_val + 9 * (size_t)L->ap_src[2 * m + 1];
                WC_PAIR_ACC_AVX2(z, A, 3, 1, P);
            }
            pair_store_avx2(L->t_val + 9 * (size_t)s, z);
        }
}
#define WC_PAIRS_AP_AVX2 1
#endif

/* The smoothed prolongator's rows of aggregates' pairs lo..hi-1 (units of L->group rows): P = (I - w
 * D^-1 A_F) P_tent, each entry pair e of row i first Z_e = sum A_ik P_tent(k) over the strong blocks k
 * whose coarse nodes they are (pr_start / pr_src; the weak blocks' sum W goes to the row's own
 * entries), gathered from zero by GATHER(z, L, i, e, W or NULL) into 18 doubles, then P_e = -w
 * D^-1 Z_e (on a pair level D^-1 couples rows 2a and 2a + 1, which share their columns), plus
 * P_tent on the row's own entries. */
#define WC_PROLONG_ROWS(L, w, lo, hi, GATHER, DINV_Z)                                                  \
    for (int u = (lo); u < (hi); ++u) {                                                                 \
        const int g = (L)->group, b = g * u, len = (L)->p_start[b + 1] - (L)->p_start[b];               \
        if ((w) == 0.0) {                                                                               \
            for (int i = b; i < b + g; ++i)                                                             \
                memset((L)->p_val + 9 * (size_t)(L)->p_start[i], 0, 9 * sizeof(double) * (size_t)len);  \
        } else {                                                                                        \
            double W[2][9] = {{0}};                                                                     \
            int weak[2] = {0, 0};                                                                       \
            for (int i = b; i < b + g; ++i)                                                             \
                for (int k = (L)->row_start[i]; k < (L)->row_start[i + 1]; ++k)                         \
                    if ((L)->a_to_p[k] < 0) {                                                           \
                        for (int q = 0; q < 9; ++q) W[i - b][q] += (L)->val[9 * (size_t)k + q];         \
                        weak[i - b] = 1;                                                                \
                    }                                                                                   \
            for (int off = 0; off < len; off += 2) {                                                    \
                double Z[2][18];                                                                        \
                for (int i = b; i < b + g; ++i)                                                         \
                    GATHER(Z[i - b], L, i, (L)->p_start[i] + off, weak[i - b] ? W[i - b] : NULL);       \
                for (int h = 0; h < 2; ++h) /* P_e = -w D^-1 Z_e, block by block */                     \
                    for (int i = b; i < b + g; ++i)                                                     \
                        DINV_Z((L)->p_val + 9 * (size_t)((L)->p_start[i] + off + h),                    \
                               (L)->Dinv + 9 * (size_t)g * i, Z, g, h, w); /* D: g blocks, to b, b + 1 */ \
            }                                                                                           \
        }                                                                                               \
        for (int i = b; i < b + g; ++i)                                                                 \
            for (int q = 0; q < 18; ++q) (L)->p_val[9 * (size_t)(L)->p_self[i] + q] += (L)->tent[18 * (size_t)i + q]; \
    }

static inline void prolong_gather(double* z, const wc_amg_level* L, int i, int e, const double* W) {
    memset(z, 0, 18 * sizeof(double));
    for (int m = L->pr_start[e / 2]; m < L->pr_start[e / 2 + 1]; ++m) {
        const int k = L->pr_src[m];
        pair_mul_add(z, L->val + 9 * (size_t)k, L->tent + 18 * (size_t)L->col[k]);
    }
    if (W && e == L->p_self[i]) pair_mul_add(z, W, L->tent + 18 * (size_t)i);
}

/* P = -w sum_j D_j Z[j]'s half h (3x3 blocks, m3_mul_add's sums from zero). */
static inline void prolong_dinv_z(double* P, const double* D, double (*Z)[18], int g, int h, double w) {
    double out[9] = {0};
    for (int j = 0; j < g; ++j) m3_mul_add(out, D + 9 * j, Z[j] + 9 * h);
    for (int q = 0; q < 9; ++q) P[q] = -w * out[q];
}

static void prolong_rows(wc_amg_level* L, double w, int lo, int hi) {
    WC_PROLONG_ROWS(L, w, lo, hi, prolong_gather, prolong_dinv_z)
}

#ifdef WC_PAIRS_AP_AVX2
__attribute__((target("avx2,fma"), always_inline)) static inline void prolong_gather_avx2(double* zo, const wc_amg_level* L,
                                                                                         int i, int e, const double* W) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    __m256d z[6];
    for (int r = 0; r < 6; ++r) z[r] = _mm256_setzero_pd();
    for (int m = L->pr_start[e / 2]; m < L->pr_start[e / 2 + 1]; ++m) {
        const int k = L->pr_src[m];
        const double* A = L->val + 9 * (size_t)k;
        const double* Pt = L->tent + 18 * (size_t)L->col[k];
        WC_PAIR_ACC_AVX2(z, A, 3, 1, Pt);
    }
    if (W && e == L->p_self[i]) {
        const double* Pt = L->tent + 18 * (size_t)i;
        WC_PAIR_ACC_AVX2(z, W, 3, 1, Pt);
    }
    pair_store_avx2(zo, z);
}

/* prolong_dinv_z with each row of the product in a register: row r of D_j Z_j is (D_r0 z_0 +
 * D_r1 z_1) + D_r2 z_2 over Z's rows z_k, m3_mul_add's products and sums in its order (separate
 * multiplies and adds, no FMA), added to the row's sum from zero, times -w: the same bits. Lane 3
 * (the next row's first entry, or masked) is overwritten by the next row's store, the last row
 * stored masked. */
__attribute__((target("avx2,fma"), always_inline)) static inline void prolong_dinv_z_avx2(double* P, const double* D,
                                                                                         double (*Z)[18], int g, int h,
                                                                                         double w) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    __m256d o[3] = {_mm256_setzero_pd(), _mm256_setzero_pd(), _mm256_setzero_pd()};
    for (int j = 0; j < g; ++j) {
        const double* z = Z[j] + 9 * h;
        const double* a = D + 9 * j;
        const __m256d z0 = _mm256_loadu_pd(z), z1 = _mm256_loadu_pd(z + 3), z2 = _mm256_maskload_pd(z + 6, m3);
        for (int r = 0; r < 3; ++r) {
            const __m256d p01 = _mm256_add_pd(_mm256_mul_pd(_mm256_broadcast_sd(a + 3 * r), z0),
                                              _mm256_mul_pd(_mm256_broadcast_sd(a + 3 * r + 1), z1));
            o[r] = _mm256_add_pd(o[r], _mm256_add_pd(p01, _mm256_mul_pd(_mm256_broadcast_sd(a + 3 * r + 2), z2)));
        }
    }
    const __m256d mw = _mm256_set1_pd(-w);
    _mm256_storeu_pd(P, _mm256_mul_pd(mw, o[0]));
    _mm256_storeu_pd(P + 3, _mm256_mul_pd(mw, o[1]));
    _mm256_maskstore_pd(P + 6, m3, _mm256_mul_pd(mw, o[2]));
}

__attribute__((target("avx2,fma"))) static void prolong_rows_avx2(wc_amg_level* L, double w, int lo, int hi) {
    WC_PROLONG_ROWS(L, w, lo, hi, prolong_gather_avx2, prolong_dinv_z_avx2)
}
#endif

static void prolongator(wc_amg* a, wc_amg_level* L, double weight, wc_par* par) {
    const double w = weight / L->bound;
    if (wc_amg_prolongator_f(a, L, w, par)) return; /* in float (single_setup, amg_setup_f.c) */
    if (!L->tent) {
        prolongator_plain(L, w, par);
        return;
    }
#ifdef WC_PAIRS_AP_AVX2
    const int vec = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n / L->group, wc_par_tid(), wc_par_nt(), &lo, &hi);
#ifdef WC_PAIRS_AP_AVX2
        if (vec) prolong_rows_avx2(L, w, lo, hi);
        else
#endif
            prolong_rows(L, w, lo, hi);
    }
}

/* T = A P on a pair level, rows in parallel; AVX2 + FMA where the CPU has them (bsr_rows.h). */
static void galerkin_pairs_ap(wc_amg_level* L, wc_par* par) {
#ifdef WC_PAIRS_AP_AVX2
    const int vec = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
#ifdef WC_PAIRS_AP_AVX2
        if (vec) pairs_ap_rows_avx2(L, lo, hi);
        else
#endif
            pairs_ap_rows(L, lo, hi);
    }
}

/* The next level's rows 2a, 2a + 1 for pairs lo..hi-1, the blocks (I, J) with J >= I = 2a (P^T A P
 * is symmetric: half the products): the slot pair (I, J) of row I += P0^T [T0 T1] and the same
 * columns of row I + 1 += P1^T [T0 T1], summed over the fine rows i of P^T's row I (P0, P1 = P(i,
 * I), P(i, I + 1); T0, T1 = T(i, J), T(i, J + 1)). */
static void pairs_ptap_rows(wc_amg_level* L, wc_amg_level* N, int lo, int hi) {
    for (int a = lo; a < hi; ++a) {
        const int I = 2 * a, c0 = N->row_start[I], d0 = N->row_start[I + 1];
        int s0 = c0;
        while (N->col[s0] < I) ++s0;
        for (int s = s0; s < d0; s += 2) {
            double z[2][18] = {{0}};
            for (int m = L->ptap_start[s / 2]; m < L->ptap_start[s / 2 + 1]; ++m) {
                const double* P = L->p_val + 9 * (size_t)L->ptap_src[2 * m];
                const double* T = L->t_val + 9 * (size_t)L->ptap_src[2 * m + 1];
                for (int h = 0; h < 2; ++h) {
                    double Q[9]; /* P(i, I + h)^T */
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 3; ++c) Q[3 * r + c] = P[9 * h + 3 * c + r];
                    pair_mul_add(z[h], Q, T);
                }
            }
            memcpy(N->val + 9 * (size_t)s, z[0], sizeof z[0]);
            memcpy(N->val + 9 * (size_t)(s - c0 + d0), z[1], sizeof z[1]);
        }
    }
}

#ifdef WC_PAIRS_AP_AVX2
/* The same, row I's slot pair and then row I + 1's (twelve accumulators and T's rows do not fit
 * the sixteen registers together). */
__attribute__((target("avx2,fma"))) static void pairs_ptap_rows_avx2(wc_amg_level* L, wc_amg_level* N, int lo, int hi) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int a = lo; a < hi; ++a) {
        const int I = 2 * a, c0 = N->row_start[I], d0 = N->row_start[I + 1];
        int s0 = c0;
        while (N->col[s0] < I) ++s0;
        for (int s = s0; s < d0; s += 2)
            for (int h = 0; h < 2; ++h) {
                __m256d z[6];
                for (int r = 0; r < 6; ++r) z[r] = _mm256_setzero_pd();
                for (int m = L->ptap_start[s / 2]; m < L->ptap_start[s / 2 + 1]; ++m) {
                    const double* Q = L->p_val + 9 * (size_t)L->ptap_src[2 * m] + 9 * h; /* transposed */
                    const double* T = L->t_val + 9 * (size_t)L->ptap_src[2 * m + 1];
                    WC_PAIR_ACC_AVX2(z, Q, 1, 3, T);
                }
                pair_store_avx2(N->val + 9 * (size_t)(h ? s - c0 + d0 : s), z);
            }
    }
}
#endif

/* N = P^T T on a pair level; AVX2 + FMA where the CPU has them. */
static void galerkin_pairs_ptap(wc_amg_level* L, wc_amg_level* N, wc_par* par) {
#ifdef WC_PAIRS_AP_AVX2
    const int vec = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n / 2, wc_par_tid(), wc_par_nt(), &lo, &hi);
#ifdef WC_PAIRS_AP_AVX2
        if (vec) pairs_ptap_rows_avx2(L, N, lo, hi);
        else
#endif
            pairs_ptap_rows(L, N, lo, hi);
    }
    /* the others by symmetry: (I, J) = (J, I)^T, written by pair I / 2 from pair J / 2's rows */
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n / 2, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int I = 2 * lo; I < 2 * hi; ++I)
            for (int slot = N->row_start[I]; slot < N->row_start[I + 1] && N->col[slot] < (I & ~1); ++slot) {
                int J = N->col[slot];
                int kt = wc_amg_find(N->col, N->row_start[J], N->row_start[J + 1], I);
                const double* src = N->val + 9 * (size_t)kt;
                double* dst = N->val + 9 * (size_t)slot;
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) dst[3 * r + c] = src[3 * c + r];
            }
    }
}

/* T = A P (phase AP), then N = P^T T (phase PTAP) and its dead unknowns' diagonal. */
static void galerkin(wc_amg* a, wc_amg_level* L, wc_amg_level* N, wc_par* par) {
    if (wc_amg_galerkin_f(a, L, N, par)) {
        revive_dead(N, par);
        return;
    }
    double t0 = wc_cpu_ms();
    if (L->cpa == 2) {
        galerkin_pairs_ap(L, par);
        double t1 = wc_cpu_ms();
        galerkin_pairs_ptap(L, N, par);
        revive_dead(N, par);
        a->phase_ms[WC_AMG_PHASE_AP] += t1 - t0;
        a->phase_ms[WC_AMG_PHASE_PTAP] += wc_cpu_ms() - t1;
        return;
    }
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            int t0 = L->t_start[i], t1 = L->t_start[i + 1];
            memset(L->t_val + 9 * (size_t)t0, 0, 9 * sizeof(double) * (size_t)(t1 - t0));
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int j = L->col[k];
                const double* Ak = L->val + 9 * (size_t)k;
                for (int e = L->p_start[j]; e < L->p_start[j + 1]; ++e) {
                    int slot = wc_amg_find(L->t_col, t0, t1, L->p_col[e]);
                    m3_mul_add(L->t_val + 9 * (size_t)slot, Ak, L->p_val + 9 * (size_t)e);
                }
            }
        }
    }
    double t1 = wc_cpu_ms();
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int I = lo; I < hi; ++I) {
            int c0 = N->row_start[I], c1 = N->row_start[I + 1];
            memset(N->val + 9 * (size_t)c0, 0, 9 * sizeof(double) * (size_t)(c1 - c0));
            for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
                int i = L->pt_row[s];
                const double* Pe = L->p_val + 9 * (size_t)L->pt_entry[s];
                for (int k = L->t_start[i]; k < L->t_start[i + 1]; ++k) {
                    int slot = wc_amg_find(N->col, c0, c1, L->t_col[k]);
                    m3_tmul_add(N->val + 9 * (size_t)slot, Pe, L->t_val + 9 * (size_t)k);
                }
            }
        }
    }
    revive_dead(N, par);
    a->phase_ms[WC_AMG_PHASE_AP] += t1 - t0;
    a->phase_ms[WC_AMG_PHASE_PTAP] += wc_cpu_ms() - t1;
}

/* Dense Cholesky of the coarsest operator (a pivot that is not positive gets 1: that unknown is
 * decoupled, which a semi-definite coarse operator's null directions are; amg_dense.c). */
static void coarse_factor(wc_amg* a) {
    const wc_amg_level* L = &a->lev[a->n_levels - 1];
    int d = a->coarse_dofs;
    double* M = a->coarse_L;
    memset(M, 0, sizeof(double) * (size_t)d * d);
    for (int i = 0; i < L->n; ++i)
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    M[(size_t)(3 * i + r) * d + 3 * L->col[k] + c] = L->val[9 * (size_t)k + 3 * r + c];
    wc_amg_cross_dense(L->cross, M, d);
    wc_amg_dense_factor(M, d, wc_amg_dense_vec());
}

static const char* const phase_names[WC_AMG_PHASES] = {
    "tentative (QR)", "project fine", "block diagonal", "power it. fine", "power it. coarse",
    "prolongator", "T = A P", "P^T T", "coarse factor", "couplings", "float copies"};

const char* wc_amg_phase_name(wc_amg_phase p) { return p >= 0 && p < WC_AMG_PHASES ? phase_names[p] : "unknown"; }

/* the time since *t into phase p; *t = now */
static void lap(wc_amg* a, wc_amg_phase p, double* t) {
    double now = wc_cpu_ms();
    a->phase_ms[p] += now - *t;
    *t = now;
}

/* hold_coarse's setup (amg.h): the finest level's values for A under f, the rest kept. The
 * fine bound is the last fresh estimate x bound_margin; bound_age is left alone, so the Newton
 * solves that follow reuse (or not) exactly as they would after the full setup. */
static void setup_fine_only(wc_amg* a, const double* A, const wc_filter* f, wc_par* par) {
    double t = wc_cpu_ms();
    wc_amg_level* L = &a->lev[0];
    project_fine(L, A, f, par);
    wc_amg_cross_fine(a, f);
    lap(a, WC_AMG_PHASE_PROJECT, &t);
    diagonal(L, a->opts.pair_blocks, par);
    lap(a, WC_AMG_PHASE_DIAGONAL, &t);
    largest_eigenvalue(a, 0, 1, 1, 0, par);
    lap(a, WC_AMG_PHASE_EIGEN_FINE, &t);
    wc_amg_single_copies(a, 1, par);
    wc_amg_cross_merge(a, 0, par);
    lap(a, WC_AMG_PHASE_SINGLE, &t);
    a->bounds_reused = 1;
    a->coarse_kept = 1;
    ++a->coarse_keeps;
}

void wc_amg_setup(wc_amg* a, const double* A, const wc_filter* f, wc_par* par) {
    double t0 = wc_now_ms(), t = wc_cpu_ms();
    if (a->hold_coarse && a->setups > 0 && a->n_levels > 1) {
        setup_fine_only(a, A, f, par);
        ++a->setups;
        a->setup_ms = wc_now_ms() - t0;
        return;
    }
    a->coarse_kept = 0;
    /* hold: reuse the estimates only after a fresh (or carried) setup, and bound_reuse times in a
       row at most; carry: an earlier substep's, bound_carry setups in a row at most */
    const int hold = a->hold_bounds && a->setups > 0 && a->bound_age < a->opts.bound_reuse;
    const int carry = !hold && a->carry_bounds && a->est_valid && a->carry_age < a->opts.bound_carry;
    a->bound_age = hold ? a->bound_age + 1 : 0;
    int reused = 0; /* levels that took an earlier estimate */
    if (a->opts.rotations && a->opts.current_positions && a->pos && a->n_levels > 1) {
        /* P_tent and the R factors about the current positions (amg.h), level by level, unless
         * they were built from the same positions */
        const size_t bytes = 3 * (size_t)a->lev[0].n * sizeof(double);
        if (a->tent_pos && a->tent_valid && memcmp(a->tent_pos, a->pos, bytes) == 0) {
            ++a->tent_kept;
        } else {
            wc_amg_rigid_modes(&a->lev[0], a->pos);
            for (int l = 0; l + 1 < a->n_levels; ++l) wc_amg_tentative(&a->lev[l], &a->lev[l + 1], a->lev[l + 1].n / 2, par);
            if (a->tent_pos) {
                memcpy(a->tent_pos, a->pos, bytes);
                a->tent_valid = 1;
            }
        }
        lap(a, WC_AMG_PHASE_TENT, &t);
    }
    project_fine(&a->lev[0], A, f, par);
    wc_amg_cross_fine(a, f);
    lap(a, WC_AMG_PHASE_PROJECT, &t);
    for (int l = 0; l + 1 < a->n_levels; ++l) {
        wc_amg_level *L = &a->lev[l], *N = &a->lev[l + 1];
        diagonal(L, a->opts.pair_blocks, par);
        lap(a, WC_AMG_PHASE_DIAGONAL, &t);
        reused += largest_eigenvalue(a, l, l == 0, hold, carry, par);
        lap(a, l == 0 ? WC_AMG_PHASE_EIGEN_FINE : WC_AMG_PHASE_EIGEN_COARSE, &t);
        prolongator(a, L, a->opts.prolong_weight, par);
        lap(a, WC_AMG_PHASE_PROLONG, &t);
        galerkin(a, L, N, par);
        t = wc_cpu_ms();
        wc_amg_cross_restrict(a, l, par);
        lap(a, WC_AMG_PHASE_CROSS, &t);
    }
    if (a->coarse_dense) {
        coarse_factor(a);
        lap(a, WC_AMG_PHASE_COARSE_FACTOR, &t);
    } else {
        diagonal(&a->lev[a->n_levels - 1], a->opts.pair_blocks, par);
        lap(a, WC_AMG_PHASE_DIAGONAL, &t);
        reused += largest_eigenvalue(a, a->n_levels - 1, a->n_levels == 1, hold, carry, par);
        lap(a, a->n_levels == 1 ? WC_AMG_PHASE_EIGEN_FINE : WC_AMG_PHASE_EIGEN_COARSE, &t);
    }
    wc_amg_single_copies(a, 0, par);
    for (int l = 0; l < a->n_levels; ++l) wc_amg_cross_merge(a, l, par);
    lap(a, WC_AMG_PHASE_SINGLE, &t);
    a->bounds_reused = reused > 0;
    if (!hold) { /* every level estimated (a fresh setup) or some carried */
        a->est_valid = 1;
        a->carry_age = reused > 0 ? a->carry_age + 1 : 0;
        if (reused > 0) ++a->carried;
    }
    ++a->setups;
    a->setup_ms = wc_now_ms() - t0;
}
