/* Tessellation of collider shapes. */
#include "render_shapes.h"

#include <math.h>

static const double kPi = 3.14159265358979323846;

void wg_capsule_counts(int slices, int stacks, int* n_vertices, int* n_indices) {
    int rings = 2 * (stacks + 1);
    *n_vertices = rings * (slices + 1);
    *n_indices = 6 * (rings - 1) * slices;
}

void wg_capsule_build(float radius, float half_height, int slices, int stacks, float* vertices,
                      unsigned* indices) {
    int rings = 2 * (stacks + 1);
    float* v = vertices;
    for (int k = 0; k < rings; ++k) {
        /* polar angle from +y: top hemisphere rings 0..stacks reach the equator, bottom ones
         * stacks+1..rings-1 start at the equator and reach the bottom pole */
        int top = k <= stacks;
        int j = top ? k : k - (stacks + 1);
        double phi = (top ? j : stacks + j) * 0.5 * kPi / stacks;
        double ny = cos(phi), radial = sin(phi);
        double cy = top ? half_height : -half_height;
        for (int i = 0; i <= slices; ++i) {
            double theta = 2.0 * kPi * i / slices;
            double nx = radial * cos(theta), nz = radial * sin(theta);
            *v++ = (float)(radius * nx);
            *v++ = (float)(cy + radius * ny);
            *v++ = (float)(radius * nz);
            *v++ = (float)nx;
            *v++ = (float)ny;
            *v++ = (float)nz;
        }
    }
    unsigned* t = indices;
    unsigned row = (unsigned)slices + 1;
    for (int k = 0; k + 1 < rings; ++k)
        for (int i = 0; i < slices; ++i) {
            unsigned a = (unsigned)k * row + (unsigned)i, b = a + row, c = b + 1, d = a + 1;
            /* a above b; d and c one slice further (theta growing): (a, c, b) and (a, d, c)
             * face outward */
            *t++ = a;
            *t++ = c;
            *t++ = b;
            *t++ = a;
            *t++ = d;
            *t++ = c;
        }
}

void wg_plane_build(float cx, float cz, float half, float* vertices, unsigned* indices) {
    const float xs[4] = {cx - half, cx - half, cx + half, cx + half};
    const float zs[4] = {cz - half, cz + half, cz + half, cz - half};
    for (int i = 0; i < 4; ++i) {
        float* v = vertices + WG_VERTEX_FLOATS * i;
        v[0] = xs[i];
        v[1] = 0.0f;
        v[2] = zs[i];
        v[3] = 0.0f;
        v[4] = 1.0f;
        v[5] = 0.0f;
    }
    const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; ++i) indices[i] = idx[i];
}

float wg_nice_step(float x) {
    double p = pow(10.0, floor(log10((double)x)));
    double m = (double)x / p;
    double step = m >= 5.0 ? 5.0 : m >= 2.0 ? 2.0 : 1.0;
    return (float)(step * p);
}
