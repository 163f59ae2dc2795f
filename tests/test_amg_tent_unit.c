/* The tentative prolongator's QR (core/amg_tent.c) with level 0's unit translations
 * (wc_amg_level.unit_translations: the translation columns' exactly-zero products skipped) against
 * the same QR with the flag off (every product computed): P_tent's rows, the next level's
 * near-null rows and its dead flags bit for bit, on aggregates of 1 to 40 nodes, about positions
 * with coordinates equal to the centre's (so the rotation columns hold -0 and +0) and random ones.
 * And the four-lane path (wc_amg_tentative, AVX2: four aggregates of different sizes at once)
 * against the one-aggregate reference (wc_amg_tentative_scalar), each flag, bit for bit.
 * Independently: each aggregate's Q columns are orthonormal (Q^T Q = I within rounding). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "check.h"
#include "test_support.h"

static uint64_t rng = 12345;
static double uniform(void) {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static void test_bits(void) {
    const int n = 600;
    double* x = malloc(sizeof(double) * 3 * n);
    int same = 1, lanes = 1, orth = 1;
    double worst = 0.0;
    for (int trial = 0; trial < 6; ++trial) {
        /* a flat sheet (y all equal: rotation entries +-0), a grid, then random clouds */
        for (int i = 0; i < n; ++i) {
            x[3 * i] = trial < 2 ? (double)(i % 25) / 24 : uniform();
            x[3 * i + 1] = trial == 0 ? 0.25 : uniform();
            x[3 * i + 2] = trial < 2 ? (double)(i / 25) / 23 : uniform();
        }
        /* aggregates of 1..40 nodes over a shuffled node order */
        int *agg_start = malloc(sizeof(int) * (n + 1)), *agg_node = malloc(sizeof(int) * n), n_agg = 0;
        for (int i = 0; i < n; ++i) agg_node[i] = i;
        for (int i = n - 1; i > 0; --i) {
            int j = (int)(uniform() * (i + 1)), t = agg_node[i];
            agg_node[i] = agg_node[j], agg_node[j] = t;
        }
        for (int at = 0; at < n; ++n_agg) {
            agg_start[n_agg] = at;
            int m = 1 + (int)(uniform() * 40);
            at = at + m < n ? at + m : n;
        }
        agg_start[n_agg] = n;
        double *nns = malloc(sizeof(double) * 18 * n), *tent[4], *nns2[4];
        unsigned char* dead[4];
        for (int f = 0; f < 4; ++f) { /* f 2, 3: f 0, 1 by the reference path */
            wc_amg_level L, N;
            memset(&L, 0, sizeof L), memset(&N, 0, sizeof N);
            L.n = n, L.nns = nns, L.agg_start = agg_start, L.agg_node = agg_node;
            wc_amg_rigid_modes(&L, x);
            CHECK(L.unit_translations == 1);
            L.unit_translations = f % 2 == 0; /* 0: the dense products */
            L.tent = tent[f] = malloc(sizeof(double) * 18 * n);
            N.n = 2 * n_agg, N.nns = nns2[f] = malloc(sizeof(double) * 36 * n_agg);
            N.dead = dead[f] = malloc(6 * (size_t)n_agg);
            if (f < 2) wc_amg_tentative(&L, &N, n_agg, NULL);
            else wc_amg_tentative_scalar(&L, &N, n_agg);
        }
        for (int f = 0; f < 2; ++f)
            lanes &= memcmp(tent[f], tent[f + 2], sizeof(double) * 18 * n) == 0 &&
                     memcmp(nns2[f], nns2[f + 2], sizeof(double) * 36 * n_agg) == 0 &&
                     memcmp(dead[f], dead[f + 2], 6 * (size_t)n_agg) == 0;
        same &= memcmp(tent[0], tent[1], sizeof(double) * 18 * n) == 0 &&
                memcmp(nns2[0], nns2[1], sizeof(double) * 36 * n_agg) == 0 && memcmp(dead[0], dead[1], 6 * (size_t)n_agg) == 0;
        for (int a = 0; a < n_agg; ++a) /* Q^T Q over the live columns */
            for (int c = 0; c < 6; ++c)
                for (int e = 0; e < 6; ++e) {
                    if (dead[0][6 * a + c] || dead[0][6 * a + e]) continue;
                    double dot = 0.0;
                    for (int k = agg_start[a]; k < agg_start[a + 1]; ++k)
                        for (int r = 0; r < 3; ++r) {
                            const double* t = tent[0] + 18 * (size_t)agg_node[k];
                            dot += t[9 * (c / 3) + 3 * r + c % 3] * t[9 * (e / 3) + 3 * r + e % 3];
                        }
                    const double err = fabs(dot - (c == e ? 1.0 : 0.0));
                    worst = fmax(worst, err);
                    orth &= err < 1e-12;
                }
        for (int f = 0; f < 4; ++f) free(tent[f]), free(nns2[f]), free(dead[f]);
        free(nns), free(agg_start), free(agg_node);
    }
    printf("  skipped zero products = dense QR: %s; four lanes = one aggregate at a time: %s; Q^T Q = I within %.1e\n",
           same ? "same bits" : "DIFFERENT", lanes ? "same bits" : "DIFFERENT", worst);
    CHECK(same);
    CHECK(lanes);
    CHECK(orth);
    free(x);
}

int main(void) {
    RUN_TEST(test_bits);
    return TEST_SUMMARY();
}
