/* An FBX file's own mesh geometry: for each Geometry object of type "Mesh", its control points
 * (`Vertices`) and polygons (`PolygonVertexIndex`) as the file stores them. assimp imports the
 * geometry; this reads only what assimp's output loses (which control point each polygon corner
 * is), so that a file mesh can be reported in the file's order (import_fbx_order.c). */
#ifndef WEFT_CORE_FBX_GEOMETRY_H
#define WEFT_CORE_FBX_GEOMETRY_H
#include "alloc.h"
#include "diag.h"
#include <stddef.h>

typedef struct wc_fbx_geometry {
    int n_points;         /* control points */
    double* points;       /* (n_points x 3) file units, in the geometry's own space */
    int n_polys;          /* polygons, every corner count (1 and 2 included) */
    int* poly_start;      /* (n_polys + 1) offsets into poly_points */
    int* poly_points;     /* control point of each corner, in the file's order */
} wc_fbx_geometry;

typedef struct wc_fbx_geometries {
    int n;                /* Geometry objects of type "Mesh", in file order */
    wc_fbx_geometry* g;
    wc_allocator alloc;
} wc_fbx_geometries;

/* Read data (size bytes: a whole binary FBX 7.x, header "Kaydara FBX Binary  ", or ASCII FBX 7.x
 * text; need not end in NUL). Binary: node records with 32-bit offsets below version 7500 and
 * 64-bit from 7500; array properties 'd', 'f', 'i', 'l' raw or zlib-deflated. ASCII:
 * `Vertices: *N { a: ... }` and `PolygonVertexIndex: *N { a: ... }`. Every offset, count and
 * inflated size is checked against the data. PolygonVertexIndex marks the last corner of each
 * polygon as -(i+1); corners after the last marked one form one more polygon.
 * Errors (*out zeroed): IMPORT naming the file, the Geometry (its index in file order) and what
 * is wrong (a record past the end of its list, an array count that does not fit its bytes, an
 * inflate failure, an unknown encoding, an ASCII array not in that form or with another count
 * of numbers, a Geometry block not closed, an index outside the control points (none without
 * `Vertices`), a `Vertices` count not a multiple of 3); OUT_OF_MEMORY. A file without mesh
 * Geometry objects gives n = 0; a Geometry without PolygonVertexIndex has no polygons. */
wc_status wc_fbx_geometry_read(wc_fbx_geometries* out, const wc_allocator* alloc,
                                 const void* data, size_t size, const char* name, wc_diag* diag);

void wc_fbx_geometry_free(wc_fbx_geometries* set);

#endif
