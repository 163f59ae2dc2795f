/* The multigrid's tentative prolongator with the rigid-body modes as near-null space (amg.h,
 * wc_amg_opts.rotations): level 0's six modes per node from the rest positions, and per
 * aggregate a QR of its (3 n_agg) x 6 block of near-null rows. Q is P_tent's rows (two 3x3
 * blocks per fine node: to coarse nodes 2a and 2a + 1), R is the next level's near-null space.
 * Built at wc_amg_create about the rest positions, and again (no allocation) by every setup
 * about the solver's current positions when wc_amg_opts.current_positions is set (amg.h). With
 * AVX2 four aggregates are done at once, one a lane, each with the one-aggregate path's bits
 * (qr_lanes; docs/bench/amg_setup_scalar.md). */
#include <math.h>
#include <string.h>
#include "amg.h"

/* Element (r, c), c in 0..5, of node i's 3 x 6 rows in an (n x 2 x 9) array. */
#define RB(arr, i, r, c) (arr)[18 * (size_t)(i) + 9 * ((c) / 3) + 3 * (r) + (c) % 3]

void wc_amg_rigid_modes(wc_amg_level* L, const double* x) {
    int n = L->n;
    double c[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i)
        for (int q = 0; q < 3; ++q) c[q] += x[3 * i + q];
    for (int q = 0; q < 3; ++q) c[q] = n > 0 ? c[q] / n : 0.0;
    for (int i = 0; i < n; ++i) {
        double d[3] = {x[3 * i] - c[0], x[3 * i + 1] - c[1], x[3 * i + 2] - c[2]};
        /* translations e_k, rotations d x e_k: (0, dz, -dy), (-dz, 0, dx), (dy, -dx, 0) */
        double rot[3][3] = {{0, -d[2], d[1]}, {d[2], 0, -d[0]}, {-d[1], d[0], 0}}; /* [r][k] */
        for (int r = 0; r < 3; ++r)
            for (int k = 0; k < 3; ++k) {
                RB(L->nns, i, r, k) = r == k ? 1.0 : 0.0;
                RB(L->nns, i, r, 3 + k) = rot[r][k];
            }
    }
    L->unit_translations = 1;
}

/* Modified Gram-Schmidt, each column orthogonalised twice against the earlier live ones, on
 * the aggregate's (3 m) x 6 block copied column by column into Q (rows: node s's 3 rows at
 * 3 s); the same operations in the same order as on the strided rows, on contiguous columns
 * (tentative QR 2.0 -> 1.6 ms per solve (CPU) on the 100^2 sheet, bench_amg_setup). */
#define TENT_LOCAL 96 /* nodes per aggregate the local copy holds (larger ones: strided) */
/* With unit translations (level 0, L->unit_translations) translation column d < 3 is nonzero on
 * rows 3 s + d only, and stays so (its dots with the earlier translations are 0): its dots with
 * the later translations are exactly +0 (skipped: subtracting 0 q_d and adding 0 to R change no
 * bit) and its dot with a rotation column sums only rows 3 s + d (the skipped terms are +-0 and
 * a sum that starts at +0 is never -0, so adding them changes no bit). Its update of a rotation
 * column stays dense: qc - dot (+0) turns a -0 into +0 when dot < 0. */
