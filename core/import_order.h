/* A file mesh in the file's own vertex numbering: what import_assimp.c needs from a format's
 * order matcher (import_obj_order.h, import_fbx_order.h) to renumber assimp's vertices. */
#ifndef WEFT_CORE_IMPORT_ORDER_H
#define WEFT_CORE_IMPORT_ORDER_H
#include "alloc.h"
#include "diag.h"

struct aiNode;

/* One mesh instance of the import: a mesh a node references, with the node's world transform. */
typedef struct wc_import_instance {
    unsigned mesh;              /* index into aiScene::mMeshes */
    const struct aiNode* node;
    double m[12];               /* rows 0..2 of the world transform (row-major, column vectors) */
} wc_import_instance;

typedef struct wc_file_order {
    int n_v;                    /* host vertices: the file's own (OBJ `v` lines, FBX control
                                   points), used or not */
    double* v;                  /* (n_v x 3) file units, node transform applied: the position of
                                   a vertex no polygon uses (the import multiplies by the scale) */
    int n_corners;
    int* corner_v;              /* (n_corners) host vertex of each corner of the instances'
                                   polygons of >= 3 corners, in the order the import
                                   concatenates them */
    wc_allocator alloc;
} wc_file_order;

/* Allocate out's arrays (zeroed); OUT_OF_MEMORY naming path. */
wc_status wc_file_order_alloc(wc_file_order* out, const wc_allocator* alloc, int n_v,
                                int n_corners, const char* path, wc_diag* diag);
void wc_file_order_free(wc_file_order* o);

#endif
