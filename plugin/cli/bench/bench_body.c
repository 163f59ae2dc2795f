/* Collision bodies of the benchmarks built in code (bench_body.h): a closed UV sphere (or an
 * ellipsoid) wound counter-clockwise seen from outside, the outward side weft.h's mesh colliders
 * expect. */
#define _POSIX_C_SOURCE 200809L
#include "bench_body.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void set3(double* v, double x, double y, double z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

int bench_body_rings(int target_tris) {
    /* 4 m (m - 1) triangles: 2 nlon (m - 1) with nlon = 2 m longitudes, m latitude bands */
    int best = 3;
    for (int m = 3; m <= 4096; ++m)
        if (fabs(4.0 * m * (m - 1) - target_tris) < fabs(4.0 * best * (best - 1) - target_tris)) best = m;
    return best;
}

int bench_body_create(bench_body* out, int rings, const double* center, const double* radii, char* msg, size_t size) {
    memset(out, 0, sizeof *out);
    if (rings < 3 || rings > 4096) {
        snprintf(msg, size, "bench body: %d latitude bands (expected 3 to 4096)", rings);
        return -1;
    }
    const int m = rings, nlon = 2 * m;
    const int nv = 2 + (m - 1) * nlon, nt = 2 * nlon * (m - 1);
    double* x = malloc(sizeof(double) * 3 * (size_t)nv);
    out->x = malloc(sizeof(float) * 3 * (size_t)nv);
    out->tris = malloc(sizeof(int) * 3 * (size_t)nt);
    if (!x || !out->x || !out->tris) {
        free(x);
        bench_body_free(out);
        snprintf(msg, size, "bench body: out of memory for %d triangles", nt);
        return -1;
    }
    const double pi = 3.14159265358979323846;
    /* vertex 0 the north pole (+y), 1 + (i - 1) nlon + j ring i (1 .. m - 1) longitude j, nv - 1 south */
    set3(x, 0.0, 1.0, 0.0);
    for (int i = 1; i < m; ++i) {
        const double th = pi * i / m;
        for (int j = 0; j < nlon; ++j) {
            const double ph = 2.0 * pi * j / nlon;
            set3(x + 3 * (1 + (i - 1) * nlon + j), sin(th) * cos(ph), cos(th), sin(th) * sin(ph));
        }
    }
    set3(x + 3 * (nv - 1), 0.0, -1.0, 0.0);
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
        for (int d = 0; d < 3; ++d) {
            e1[d] = x[3 * a[1] + d] - x[3 * a[0] + d];
            e2[d] = x[3 * a[2] + d] - x[3 * a[0] + d];
            c[d] = x[3 * a[0] + d] + x[3 * a[1] + d] + x[3 * a[2] + d];
        }
        set3(n, e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]);
        if (n[0] * c[0] + n[1] * c[1] + n[2] * c[2] < 0) {
            const int s = a[1];
            a[1] = a[2], a[2] = s;
        }
    }
    for (int v = 0; v < nv; ++v)
        for (int d = 0; d < 3; ++d) out->x[3 * v + d] = (float)(center[d] + radii[d] * x[3 * v + d]);
    free(x);
    out->n_verts = nv;
    out->n_tris = nt;
    return 0;
}

void bench_body_free(bench_body* b) {
    free(b->x);
    free(b->tris);
    memset(b, 0, sizeof *b);
}

weft_mesh_collider_def bench_body_collider(const bench_body* b, double thickness, double friction) {
    weft_mesh_collider_def d = weft_default_mesh_collider_def();
    d.mesh.positions = b->x;
    d.mesh.n_vertices = b->n_verts;
    d.mesh.indices = b->tris;
    d.mesh.n_faces = b->n_tris;   /* face_sizes NULL: triangles */
    d.thickness = thickness;
    d.friction = friction;
    return d;
}