static void qr_local(wc_amg_level* L, const int* nodes, int m, double* Q, double* R, int* live, unsigned char* dead) {
    const int rows = 3 * m, unit = L->unit_translations;
    for (int s = 0; s < m; ++s)
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 6; ++c) Q[c * rows + 3 * s + r] = RB(L->nns, nodes[s], r, c);
    for (int c = 0; c < 6; ++c) {
        double* qc = Q + c * rows;
        double norm0 = 0.0;
        for (int q = 0; q < rows; ++q) norm0 += qc[q] * qc[q];
        norm0 = sqrt(norm0);
        for (int pass = 0; pass < 2; ++pass)
            for (int d = 0; d < c; ++d) {
                if (!live[d]) continue;
                const double* qd = Q + d * rows;
                double dot = 0.0;
                if (unit && d < 3) {
                    if (c < 3) continue;
                    for (int q = d; q < rows; q += 3) dot += qd[q] * qc[q];
                } else
                    for (int q = 0; q < rows; ++q) dot += qd[q] * qc[q];
                for (int q = 0; q < rows; ++q) qc[q] -= dot * qd[q];
                R[6 * d + c] += dot;
            }
        double norm = 0.0;
        for (int q = 0; q < rows; ++q) norm += qc[q] * qc[q];
        norm = sqrt(norm);
        live[c] = norm > WC_AMG_DEPENDENT * norm0 && isfinite(norm);
        double scale = live[c] ? 1.0 / norm : 0.0;
        for (int q = 0; q < rows; ++q) qc[q] *= scale;
        R[6 * c + c] = live[c] ? norm : 0.0;
        dead[c] = (unsigned char)!live[c];
    }
    for (int s = 0; s < m; ++s)
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 6; ++c) RB(L->tent, nodes[s], r, c) = Q[c * rows + 3 * s + r];
}

/* The aggregate's nodes' rows of P_tent rounded into tent_f (the float setup's copy, amg.h):
 * the same float per double as rounding where it is read. */
static void round_tent(wc_amg_level* L, const int* nodes, int m) {
    if (!L->tent_f) return;
    for (int s = 0; s < m; ++s)
        for (int q = 0; q < 18; ++q) L->tent_f[18 * (size_t)nodes[s] + q] = (float)L->tent[18 * (size_t)nodes[s] + q];
}

/* Aggregates lo..hi-1: each writes only its own nodes' rows of P_tent and its own coarse rows. */
static void tentative_range(wc_amg_level* L, wc_amg_level* N, int lo, int hi) {
    double Q[6 * 3 * TENT_LOCAL];
    for (int a = lo; a < hi; ++a) {
        const int* nodes = L->agg_node + L->agg_start[a];
        int m = L->agg_start[a + 1] - L->agg_start[a];
        double R[36] = {0};
        int live[6];
        if (m <= TENT_LOCAL) {
            unsigned char dead[6];
            qr_local(L, nodes, m, Q, R, live, dead);
            round_tent(L, nodes, m);
            for (int c = 0; c < 6; ++c) N->dead[3 * (2 * a + c / 3) + c % 3] = dead[c];
            for (int q = 0; q < 2; ++q)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 6; ++c) RB(N->nns, 2 * a + q, r, c) = R[6 * (3 * q + r) + c];
            continue;
        }
        for (int s = 0; s < m; ++s) memcpy(L->tent + 18 * (size_t)nodes[s], L->nns + 18 * (size_t)nodes[s], 18 * sizeof(double));
        for (int c = 0; c < 6; ++c) {
            double norm0 = 0.0;
            for (int s = 0; s < m; ++s)
                for (int r = 0; r < 3; ++r) norm0 += RB(L->tent, nodes[s], r, c) * RB(L->tent, nodes[s], r, c);
            norm0 = sqrt(norm0);
            for (int pass = 0; pass < 2; ++pass)
                for (int d = 0; d < c; ++d) {
                    if (!live[d]) continue;
                    double dot = 0.0;
                    for (int s = 0; s < m; ++s)
                        for (int r = 0; r < 3; ++r) dot += RB(L->tent, nodes[s], r, d) * RB(L->tent, nodes[s], r, c);
                    for (int s = 0; s < m; ++s)
                        for (int r = 0; r < 3; ++r) RB(L->tent, nodes[s], r, c) -= dot * RB(L->tent, nodes[s], r, d);
                    R[6 * d + c] += dot;
                }
            double norm = 0.0;
            for (int s = 0; s < m; ++s)
                for (int r = 0; r < 3; ++r) norm += RB(L->tent, nodes[s], r, c) * RB(L->tent, nodes[s], r, c);
            norm = sqrt(norm);
            live[c] = norm > WC_AMG_DEPENDENT * norm0 && isfinite(norm);
            double scale = live[c] ? 1.0 / norm : 0.0;
            for (int s = 0; s < m; ++s)
                for (int r = 0; r < 3; ++r) RB(L->tent, nodes[s], r, c) *= scale;
            R[6 * c + c] = live[c] ? norm : 0.0;
            N->dead[3 * (2 * a + c / 3) + c % 3] = (unsigned char)!live[c];
        }
        round_tent(L, nodes, m);
        for (int q = 0; q < 2; ++q)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 6; ++c) RB(N->nns, 2 * a + q, r, c) = R[6 * (3 * q + r) + c];
    }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define TENT_ROWS (3 * TENT_LOCAL)

