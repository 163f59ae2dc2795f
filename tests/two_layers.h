/* Two horizontal sheets in one model (tests of self-collision and its in-solve pairs). */
#ifndef WEFT_TESTS_TWO_LAYERS_H
#define WEFT_TESTS_TWO_LAYERS_H
#include <stdio.h>
#include <stdlib.h>
#include "model.h"
#include "source_mesh.h"
#include "test_support.h"
#include "vec3.h"

/* Two sheets of n x n vertices and size s (one model, two components), horizontal at heights y0 and y1. */
static inline int two_layers(wc_model* m, int n, double s, double y0, double y1) {
    wc_source_mesh a;
    ts_quad_grid(&a, n, n, s, s, 0);
    int nv = a.n_verts, np = a.n_polys, ni = a.poly_start[np];
    double* pos = malloc(6 * (size_t)nv * sizeof(double));
    int* sizes = malloc(2 * (size_t)np * sizeof(int));
    int* idx = malloc(2 * (size_t)ni * sizeof(int));
    for (int L = 0; L < 2; ++L) {
        for (int v = 0; v < nv; ++v) {
            double* p = pos + 3 * (L * nv + v);
            v3_set(p, a.pos[3 * v] - 0.5 * s, L ? y1 : y0, a.pos[3 * v + 1] - 0.5 * s);
        }
        for (int k = 0; k < np; ++k) sizes[L * np + k] = a.poly_start[k + 1] - a.poly_start[k];
        for (int k = 0; k < ni; ++k) idx[L * ni + k] = a.poly_verts[k] + L * nv;
    }
    wc_source_mesh src;
    wc_diag d = {0};
    int ok = wc_source_mesh_from_arrays(&src, NULL, pos, 2 * nv, sizes, 2 * np, idx, 1.0, &d) == WEFT_OK;
    if (ok) {
        wc_model_def def = wc_default_model_def();
        ok = wc_model_build(m, &src, &def, NULL, &d) == WEFT_OK;
        wc_source_mesh_free(&src);
    }
    if (!ok) fprintf(stderr, "two_layers: %s\n", d.message);
    wc_source_mesh_free(&a);
    free(pos);
    free(sizes);
    free(idx);
    return ok;
}

#endif
