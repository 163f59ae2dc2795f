/* The sewing tests' host-pair sheets (test_sew.c, test_gpu_sew.c, test_api_gpu_sew.c): two square
 * 0.3 m sheets of SHEET_N x SHEET_N vertices in parallel planes `apart` metres apart, A's top row
 * at height TOP (sew_tube.h); vertex (i, j) of sheet `panel` (j = 0 the top row) is
 * panel SHEET_N^2 + j SHEET_N + i. */
#ifndef WEFT_TESTS_SEW_SHEETS_H
#define WEFT_TESTS_SEW_SHEETS_H
#include "sew_tube.h"

#define SHEET_N 7

static inline void two_sheets(double* pos, int* sizes, int* idx, double apart) {
    int f = 0;
    for (int panel = 0; panel < 2; ++panel) {
        for (int j = 0; j < SHEET_N; ++j)
            for (int i = 0; i < SHEET_N; ++i) {
                double* p = pos + 3 * (panel * SHEET_N * SHEET_N + j * SHEET_N + i);
                p[0] = 0.3 * i / (SHEET_N - 1);
                p[1] = TOP - 0.3 * j / (SHEET_N - 1);
                p[2] = panel * apart;
            }
        for (int j = 0; j + 1 < SHEET_N; ++j)
            for (int i = 0; i + 1 < SHEET_N; ++i, ++f) {
                int a = panel * SHEET_N * SHEET_N + j * SHEET_N + i;
                sizes[f] = 4;
                idx[4 * f] = a;
                idx[4 * f + 1] = a + 1;
                idx[4 * f + 2] = a + 1 + SHEET_N;
                idx[4 * f + 3] = a + SHEET_N;
            }
    }
}

#endif
