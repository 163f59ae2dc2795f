/* Collision bodies of the benchmarks built in code: a closed UV sphere (or an ellipsoid: the
 * sphere scaled per axis) as a triangle mesh, wound counter-clockwise seen from outside (the
 * outward side mesh_collider.h expects), and its mesh collider. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cmd_bench.h"
#include "vec3.h"

int bench_body_rings(int target_tris) {
    /* 4 m (m - 1) triangles: 2 nlon (m - 1) with nlon = 2 m longitudes, m latitude bands */
    int best = 3;
    for (int m = 3; m <= 4096; ++m)
        if (fabs(4.0 * m * (m - 1) - target_tris) < fabs(4.0 * best * (best - 1) - target_tris)) best = m;
    return best;
}

wc_status bench_body_create(bench_body* out, int rings, const double* center, const double* radii, double thickness,
                              double friction, wc_diag* diag) {
    memset(out, 0, sizeof *out);
    if (rings < 3 || rings > 4096)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "bench body: %d latitude bands (expected 3 to 4096)", rings);
    const int m = rings, nlon = 2 * m;
    const int nv = 2 + (m - 1) * nlon, nt = 2 * nlon * (m - 1);
    out->x = malloc(sizeof(double) * 3 * (size_t)nv);
    out->tris = malloc(sizeof(int) * 3 * (size_t)nt);
    if (!out->x || !out->tris) {
        bench_body_free(out);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "bench body: out of memory for %d triangles", nt);
    }
    const double pi = 3.14159265358979323846;
    /* vertex 0 the north pole (+y), 1 + (i - 1) nlon + j ring i (1 .. m - 1) longitude j, nv - 1 south */
    double* x = out->x;
    v3_set(x, 0.0, 1.0, 0.0);
    for (int i = 1; i < m; ++i) {
        const double th = pi * i / m;
        for (int j = 0; j < nlon; ++j) {
            const double ph = 2.0 * pi * j / nlon;
            v3_set(x + 3 * (1 + (i - 1) * nlon + j), sin(th) * cos(ph), cos(th), sin(th) * sin(ph));
        }
    }
    v3_set(x + 3 * (nv - 1), 0.0, -1.0, 0.0);
    int* t = out->tris;
    int k = 0;
#define RING(i, j) (1 + ((i) - 1) * nlon + ((j) % nlon))
    for (int j = 0; j < nlon; ++j) {
        int* a = t + 3 * k++;
        a[0] = 0, a[1] = RING(1, j), a[2] = RING(1, j + 1);
    }
    for (int i = 1; i < m - 1; ++i)
        for (int j = 0; j < nlon; ++j) {
            int* a = t + 3 * k++;
            a[0] = RING(i, j), a[1] = RING(i + 1, j), a[2] = RING(i + 1, j + 1);
            a = t + 3 * k++;
            a[0] = RING(i, j), a[1] = RING(i + 1, j + 1), a[2] = RING(i, j + 1);
        }
    for (int j = 0; j < nlon; ++j) {
        int* a = t + 3 * k++;
        a[0] = nv - 1, a[1] = RING(m - 1, j + 1), a[2] = RING(m - 1, j);
    }
#undef RING
    /* outward winding, checked on the unit sphere: the normal of every triangle points away from
       the centre (flipped where it does not, so the rule holds whatever the loops above do) */
    for (int q = 0; q < nt; ++q) {
        int* a = t + 3 * q;
        double e1[3], e2[3], n[3], c[3];
        v3_sub(e1, x + 3 * a[1], x + 3 * a[0]);
        v3_sub(e2, x + 3 * a[2], x + 3 * a[0]);
        v3_cross(n, e1, e2);
        for (int d = 0; d < 3; ++d) c[d] = x[3 * a[0] + d] + x[3 * a[1] + d] + x[3 * a[2] + d];
        if (v3_dot(n, c) < 0) {
            const int s = a[1];
            a[1] = a[2], a[2] = s;
        }
    }
    for (int v = 0; v < nv; ++v)
        for (int d = 0; d < 3; ++d) x[3 * v + d] = center[d] + radii[d] * x[3 * v + d];
    out->n_verts = nv;
    out->n_tris = nt;
    const wc_status st = wc_mesh_collider_create(&out->mesh, out->x, nv, out->tris, nt, thickness, friction, NULL, diag);
    if (st != WC_OK) bench_body_free(out);
    return st;
}

void bench_body_free(bench_body* b) {
    if (b->mesh) wc_mesh_collider_destroy(b->mesh);
    free(b->x);
    free(b->tris);
    memset(b, 0, sizeof *b);
}
