/* The host's mesh before any processing: positions in the host's own vertex order (split seam
 * vertices included) and polygons as index lists into them. Built from a file (assimp) or from
 * host arrays. Units: metres (file units times unit_scale). */
#ifndef WEFT_CORE_SOURCE_MESH_H
#define WEFT_CORE_SOURCE_MESH_H
#include "alloc.h"
#include "diag.h"

typedef struct wc_source_mesh {
    int n_verts;          /* host vertices */
    double* pos;          /* (n_verts x 3) metres */
    int n_polys;          /* polygons with >= 3 corners */
    int* poly_start;      /* (n_polys + 1) offsets into poly_verts */
    int* poly_verts;      /* (poly_start[n_polys]) host vertex indices */
    int n_points;         /* point primitives seen and ignored */
    int n_lines;          /* line primitives seen and ignored */
    int n_meshes;         /* meshes the vertices came from (1 for host arrays) */
    double unit_scale;    /* metres per file unit that was applied */
    wc_allocator alloc;
} wc_source_mesh;

/* Build from host arrays: positions (n_verts x 3, metres after multiplying by scale) and
 * polygons given as per-polygon corner counts (n_polys) plus concatenated indices.
 * Polygons with 1 or 2 corners are counted as points/lines and ignored.
 * Fails on NaN/Inf positions, indices out of range, non-positive scale. */
weft_status wc_source_mesh_from_arrays(wc_source_mesh* out, const wc_allocator* alloc,
                                       const double* positions, int n_verts,
                                       const int* poly_sizes, int n_polys, const int* indices,
                                       double scale, wc_diag* diag);

/* Options for importing a file through assimp. */
typedef struct wc_import_opts {
    double scale;           /* metres per unit for unit-less formats (OBJ, PLY, ...); default 1 */
    const char* select;     /* name of one mesh or node to import (node: with its children);
                               NULL imports every mesh of the scene */
} wc_import_opts;

wc_import_opts wc_default_import_opts(void);

/* Import every mesh of a scene (node transforms applied) or the one selected by name.
 * FBX UnitScaleFactor is honoured (cm when it is 1). Errors name the file and assimp's reason. */
weft_status wc_import_file(wc_source_mesh* out, const wc_allocator* alloc, const char* path,
                           const wc_import_opts* opts, wc_diag* diag);

void wc_source_mesh_free(wc_source_mesh* m);

#endif
