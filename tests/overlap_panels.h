/* Two overlapping panels for the self-collision tests (test_self_collide.c, test_self_near.c): a
 * horizontal one (5 x 5 vertices, 0.1 m, y = 0) and a vertical one (x = 0.097, reaching 1 mm below
 * the first's plane, its columns 3 mm off the first's). Built apart (sewn 0) they cross at rest;
 * sewn (1) at 5 mm, every crossing pair has a particle sewn to the other element. */
#ifndef WEFT_TESTS_OVERLAP_PANELS_H
#define WEFT_TESTS_OVERLAP_PANELS_H
#include "check.h"
#include "model.h"
#include "source_mesh.h"
#include "vec3.h"

static inline void overlap_panels(wc_model* m, int sewn) {
    double pos[2 * 25 * 3];
    int idx[2 * 16 * 4], sizes[2 * 16];
    for (int i = 0; i < 5; ++i)
        for (int j = 0; j < 5; ++j) {
            v3_set(pos + 3 * (5 * i + j), 0.025 * i, 0.0, 0.025 * j);
            v3_set(pos + 3 * (25 + 5 * i + j), 0.097, -0.001 + 0.0125 * i, 0.003 + 0.025 * j);
        }
    int f = 0;
    for (int L = 0; L < 2; ++L)
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j, ++f) {
                int o = 25 * L + 5 * i + j;
                sizes[f] = 4;
                idx[4 * f] = o;
                idx[4 * f + 1] = o + 1;
                idx[4 * f + 2] = o + 6;
                idx[4 * f + 3] = o + 5;
            }
    wc_source_mesh src;
    wc_diag d = {0};
    CHECK(wc_source_mesh_from_arrays(&src, NULL, pos, 50, sizes, 32, idx, 1.0, &d) == WC_OK);
    wc_model_def def = wc_default_model_def();
    def.sew_distance = sewn ? 0.005 : 0.0;
    CHECK(wc_model_build(m, &src, &def, NULL, &d) == WC_OK);
    wc_source_mesh_free(&src);
}

#endif
