/* The finest level's Gauss-Seidel smoother (amg.h, wc_amg_opts.fine_gs): a symmetric l1 block
 * Gauss-Seidel, "hybrid" over fixed chunks of WC_AMG_GS_CHUNK rows (Baker, Falgout, Kolev & Yang
 * 2011, "Multigrid smoothers for ultraparallel computing"). Within a chunk the rows are relaxed in
 * order (forward before the coarse correction, backward after it), each with its 3x3 block; the
 * blocks to other chunks and the couplings' terms (amg_cross.c) are read at the sweep's start
 * values (Jacobi between chunks), so a chunk's result does not depend on which thread runs it.
 * The forward sweep is x += M^-1 (r - F x), M = D' + L_c (L_c: the strictly lower blocks inside a
 * chunk), the backward one the same with M^T = D' + U_c: the V-cycle stays symmetric. D' is the
 * block diagonal D (the BSR's and the couplings' part, Chebyshev's D) plus, on each unknown, half
 * the absolute row sum of what a sweep reads at its start values: the blocks to other chunks
 * (R_out) and the couplings' off-diagonal part (R_X, bounded term by term: c_k |u_i| sum_{j != i}
 * |u_j|_1). Then M + M^T - F = D + (R_out - A_out) + (R_X - X_off) >= D (each bracket by
 * Gershgorin), so a sweep contracts in the F-norm and the V-cycle is SPD however stiff the
 * couplings (without the row sums it is not: PCG breaks down on tests/test_amg_smooth.c's layers).
 * Where it pays (wc_amg_gs_on, WC_AMG_GS_ENTRIES): docs/bench/dance_frame.md. */
#include <math.h>
#include <string.h>
#include "amg.h"
#include "vec3.h"

/* D' adds this x the absolute row sums: 1/2 is the least that keeps M + M^T - F >= D (above) */
#define GS_L1 0.5

int wc_amg_gs_on(const wc_amg* a, int l) {
    if (l != 0 || a->n_levels < 2 || !a->opts.fine_gs || !a->lev[0].gs_dinv) return 0;
    const wc_amg_cross* X = a->lev[0].cross;
    const int held = X && X->n_terms > 0;
    if (held && !wc_amg_cross_as_terms(X)) return 0;
    return a->opts.fine_gs == 2 || (held && X->n_entries >= WC_AMG_GS_ENTRIES * a->lev[0].n);
}

void wc_amg_gs_setup(wc_amg* a, wc_par* par) {
    if (!wc_amg_gs_on(a, 0)) return;
    wc_amg_level* L = &a->lev[0];
    const wc_amg_cross* X = L->cross && L->cross->n_terms > 0 ? L->cross : NULL;
    const int G = WC_AMG_GS_CHUNK;
    const double h = GS_L1;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double D[9], l1[3] = {0, 0, 0};
            memcpy(D, L->val + 9 * (size_t)L->diag[i], sizeof D);
            const int c0 = i / G * G, c1 = c0 + G;
            for (int s = L->row_start[i]; s < L->row_start[i + 1]; ++s) {
                const int j = L->col[s];
                if (j >= c0 && j < c1) continue;
                const double* B = L->val + 9 * (size_t)s;
                for (int r = 0; r < 3; ++r) l1[r] += fabs(B[3 * r]) + fabs(B[3 * r + 1]) + fabs(B[3 * r + 2]);
            }
            if (X) {
                for (int q = 0; q < 9; ++q) D[q] += X->dadd[9 * (size_t)i + q];
                for (int e = X->node_start[i]; e < X->node_start[i + 1]; ++e) {
                    const int k = X->entry_term[e];
                    const double* u = X->node_val + 3 * (size_t)e;
                    double others = 0.0; /* sum_{j != i} |u_j|_1 over term k's entries */
                    for (int f = X->start[k]; f < X->start[k + 1]; ++f) {
                        if (X->node[f] == i) continue;
                        const double* v = X->val + 3 * (size_t)f;
                        others += fabs(v[0]) + fabs(v[1]) + fabs(v[2]);
                    }
                    for (int r = 0; r < 3; ++r) l1[r] += X->c[k] * fabs(u[r]) * others;
                }
            }
            for (int r = 0; r < 3; ++r) D[4 * r] += h * l1[r];
            double* Di = L->gs_dinv + 9 * (size_t)i;
            if (m3_inverse(Di, D) == 0.0 || !isfinite(Di[0])) {
                double tr = (D[0] + D[4] + D[8]) / 3.0;
                m3_identity(Di, tr > 0 && isfinite(tr) ? 1.0 / tr : 1.0);
            }
        }
    }
}

