/* Triangle meshes generated for the mesh-collider tests: an icosphere and an axis-aligned box,
 * outward winding, in a fixed-size struct (no allocation). */
#ifndef WEFT_TESTS_TEST_MESHES_H
#define WEFT_TESTS_TEST_MESHES_H
#include <math.h>
#include <string.h>
#include "vec3.h"

typedef struct tmesh {
    int nv, nt;
    double x[3 * 2600];
    int t[3 * 5200];
} tmesh;

static inline int tm_vert(tmesh* m, double x, double y, double z) {
    v3_set(m->x + 3 * m->nv, x, y, z);
    return m->nv++;
}
static inline void tm_tri(tmesh* m, int a, int b, int c) {
    m->t[3 * m->nt] = a;
    m->t[3 * m->nt + 1] = b;
    m->t[3 * m->nt + 2] = c;
    ++m->nt;
}

/* Midpoint of edge a-b on the unit sphere (shared through a small linear lookup). */
static inline int midpoint(tmesh* m, int* ea, int* eb, int* em, int* ne, int a, int b) {
    for (int k = 0; k < *ne; ++k)
        if ((ea[k] == a && eb[k] == b) || (ea[k] == b && eb[k] == a)) return em[k];
    double p[3];
    v3_add(p, m->x + 3 * a, m->x + 3 * b);
    v3_scale(p, p, 1.0 / v3_norm(p));
    int v = tm_vert(m, p[0], p[1], p[2]);
    ea[*ne] = a;
    eb[*ne] = b;
    em[*ne] = v;
    ++*ne;
    return v;
}

/* Icosphere: icosahedron subdivided `levels` times, radius r around c, outward winding. */
static inline void icosphere(tmesh* m, int levels, double r, const double* c) {
    m->nv = m->nt = 0;
    double g = (1.0 + sqrt(5.0)) / 2.0;
    double v[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                       {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    int f[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int k = 0; k < 12; ++k) {
        double l = v3_norm(v[k]);
        tm_vert(m, v[k][0] / l, v[k][1] / l, v[k][2] / l);
    }
    for (int k = 0; k < 20; ++k) tm_tri(m, f[k][0], f[k][1], f[k][2]);
    static int ea[8000], eb[8000], em[8000];
    for (int lv = 0; lv < levels; ++lv) {
        int ne = 0, nt = m->nt;
        static int old[3 * 5200];
        memcpy(old, m->t, 3 * (size_t)nt * sizeof(int));
        m->nt = 0;
        for (int k = 0; k < nt; ++k) {
            int a = old[3 * k], b = old[3 * k + 1], cc = old[3 * k + 2];
            int ab = midpoint(m, ea, eb, em, &ne, a, b), bc = midpoint(m, ea, eb, em, &ne, b, cc),
                ca = midpoint(m, ea, eb, em, &ne, cc, a);
            tm_tri(m, a, ab, ca);
            tm_tri(m, b, bc, ab);
            tm_tri(m, cc, ca, bc);
            tm_tri(m, ab, bc, ca);
        }
    }
    for (int k = 0; k < m->nv; ++k) {
        double* p = m->x + 3 * k;
        for (int q = 0; q < 3; ++q) p[q] = c[q] + r * p[q];
    }
}

/* Axis-aligned box [lo, hi], 12 triangles, outward winding. */
static inline void box(tmesh* m, const double* lo, const double* hi) {
    m->nv = m->nt = 0;
    for (int k = 0; k < 8; ++k) tm_vert(m, (k & 1) ? hi[0] : lo[0], (k & 2) ? hi[1] : lo[1], (k & 4) ? hi[2] : lo[2]);
    /* faces as quads a b c d counter-clockwise seen from outside */
    int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int k = 0; k < 6; ++k) {
        tm_tri(m, q[k][0], q[k][1], q[k][2]);
        tm_tri(m, q[k][0], q[k][2], q[k][3]);
    }
}

#endif
