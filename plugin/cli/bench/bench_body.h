/* Collision bodies of the benchmarks built in code (bench_body.c): a closed UV sphere, or an
 * ellipsoid (the sphere scaled per axis), as a triangle mesh wound counter-clockwise seen from
 * outside, handed to the library as a mesh collider of host arrays. */
#ifndef WEFT_CLI_BENCH_BODY_H
#define WEFT_CLI_BENCH_BODY_H
#include "weft/weft.h"

/* `rings` latitude bands (3 .. 4096) and 2 rings longitudes: 2 + (rings - 1) 2 rings vertices and
 * 4 rings (rings - 1) triangles, scaled by radii (3, m) about center (3, m). */
typedef struct bench_body {
    int n_verts, n_tris;
    float* x;               /* (n_verts x 3) m, world */
    int* tris;              /* (n_tris x 3) */
} bench_body;

/* The band count whose triangle count 4 m (m - 1) is nearest target_tris (m >= 3). */
int bench_body_rings(int target_tris);
/* 0, or -1 with msg (bands out of range, out of memory). */
int bench_body_create(bench_body* out, int rings, const double* center, const double* radii, char* msg, size_t size);
void bench_body_free(bench_body* b);
/* The body as a mesh collider def (its arrays borrowed: the body must outlive the cloth's
 * creation), identity transform. */
weft_mesh_collider_def bench_body_collider(const bench_body* b, double thickness, double friction);

#endif
