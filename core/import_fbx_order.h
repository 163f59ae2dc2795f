/* Which control point of an FBX file each polygon corner of assimp's import is, so that the
 * import can number its vertices by the file's control points (import_assimp.c) instead of
 * assimp's order. */
#ifndef WEFT_CORE_IMPORT_FBX_ORDER_H
#define WEFT_CORE_IMPORT_FBX_ORDER_H
#include "fbx_geometry.h"
#include "import_order.h"
#include <stddef.h>

struct aiScene;

/* inst: the import's mesh instances in the order it concatenates them (n_inst). assimp 5.2's FBX
 * importer converts each mesh Geometry once, into one mesh per material (materials in order of
 * first use), each holding that material's polygons in file order with one vertex per corner,
 * corners in file order. Each mesh is matched against the geometries in file order: every face,
 * in order, against the next polygon of that geometry no other mesh has taken with the same
 * corner count and every corner's position equal to its control point's (within 1e-5 relative
 * plus 1e-6 of the geometry's largest coordinate); the first geometry where all faces match is
 * the mesh's. Geometries identical in their polygons are told apart by file order only.
 * Writes out: one block of host vertices per (node, geometry) pair in the order of the first
 * instance that has it (a geometry split by material stays one block; a geometry at two nodes
 * is two blocks), each block the geometry's control points in file order, positions as the
 * file has them (rounded to float, as assimp reads them) with that node's transform; and each
 * corner's host vertex. Errors (*out zeroed): IMPORT naming the mesh and face that matches no
 * polygon (the file's order cannot be kept), NONFINITE (a control point), OUT_OF_RANGE (more
 * than INT_MAX vertices), OUT_OF_MEMORY. */
wc_status wc_fbx_file_order(const struct aiScene* s, const wc_import_instance* inst,
                              size_t n_inst, const wc_fbx_geometries* geo, wc_file_order* out,
                              const wc_allocator* alloc, const char* path, wc_diag* diag);

#endif