/* qr_local on four aggregates at once, one an AVX lane: Q4[4 (c TENT_ROWS + q) + l] is lane l's
 * Q[c rows + q]. Each lane does its aggregate's operations in qr_local's order (the same bits):
 * a dot's or norm's product on a row past the lane's 3 m rows is masked to +0 (a sum that starts
 * at +0 is never -0, so adding +0 changes no bit); a lane whose column d is dead keeps its
 * column c and R (the update is computed and blended away); the pad rows' values are never read
 * unmasked nor written out. */
__attribute__((target("avx2"))) static void qr_lanes(wc_amg_level* L, wc_amg_level* N, int a0, double* Q4) {
    const int unit = L->unit_translations;
    const int* nodes[4];
    int m[4], rows = 0;
    for (int l = 0; l < 4; ++l) {
        nodes[l] = L->agg_node + L->agg_start[a0 + l];
        m[l] = L->agg_start[a0 + l + 1] - L->agg_start[a0 + l];
        if (3 * m[l] > rows) rows = 3 * m[l];
    }
    const __m256d nrows = _mm256_setr_pd(3 * m[0], 3 * m[1], 3 * m[2], 3 * m[3]), zero = _mm256_setzero_pd();
    const __m256d one = _mm256_set1_pd(1.0), dep = _mm256_set1_pd(WC_AMG_DEPENDENT), big = _mm256_set1_pd(1.7976931348623157e308);
    for (int l = 0; l < 4; ++l) {
        for (int s = 0; s < m[l]; ++s)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 6; ++c) Q4[4 * (c * TENT_ROWS + 3 * s + r) + l] = RB(L->nns, nodes[l][s], r, c);
        for (int q = 3 * m[l]; q < rows; ++q)
            for (int c = 0; c < 6; ++c) Q4[4 * (c * TENT_ROWS + q) + l] = 0.0;
    }
    __m256d R[36], live[6], in[TENT_ROWS]; /* in[q]: the lanes whose aggregate has row q */
    for (int q = 0; q < rows; ++q) in[q] = _mm256_cmp_pd(_mm256_set1_pd(q), nrows, _CMP_LT_OQ);
    for (int k = 0; k < 36; ++k) R[k] = zero;
    for (int c = 0; c < 6; ++c) live[c] = zero;
    for (int c = 0; c < 6; ++c) {
        double* qc = Q4 + 4 * c * TENT_ROWS;
        __m256d norm0 = zero;
        for (int q = 0; q < rows; ++q) {
            const __m256d v = _mm256_loadu_pd(qc + 4 * q);
            norm0 = _mm256_add_pd(norm0, _mm256_and_pd(_mm256_mul_pd(v, v), in[q]));
        }
        norm0 = _mm256_sqrt_pd(norm0);
        for (int pass = 0; pass < 2; ++pass)
            for (int d = 0; d < c; ++d) {
                if (_mm256_testz_pd(live[d], live[d])) continue;
                if (unit && d < 3 && c < 3) continue;
                const double* qd = Q4 + 4 * d * TENT_ROWS;
                __m256d dot = zero;
                for (int q = unit && d < 3 ? d : 0; q < rows; q += unit && d < 3 ? 3 : 1) {
                    const __m256d p = _mm256_mul_pd(_mm256_loadu_pd(qd + 4 * q), _mm256_loadu_pd(qc + 4 * q));
                    dot = _mm256_add_pd(dot, _mm256_and_pd(p, in[q]));
                }
                const int all = _mm256_movemask_pd(live[d]) == 15;
                for (int q = 0; q < rows; ++q) {
                    const __m256d v = _mm256_loadu_pd(qc + 4 * q);
                    const __m256d u = _mm256_sub_pd(v, _mm256_mul_pd(dot, _mm256_loadu_pd(qd + 4 * q)));
                    _mm256_storeu_pd(qc + 4 * q, all ? u : _mm256_blendv_pd(v, u, live[d]));
                }
                R[6 * d + c] = _mm256_blendv_pd(R[6 * d + c], _mm256_add_pd(R[6 * d + c], dot), live[d]);
            }
        __m256d norm = zero;
        for (int q = 0; q < rows; ++q) {
            const __m256d v = _mm256_loadu_pd(qc + 4 * q);
            norm = _mm256_add_pd(norm, _mm256_and_pd(_mm256_mul_pd(v, v), in[q]));
        }
        norm = _mm256_sqrt_pd(norm);
        /* norm > WC_AMG_DEPENDENT norm0 && isfinite(norm) (norm >= 0 or NaN) */
        live[c] = _mm256_and_pd(_mm256_cmp_pd(norm, _mm256_mul_pd(dep, norm0), _CMP_GT_OQ), _mm256_cmp_pd(norm, big, _CMP_LE_OQ));
        const __m256d scale = _mm256_and_pd(_mm256_div_pd(one, norm), live[c]);
        for (int q = 0; q < rows; ++q) _mm256_storeu_pd(qc + 4 * q, _mm256_mul_pd(_mm256_loadu_pd(qc + 4 * q), scale));
        R[6 * c + c] = _mm256_and_pd(norm, live[c]);
    }
    double Rl[36 * 4];
    for (int k = 0; k < 36; ++k) _mm256_storeu_pd(Rl + 4 * k, R[k]);
    for (int l = 0; l < 4; ++l) {
        const int a = a0 + l;
        for (int c = 0; c < 6; ++c) N->dead[3 * (2 * a + c / 3) + c % 3] = (unsigned char)!(_mm256_movemask_pd(live[c]) >> l & 1);
        for (int q = 0; q < 2; ++q)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 6; ++c) RB(N->nns, 2 * a + q, r, c) = Rl[4 * (6 * (3 * q + r) + c) + l];
        for (int s = 0; s < m[l]; ++s)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 6; ++c) RB(L->tent, nodes[l][s], r, c) = Q4[4 * (c * TENT_ROWS + 3 * s + r) + l];
        round_tent(L, nodes[l], m[l]);
    }
}

