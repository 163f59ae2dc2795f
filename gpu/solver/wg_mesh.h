/* The triangle-mesh colliders on the GPU: the bodies' vertices, triangles and BVH nodes in
 * textures that the contact passes search (contact_query.glsl). The body itself stays core's
 * (core/mesh_collider.h, the state's s->mesh): every substep runs core's
 * wc_mesh_collider_substep (the substep's positions interpolated between the frame's, the vertex
 * velocities, the triangle normals, the BVH refitted over the swept triangles, O(vertices +
 * triangles), no allocation) and uploads its results, so the GPU searches the same body as the
 * CPU, in float. All the meshes share one set of textures (vertex, triangle and node indices
 * offset per mesh); the tree's shape and the triangles' vertices are uploaded with the rest (one
 * staging buffer sized at creation). Calls are made with the cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_MESH_H
#define WEFT_GPU_SOLVER_MESH_H

#include "mesh_collider.h"
#include "wg_layout.h"

typedef struct wg_mesh {
    int n_mesh;
    wc_mesh_collider* const* mesh;   /* the state's (borrowed) */
    int *vert0, *tri0, *node0;       /* (n_mesh) each mesh's first vertex, triangle and node */
    wg_tex vert;                     /* 3 texels a vertex: start, end, velocity */
    wg_tex tri;                      /* 3 a triangle: vertex indices (floats), normal at start, at end */
    wg_tex node;                     /* 2 a node: (min, left child), (max, right child); leaf: -1, triangle */
    int n_vert, n_tri, n_node;       /* over all meshes */
    float* staging;
    wc_allocator alloc;
} wg_mesh;

/* The textures for the n_mesh meshes (n_mesh 0: one zero texel each, so that the passes' inputs
 * are bound); 0 with err (the device's textures too small, GL, out of memory). */
int wg_mesh_init(wg_mesh* g, const wg_layout* L, wc_mesh_collider* const* mesh, int n_mesh, char* err,
                 size_t err_len);
void wg_mesh_release(wg_mesh* g, int gl);   /* gl 0: the memory only (the GL context is gone) */
/* The substep from frame fraction a0 to a1, of length h (core/step.c's substep_colliders): core
 * moves every mesh to it, then its positions, velocities, normals and BVH boxes are uploaded. */
void wg_mesh_substep(wg_mesh* g, const wg_layout* L, double a0, double a1, double h);
/* Mesh k's row in the colliders' texture (20 floats, contact_query.glsl). */
void wg_mesh_row(const wg_mesh* g, int k, float* row);

#endif