/* Row i of a sweep inside chunk [c0, c1): x_i += D'^-1 (b_i - sum_j A_ij x_j), x_j read in place
 * inside the chunk and from xo outside it. xo NULL: a forward sweep from x = 0, which reads only
 * the chunk's columns below i (the rest are zero; columns ascend). */
#define WC_GS_ROW(VAL, CAST)                                                                              \
    {                                                                                                     \
        double acc[3] = {b[3 * i], b[3 * i + 1], b[3 * i + 2]};                                          \
        for (int s = L->row_start[i]; s < L->row_start[i + 1]; ++s) {                                     \
            const int j = L->col[s];                                                                      \
            const double* v;                                                                              \
            if (!xo && j >= i) break;                                                                     \
            if (j >= c0 && j < c1) v = x + 3 * (size_t)j;                                                 \
            else if (xo) v = xo + 3 * (size_t)j;                                                          \
            else continue;                                                                                \
            const VAL* B = L->VAL##_blk + 9 * (size_t)s;                                                  \
            acc[0] -= CAST B[0] * v[0] + CAST B[1] * v[1] + CAST B[2] * v[2];                             \
            acc[1] -= CAST B[3] * v[0] + CAST B[4] * v[1] + CAST B[5] * v[2];                             \
            acc[2] -= CAST B[6] * v[0] + CAST B[7] * v[1] + CAST B[8] * v[2];                             \
        }                                                                                                 \
        m3_mulv_add(x + 3 * (size_t)i, L->gs_dinv + 9 * (size_t)i, acc);                                 \
    }

typedef struct {
    const int* row_start;
    const int* col;
    const double* gs_dinv;
    const double* double_blk;
    const float* float_blk;
} gs_view;

static void sweep_chunk(const gs_view* L, int single, const double* b, double* x, const double* xo, int c0, int c1,
                        int backward) {
    for (int k = c0; k < c1; ++k) {
        const int i = backward ? c0 + c1 - 1 - k : k;
        if (single) WC_GS_ROW(float, (double))
        else WC_GS_ROW(double, )
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define WC_GS_AVX2 1
/* sweep_chunk with float blocks, AVX2 + FMA: each block row times x_j in one register (x_j loaded
 * masked to 3 lanes; the third row's 4th float, the next block's or WC_BSR_F_PAD's, meets its
 * zero lane), as bsr_rows.c's kernel; the sums round differently from the scalar ones. */
__attribute__((target("avx2,fma"))) static void sweep_chunk_f_avx2(const gs_view* L, const double* b, double* x,
                                                                    const double* xo, int c0, int c1, int backward) {
    const __m256i m3 = _mm256_setr_epi64x(-1, -1, -1, 0);
    for (int k = c0; k < c1; ++k) {
        const int i = backward ? c0 + c1 - 1 - k : k;
        __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd();
        const int s1 = L->row_start[i + 1];
        int s = L->row_start[i];
        /* columns ascend: the blocks before the chunk, inside it, after it (from zero: inside, below i) */
#define WC_GS_BLOCK(V)                                                                                   \
    {                                                                                                    \
        const float* B = L->float_blk + 9 * (size_t)s;                                                   \
        const __m256d w = _mm256_maskload_pd((V) + 3 * (size_t)L->col[s], m3);                           \
        a0 = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(B)), w, a0);                                   \
        a1 = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(B + 3)), w, a1);                               \
        a2 = _mm256_fmadd_pd(_mm256_cvtps_pd(_mm_loadu_ps(B + 6)), w, a2);                               \
    }
        if (!xo) {
            while (s < s1 && L->col[s] < c0) ++s;
            for (; s < s1 && L->col[s] < i; ++s) WC_GS_BLOCK(x)
        } else {
            for (; s < s1 && L->col[s] < c0; ++s) WC_GS_BLOCK(xo)
            for (; s < s1 && L->col[s] < c1; ++s) WC_GS_BLOCK(x)
            for (; s < s1; ++s) WC_GS_BLOCK(xo)
        }
