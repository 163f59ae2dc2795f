/* The multigrid's tentative prolongator with the rigid-body modes as near-null space (amg.h,
 * wc_amg_opts.rotations): level 0's six modes per node from the rest positions, and per
 * aggregate a QR of its (3 n_agg) x 6 block of near-null rows. Q is P_tent's rows (two 3x3
 * blocks per fine node: to coarse nodes 2a and 2a + 1), R is the next level's near-null space.
 * Built at wc_amg_create about the rest positions, and again (no allocation) by every setup
 * about the solver's current positions when wc_amg_opts.current_positions is set (amg.h). */
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

void wc_amg_tentative(wc_amg_level* L, wc_amg_level* N, int n_agg, wc_par* par) {
    if (!par || par->threads <= 1) {
        tentative_range(L, N, 0, n_agg);
        return;
    }
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(n_agg, wc_par_tid(), wc_par_nt(), &lo, &hi);
        tentative_range(L, N, lo, hi);
    }
}
