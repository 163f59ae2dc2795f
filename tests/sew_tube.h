/* The sewing tests' tube (test_sew.c, test_sew_api.c): two arched quad panels whose long edges
 * lie GAP apart with panel B's rows offset by half a row, so every seam pairs a vertex with the
 * middle of the other panel's boundary edge (vertex to edge, never vertex to vertex). */
#ifndef WEFT_TESTS_SEW_TUBE_H
#define WEFT_TESTS_SEW_TUBE_H
#include <math.h>
#include <stdlib.h>
#include "model.h"

/* ---- the tube: two arched panels, long edges within GAP, rows offset by half a row --------- */

#define NA 13           /* rows of panel A; panel B has NA - 1 */
#define NW 8            /* quads across a panel */
#define DY 0.025        /* row spacing (m) */
#define WIDTH 0.2       /* m */
#define ARCH 0.08       /* m: panel A bulges to +Z, B to -Z */
#define GAP 0.0005      /* m: B's long edges sit this far behind A's */
#define TOP 1.0         /* m: height of A's top row */
#define SEW 0.002       /* m: the sew distance used */
/* A's long-edge vertices but the two ends, and all of B's, on both long edges */
#define TUBE_SEAMS (2 * ((NA - 2) + (NA - 1)))

typedef struct tube {
    int nv, nf, na_verts;
    double* pos;    /* (nv x 3) */
    int* sizes;     /* (nf) */
    int* idx;       /* (4 nf) */
} tube;

static inline int tube_vertex(int panel, int i, int j) { return (panel ? NA * (NW + 1) : 0) + i * (NW + 1) + j; }

static inline void tube_make(tube* t) {
    t->na_verts = NA * (NW + 1);
    t->nv = t->na_verts + (NA - 1) * (NW + 1);
    t->nf = (NA - 1) * NW + (NA - 2) * NW;
    t->pos = calloc(3 * (size_t)t->nv, sizeof(double));
    t->sizes = malloc(sizeof(int) * (size_t)t->nf);
    t->idx = malloc(4 * sizeof(int) * (size_t)t->nf);
    int f = 0;
    for (int panel = 0; panel < 2; ++panel) {
        int rows = panel ? NA - 1 : NA;
        for (int i = 0; i < rows; ++i)
            for (int j = 0; j <= NW; ++j) {
                double* p = t->pos + 3 * tube_vertex(panel, i, j);
                double bulge = ARCH * sin(3.14159265358979323846 * j / NW);
                p[0] = -0.5 * WIDTH + WIDTH * j / NW;
                p[1] = TOP - (i + 0.5 * panel) * DY;
                p[2] = panel ? -bulge - GAP : bulge;
            }
        for (int i = 0; i + 1 < rows; ++i)
            for (int j = 0; j < NW; ++j, ++f) {
                t->sizes[f] = 4;
                int* q = t->idx + 4 * f;
                q[0] = tube_vertex(panel, i, j);
                q[1] = tube_vertex(panel, i, j + 1);
                q[2] = tube_vertex(panel, i + 1, j + 1);
                q[3] = tube_vertex(panel, i + 1, j);
            }
    }
}

static inline void tube_free(tube* t) {
    free(t->pos);
    free(t->sizes);
    free(t->idx);
}

static inline wc_status tube_model(wc_model* m, const wc_model_def* def, wc_diag* d) {
    tube t;
    tube_make(&t);
    wc_source_mesh src;
    wc_status st = wc_source_mesh_from_arrays(&src, NULL, t.pos, t.nv, t.sizes, t.nf, t.idx, 1.0, d);
    if (st == WC_OK) st = wc_model_build(m, &src, def, NULL, d);
    wc_source_mesh_free(&src);
    tube_free(&t);
    return st;
}

#endif
