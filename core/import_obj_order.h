/* Which `f` line of an OBJ file each polygon of assimp's import came from, so that the import can
 * number its vertices by the file's `v` lines (import_assimp.c) instead of assimp's order. */
#ifndef WEFT_CORE_IMPORT_OBJ_ORDER_H
#define WEFT_CORE_IMPORT_OBJ_ORDER_H
#include "obj_text.h"

struct aiScene;

/* meshes: the scene's mesh index of each instance (n_inst, in the order the import concatenates
 * them). Writes poly_face: for every face with >= 3 indices of those instances, in that order,
 * the index of its `f` line among obj's faces. assimp 5.2's OBJ importer gives each mesh a run
 * of the file's faces in file order, each face's corners in file order and one vertex per
 * corner; each mesh is matched against the file's faces in order (same corner count, every
 * corner's position equal to its `v` line's within 1e-5 relative). A face that matches nothing
 * fails with IMPORT naming the mesh and face, rather than reporting a wrong order. */
wc_status wc_obj_match_faces(const struct aiScene* s, const unsigned* meshes, size_t n_inst,
                               const wc_obj_text* obj, int* poly_face, const wc_allocator* alloc,
                               const char* path, wc_diag* diag);

#endif