/* Aggregates lo..hi-1, four at a time where four in a row fit TENT_LOCAL (AVX2), else one. */
static void tentative_lanes(wc_amg_level* L, wc_amg_level* N, int lo, int hi) {
    double Q4[4 * 6 * TENT_ROWS];
    int a = lo;
    while (a < hi) {
        int fit = a + 4 <= hi;
        for (int l = 0; fit && l < 4; ++l) fit = L->agg_start[a + l + 1] - L->agg_start[a + l] <= TENT_LOCAL;
        if (fit) {
            qr_lanes(L, N, a, Q4);
            a += 4;
        } else {
            tentative_range(L, N, a, a + 1);
            ++a;
        }
    }
}
static int lanes_vec(void) { return __builtin_cpu_supports("avx2"); }
#else
static void tentative_lanes(wc_amg_level* L, wc_amg_level* N, int lo, int hi) { tentative_range(L, N, lo, hi); }
static int lanes_vec(void) { return 0; }
#endif

static void tentative_any(wc_amg_level* L, wc_amg_level* N, int lo, int hi, int vec) {
    if (vec) tentative_lanes(L, N, lo, hi);
    else tentative_range(L, N, lo, hi);
}

void wc_amg_tentative_scalar(wc_amg_level* L, wc_amg_level* N, int n_agg) { tentative_range(L, N, 0, n_agg); }

void wc_amg_tentative(wc_amg_level* L, wc_amg_level* N, int n_agg, wc_par* par) {
    const int vec = lanes_vec();
    if (!par || par->threads <= 1) {
        tentative_any(L, N, 0, n_agg, vec);
        return;
    }
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(n_agg, wc_par_tid(), wc_par_nt(), &lo, &hi);
        tentative_any(L, N, lo, hi, vec);
    }
}
