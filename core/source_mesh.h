/* The host's mesh before any processing: positions in the host's own vertex order (split seam
 * vertices included; for an OBJ file, its `v` lines; for FBX, its control points) and polygons as index lists into them.
 * Built from a file (assimp) or from host arrays. Units: metres (file units times unit_scale). */
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
    int n_meshes;         /* mesh instances the vertices came from (1 for host arrays) */
    double unit_scale;    /* metres per file unit that was applied (file unit x user scale) */
    wc_allocator alloc;
} wc_source_mesh;

/* Build from host arrays: positions (n_verts x 3, metres after multiplying by scale) and
 * polygons given as per-polygon corner counts (n_polys) plus concatenated indices.
 * Polygons with 1 or 2 corners are counted as points/lines and ignored; vertices keep the host's
 * order. On failure *out is zeroed: NULL array with a count > 0, negative count or a polygon
 * with < 1 corners (INVALID_ARGUMENT), index out of range (OUT_OF_RANGE), NaN/Inf position or
 * position x scale (NONFINITE), scale not finite or <= 0 (INVALID_ARGUMENT), no polygon with
 * >= 3 corners (EMPTY_MESH). Messages name the offending vertex/polygon/index. */
wc_status wc_source_mesh_from_arrays(wc_source_mesh* out, const wc_allocator* alloc,
                                       const double* positions, int n_verts,
                                       const int* poly_sizes, int n_polys, const int* indices,
                                       double scale, wc_diag* diag);

/* Options for importing a file through assimp. Zeroed fields mean the defaults. */
typedef struct wc_import_opts {
    double scale;           /* extra factor applied for every format on top of the file's own
                               unit: metres per unit for unit-less formats (OBJ, PLY, STL);
                               keep 1 for glTF (metres) and FBX (UnitScaleFactor is applied).
                               default 1; 0 means 1 */
    const char* select;     /* name of a node (every node of that name, each with its subtree)
                               or, when no node has that name, of a mesh (at every node that
                               uses it); NULL or "" imports every mesh of the scene */
} wc_import_opts;

wc_import_opts wc_default_import_opts(void);

/* Import every mesh of a scene (node transforms applied) or the one selected by name.
 * FBX UnitScaleFactor is honoured (cm when it is 1). Errors name the file and assimp's reason.
 *
 * Host vertex order, OBJ (a file or memory named .obj): the file's own `v` lines in file order,
 * one host vertex per line (duplicate lines at one position stay separate vertices and weld;
 * a line no polygon uses is a vertex without a particle). With select, only the `v` lines the
 * selected polygons use, still in file order. assimp does the import; obj_text.c reads which `v`
 * line each corner names and import_obj_order.c matches assimp's faces to the `f` lines (refusing
 * the file with IMPORT if a face matches none).
 * Host vertex order, FBX (binary or ASCII 7.x): the control points of each mesh Geometry, in file
 * order, used or not; with select, only those the selected polygons use, still in file order.
 * fbx_geometry.c reads the file's Vertices and PolygonVertexIndex (assimp 5.2 keeps no
 * control-point indices) and import_fbx_order.c matches assimp's polygons to the file's, one
 * block of vertices per (node, Geometry) in instance order, each with its node's transform (a
 * corner takes assimp's position; an unused control point its own, rounded to float as assimp
 * reads it, transformed). A corrupt geometry or a polygon that matches none refuses the file
 * with IMPORT rather than reporting a wrong order.
 * Host vertex order, other formats (glTF, PLY, ...): assimp's. The node tree is walked depth
 * first from the root (children in order); each mesh a node references is one instance (a mesh
 * used by two nodes is emitted twice), with the node's accumulated world transform applied.
 * Instances are concatenated in that order, each in assimp's vertex order after
 * aiProcess_JoinIdenticalVertices (which joins only vertices equal in every attribute, so UV
 * seams and split normals stay split).
 * Polygons keep their corner count (no triangulation); faces of 1 and 2 indices are counted in
 * n_points/n_lines and dropped.
 * Axes are left as the file has them (FBX UpAxis/FrontAxis are not applied; assimp 5.2.5 applies
 * node transforms only). unit_scale = file unit (FBX: UnitScaleFactor / 100, else 1) x scale.
 * Errors (*out zeroed): IO (cannot open/read), IMPORT (assimp failed, empty/UTF-16/binary-garbage
 * file, unknown select name: the message lists the names; an OBJ or FBX whose own order cannot
 * be read or matched), EMPTY_MESH (no meshes, or no polygon
 * with >= 3 corners), NONFINITE (NaN/Inf position), INVALID_ARGUMENT, OUT_OF_MEMORY.
 * Not thread-safe against other assimp users in the process: assimp's last-error string is
 * global. */
wc_status wc_import_file(wc_source_mesh* out, const wc_allocator* alloc, const char* path,
                           const wc_import_opts* opts, wc_diag* diag);

/* The same from a buffer in memory (assimp's read-from-memory): hint is the format's file
 * extension ("obj", "fbx", "gltf", "glb", "ply"; at most 15 characters), which messages use as
 * "<memory>.HINT". A format that refers to other files (an OBJ's mtllib, a glTF's external
 * buffers) makes assimp 5.2.5 open them by path from the file system: its memory reader falls
 * back to the default one (seen with strace: "mtllib /tmp/x.mtl" in a buffer opens /tmp/x.mtl).
 * Errors as wc_import_file (IMPORT for an empty buffer). */
wc_status wc_import_memory(wc_source_mesh* out, const wc_allocator* alloc, const void* data,
                             size_t size, const char* hint, const wc_import_opts* opts,
                             wc_diag* diag);

void wc_source_mesh_free(wc_source_mesh* m);

#endif
