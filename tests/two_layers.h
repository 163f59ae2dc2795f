/* Two horizontal sheets in one model (tests of self-collision and its in-solve pairs). */
#ifndef WEFT_TESTS_TWO_LAYERS_H
#define WEFT_TESTS_TWO_LAYERS_H
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "model.h"
#include "state.h"
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
    int ok = wc_source_mesh_from_arrays(&src, NULL, pos, 2 * nv, sizes, 2 * np, idx, 1.0, &d) == WC_OK;
    if (ok) {
        wc_model_def def = wc_default_model_def();
        ok = wc_model_build(m, &src, &def, NULL, &d) == WC_OK;
        wc_source_mesh_free(&src);
    }
    if (!ok) fprintf(stderr, "two_layers: %s\n", d.message);
    wc_source_mesh_free(&a);
    free(pos);
    free(sizes);
    free(idx);
    return ok;
}

/* The positions of two_layers(m, n, s, ...) with the top layer (host vertices n^2 .. 2 n^2 - 1)
 * shifted by a third of a cell along x and a fifth along z, so that its vertices sit over the
 * bottom layer's triangles. */
static inline void two_layers_shifted(const wc_model* m, int n, double s, double* x) {
    double cell = s / (n - 1);
    memcpy(x, m->rest_pos, 3 * (size_t)m->n_particles * sizeof(double));
    for (int v = n * n; v < 2 * n * n; ++v) {
        int p = m->host_to_particle[v];
        x[3 * p] += cell / 3.0;
        x[3 * p + 2] += cell / 5.0;
    }
}

/* A state of two_layers(m, n, s, ...) at two_layers_shifted's positions, its top layer moving
 * down at `speed` m/s; NULL when it cannot be made. */
static inline wc_state* two_layers_approaching(const wc_model* m, int n, double s, double speed, const wc_sim_def* def) {
    wc_state* st = NULL;
    wc_diag d = {0};
    if (wc_state_create(&st, m, def, NULL, &d) != WC_OK) {
        fprintf(stderr, "two_layers_approaching: %s\n", d.message);
        return NULL;
    }
    int np = m->n_particles;
    double* x = malloc(3 * (size_t)np * sizeof(double));
    double* v = calloc(3 * (size_t)np, sizeof(double));
    two_layers_shifted(m, n, s, x);
    for (int hv = n * n; hv < 2 * n * n; ++hv) v[3 * m->host_to_particle[hv] + 1] = -speed;
    int ok = wc_state_set_positions(st, x, v, &d) == WC_OK;
    free(x);
    free(v);
    if (!ok) {
        fprintf(stderr, "two_layers_approaching: %s\n", d.message);
        wc_state_destroy(st);
        return NULL;
    }
    return st;
}

#endif
