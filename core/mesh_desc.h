/* A mesh as a host gives it: a file (read through assimp) or host arrays (float positions,
 * polygons as corner counts plus concatenated indices), with the metres per unit to apply.
 * Read into a wc_source_mesh (source_mesh.h) in the host's vertex order. */
#ifndef WEFT_CORE_MESH_DESC_H
#define WEFT_CORE_MESH_DESC_H
#include "source_mesh.h"

typedef struct wc_mesh_desc {
    const char* path;           /* a file, or NULL for the arrays */
    const char* select;         /* file: the node to take (NULL: every mesh) */
    const float* positions;     /* arrays: (n_vertices x 3) */
    int n_vertices;
    const int* face_sizes;      /* (n_faces) corners per polygon; NULL: triangles */
    int n_faces;
    const int* indices;         /* (sum of face_sizes) */
    double unit_scale;          /* metres per unit (files: on top of the file's own unit) */
} wc_mesh_desc;

/* Read the mesh (errors as wc_import_file and wc_source_mesh_from_arrays, whose messages name
 * the file or the offending vertex, polygon or index). On failure *out is zeroed. */
wc_status wc_mesh_desc_read(const wc_mesh_desc* desc, wc_source_mesh* out, const wc_allocator* alloc, wc_diag* d);

#endif
