/* A pair level's 6x6 block inverses (core/amg_pair_inverse.c): the four-lane AVX2 path
 * (wc_amg_inverse6_x4) against the scalar Gauss-Jordan (wc_amg_inverse6), bit for bit, and the
 * same success flag per lane, on matrices that pivot (small or zero diagonal entries, rows to
 * swap), hold exact zeros (the row updates skipped), tie between pivot candidates, are singular, or hold inf/NaN; lanes of one
 * batch mixing these. Independently: M M^-1 = I within rounding for every lane that succeeded.
 * Where the CPU has no AVX2, _x4 is the scalar loop per lane (said so). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include "amg.h"
#include "check.h"
#include "test_support.h"

static uint64_t rng = 987654321;
static double uniform(void) {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* matrix kind 0..7 into M (row-major 6x6) */
static void make(int kind, double* M) {
    for (int k = 0; k < 36; ++k) M[k] = uniform() * 2.0 - 1.0;
    switch (kind) {
    case 0: /* diagonally dominant (no swaps) */
        for (int r = 0; r < 6; ++r) M[7 * r] += 8.0;
        break;
    case 1: /* tiny diagonal: a swap at every column */
        for (int r = 0; r < 6; ++r) M[7 * r] *= 1e-6;
        break;
    case 2: /* sparse: exact zeros, including under pivots (skipped row updates), -0 too */
        for (int k = 0; k < 36; ++k)
            if (uniform() < 0.5) M[k] = uniform() < 0.5 ? 0.0 : -0.0;
        for (int r = 0; r < 6; ++r) M[7 * r] = 1.0 + uniform();
        break;
    case 3: /* singular: row 4 = row 1 + row 2 */
        for (int q = 0; q < 6; ++q) M[24 + q] = M[6 + q] + M[12 + q];
        break;
    case 4: /* a pivot below 1e-13 x the largest diagonal entry */
        for (int q = 0; q < 6; ++q) M[6 * q + 3] = M[6 * q + 3] * 1e-15;
        M[0] = 1e3;
        break;
    case 5: /* inf or NaN */
        M[(int)(uniform() * 36)] = uniform() < 0.5 ? INFINITY : NAN;
        break;
    case 6: /* small integers: ties between pivot candidates (the first stays), zeros, some singular */
        for (int k = 0; k < 36; ++k) M[k] = (double)((int)(uniform() * 7) - 3);
        break;
    default: /* symmetric positive definite, a pair block's usual shape */
        for (int r = 0; r < 6; ++r)
            for (int c = 0; c < r; ++c) M[6 * c + r] = M[6 * r + c];
        for (int r = 0; r < 6; ++r) M[7 * r] = fabs(M[7 * r]) + 6.0;
        break;
    }
}

static void test_lanes_same_bits(void) {
    int same = 1, flags = 1, exact = 1, fails = 0, oks = 0;
    double worst = 0.0;
    for (int batch = 0; batch < 2000; ++batch) {
        double orig[4][36], one[4][36], M4[4 * 36];
        int ok1[4], kind[4];
        for (int l = 0; l < 4; ++l) {
            kind[l] = batch < 8 ? batch : (int)(uniform() * 8);
            make(kind[l], orig[l]);
            memcpy(one[l], orig[l], sizeof one[l]);
            ok1[l] = wc_amg_inverse6(one[l]);
            for (int k = 0; k < 36; ++k) M4[4 * k + l] = orig[l][k];
        }
        const unsigned ok4 = wc_amg_inverse6_x4(M4);
        for (int l = 0; l < 4; ++l) {
            flags &= ok1[l] == (int)((ok4 >> l) & 1u);
            if (!ok1[l]) {
                ++fails;
                continue;
            }
            ++oks;
            for (int k = 0; k < 36; ++k) same &= memcmp(&M4[4 * k + l], &one[l][k], sizeof(double)) == 0;
            if (kind[l] == 5) continue; /* an inf entry can invert (1 / inf = 0); inf x 0 is NaN */
            for (int r = 0; r < 6; ++r) /* M M^-1 = I, relative to |M| |M^-1| */
                for (int c = 0; c < 6; ++c) {
                    double s = 0.0, mag = 0.0;
                    for (int k = 0; k < 6; ++k) {
                        s += orig[l][6 * r + k] * one[l][6 * k + c];
                        mag += fabs(orig[l][6 * r + k] * one[l][6 * k + c]);
                    }
                    const double err = fabs(s - (r == c ? 1.0 : 0.0)) / (mag > 1.0 ? mag : 1.0);
                    worst = fmax(worst, err);
                    exact &= err < 1e-9;
                }
        }
    }
    printf("  %s: %d inverses, %d failed (both paths); same bits: %s, same flags: %s; |M M^-1 - I| <= %.1e\n",
           wc_amg_inverse6_vec() ? "AVX2 lanes" : "no AVX2 (scalar per lane)", oks, fails, same ? "yes" : "NO",
           flags ? "yes" : "NO", worst);
    CHECK(same);
    CHECK(flags);
    CHECK(exact);
    CHECK(fails > 0 && oks > 0);
}

int main(void) {
    RUN_TEST(test_lanes_same_bits);
    return TEST_SUMMARY();
}
