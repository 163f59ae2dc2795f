/* A small host-array cloth for the API harnesses: an n x n grid of quads, horizontal at height
 * y, 1 m wide, as a host would pass it (float positions, face sizes, indices). */
#ifndef WEFT_FUZZ_GRID_H
#define WEFT_FUZZ_GRID_H
#include "weft/weft.h"

#define FUZZ_GRID_MAX 8

typedef struct fuzz_grid {
    int n;
    float pos[FUZZ_GRID_MAX * FUZZ_GRID_MAX * 3];
    int sizes[(FUZZ_GRID_MAX - 1) * (FUZZ_GRID_MAX - 1)];
    int idx[(FUZZ_GRID_MAX - 1) * (FUZZ_GRID_MAX - 1) * 4];
} fuzz_grid;

static inline void fuzz_grid_make(fuzz_grid* g, int n, float y) {
    g->n = n;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float* p = &g->pos[3 * (j * n + i)];
            p[0] = (float)i / (float)(n - 1) - 0.5f;
            p[1] = y;
            p[2] = (float)j / (float)(n - 1) - 0.5f;
        }
    int f = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++f) {
            g->sizes[f] = 4;
            int* q = &g->idx[4 * f];
            q[0] = j * n + i;
            q[1] = (j + 1) * n + i;
            q[2] = (j + 1) * n + i + 1;
            q[3] = j * n + i + 1;
        }
}

static inline void fuzz_grid_mesh(const fuzz_grid* g, weft_mesh_desc* m) {
    m->path = NULL;
    m->positions = g->pos;
    m->n_vertices = g->n * g->n;
    m->face_sizes = g->sizes;
    m->n_faces = (g->n - 1) * (g->n - 1);
    m->indices = g->idx;
}

static const float fuzz_identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

#endif