#undef WC_GS_BLOCK
        const __m256d h01 = _mm256_hadd_pd(a0, a1), h22 = _mm256_hadd_pd(a2, a2);
        const __m128d r01 = _mm_add_pd(_mm256_castpd256_pd128(h01), _mm256_extractf128_pd(h01, 1));
        const __m128d r22 = _mm_add_pd(_mm256_castpd256_pd128(h22), _mm256_extractf128_pd(h22, 1));
        double acc[3];
        _mm_storeu_pd(acc, _mm_sub_pd(_mm_loadu_pd(b + 3 * (size_t)i), r01));
        acc[2] = b[3 * (size_t)i + 2] - _mm_cvtsd_f64(r22);
        m3_mulv_add(x + 3 * (size_t)i, L->gs_dinv + 9 * (size_t)i, acc);
    }
}
#endif

void wc_amg_gs_part(wc_amg_level* L, int single, const double* r, double* x, int zero, int backward) {
    const wc_amg_cross* X = L->cross && L->cross->n_terms > 0 ? L->cross : NULL;
    const int G = WC_AMG_GS_CHUNK, nc = (L->n + G - 1) / G;
    int k0, k1;
    wc_par_range(nc, wc_par_tid(), wc_par_nt(), &k0, &k1);
    const int lo = k0 * G, hi = k1 * G < L->n ? k1 * G : L->n;
    double* xo = L->ev_scratch;
    const double* b = r;
    if (zero) {
        if (hi > lo) memset(x + 3 * (size_t)lo, 0, sizeof(double) * 3 * (size_t)(hi - lo));
    } else { /* the sweep's start values, and b = r - X xo */
        if (hi > lo) memcpy(xo + 3 * (size_t)lo, x + 3 * (size_t)lo, sizeof(double) * 3 * (size_t)(hi - lo));
        if (X) {
            int q0, q1;
            wc_par_range(X->n_terms, wc_par_tid(), wc_par_nt(), &q0, &q1);
            wc_amg_cross_scale(X, -1.0, x, q0, q1);
        }
        WC_PAR_BARRIER(); /* xo complete, every term's s_k in */
        if (hi > lo) memcpy(L->t + 3 * (size_t)lo, r + 3 * (size_t)lo, sizeof(double) * 3 * (size_t)(hi - lo));
        if (X) wc_amg_cross_rows_add(X, -1.0, xo, L->t, L->n, lo, hi);
        b = L->t;
    }
    const gs_view v = {L->row_start, L->col, L->gs_dinv, L->val, L->val_f};
#ifdef WC_GS_AVX2
    const int vec = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
    for (int k = k0; k < k1; ++k) {
        const int c0 = k * G, c1 = c0 + G < L->n ? c0 + G : L->n;
#ifdef WC_GS_AVX2
        if (single && vec) {
            sweep_chunk_f_avx2(&v, b, x, zero ? NULL : xo, c0, c1, backward);
            continue;
        }
#endif
        sweep_chunk(&v, single, b, x, zero ? NULL : xo, c0, c1, backward);
    }
}
