/* The triangle-mesh colliders on the GPU: the bodies' vertices, triangles and BVH nodes in
 * textures that the contact passes search (contact_query.glsl). A body is moved to each substep
 * in one of two ways:
 *  - on the host (the default): core's wc_mesh_collider_substep (core/mesh_collider.h, the
 *    state's s->mesh: the substep's positions interpolated between the frame's, the vertex
 *    velocities, the triangle normals, the BVH refitted over the swept triangles, O(vertices +
 *    triangles), no allocation), its results uploaded, so the GPU searches the same body as the
 *    CPU, in float;
 *  - on the device (a body "resident" on the GPU, compute passes only: wg_mesh_body.c): its
 *    frame's start and end positions live in textures and passes compute the same things in
 *    float. A body from a host GL buffer (core's on_device): core's copy of it is stale until
 *    wg_mesh_body_pull brings it back. A body core's copy moves (the host's arrays, a rigid
 *    transform; core's substep_on_device, wg_mesh_host.c, WEFT_GPU_BODY=device): core's frame
 *    start and end stay current and the end is uploaded once a frame; only the substep's
 *    arrays are stale in core.
 * All the meshes share one set of textures (vertex, triangle and node indices offset per mesh);
 * the tree's shape and the triangles' vertices are uploaded at creation (one staging buffer sized
 * then). Calls are made with the cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_MESH_H
#define WEFT_GPU_SOLVER_MESH_H

#include "mesh_collider.h"
#include "wg_reduce.h"
#include "wg_runner.h"

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
    wg_runner* run;
    /* the bodies computed on the device (wg_mesh_body.c; body 0 without compute passes) */
    int body;                        /* 1: the passes and textures below exist */
    int host_fed;                    /* 1: the bodies core's copy moves are made resident too
                                        (wg_mesh_host_frame; WEFT_GPU_BODY=device) */
    unsigned char* resident;         /* (n_mesh) 1: mesh k's frame positions are from / to's */
    int n_resident;
    wg_tex from, to, to_next;        /* 1 texel a vertex: the frame's start and end (xyz, 0); to_next
                                        a take's scratch */
    wg_tex from_bk;                  /* the frame's back-up of from */
    wg_tex tri_idx;                  /* 1 a triangle: its vertices' global indices, its mesh's thickness */
    wg_tex order;                    /* the refit's nodes, resident meshes only, by height */
    int* height;                     /* (n_node) a node's height over its deepest leaf (0: a leaf) */
    int* order_first;                /* (max height + 2) first entry of each height in order */
    int n_heights;
    wg_tex meas;                     /* 1 a vertex: a reduction's input (speed, a bad coordinate) */
    wg_chain chain;                  /* meas's reductions */
    wg_tex raw;                      /* R32F: a host buffer's floats (wg_mesh_body_take) */
    long long up_bytes, read_bytes;  /* the bodies' transfers since creation (logged by the step at
                                        WC_LOG_DEBUG): the host-moved bodies' substep texels, the
                                        resident bodies' positions and refit order uploaded; their
                                        fastest vertex, a buffer call's check and a pull read back
                                        (the sharp pairs' transfers are wg_mesh_sharp_find's) */
} wg_mesh;

/* The textures for the n_mesh meshes (n_mesh 0: one zero texel each, so that the passes' inputs
 * are bound); 0 with err (the device's textures too small, GL, out of memory). */
int wg_mesh_init(wg_mesh* g, wg_runner* run, wc_mesh_collider* const* mesh, int n_mesh, char* err,
                 size_t err_len);
void wg_mesh_release(wg_mesh* g, int gl);   /* gl 0: the memory only (the GL context is gone) */
size_t wg_mesh_bytes(const wg_mesh* g);        /* GPU memory held: every texture, the bodies' too */
/* The substep from frame fraction a0 to a1, of length h (core/step.c's substep_colliders): the
 * resident bodies by the passes (wg_mesh_body_substep), then core moves every other mesh to it
 * and its positions, velocities, normals and BVH boxes are uploaded. */
void wg_mesh_substep(wg_mesh* g, double a0, double a1, double h);
/* Mesh k's substep results as core holds them into the textures (k -1: all meshes at once). */
void wg_mesh_upload(wg_mesh* g, int k);

/* ---- the bodies on the device (wg_mesh_body.c; g->body only) ---- */
/* The textures and the tree's heights; 0 with err (GL, out of memory). */
int wg_mesh_body_init(wg_mesh* g, char* err, size_t err_len);
void wg_mesh_body_release(wg_mesh* g, int gl);
size_t wg_mesh_body_bytes(const wg_mesh* g);   /* the bodies' textures (0 without them) */
/* Make mesh k resident with frame positions from and to (n_verts x 3 each, rounded to float). */
void wg_mesh_body_set(wg_mesh* g, int k, const double* from, const double* to);
/* The resident bodies moved to the substep (a0, a1, h) by the passes: their vertex and triangle
 * texels, the tree refitted bottom-up one height a pass, and each one's fastest vertex (a max
 * reduction, read back: core's m->max_speed and m->h, which the step's judge and the colliders'
 * rows take). */
void wg_mesh_body_substep(wg_mesh* g, double a0, double a1, double h);
/* End of a frame: from = to for the resident bodies (g NULL: nothing). */
void wg_mesh_body_end_frame(wg_mesh* g);
/* The frame's back-up of the resident bodies' start positions, and its restore. */
void wg_mesh_body_backup(wg_mesh* g);
void wg_mesh_body_restore_backup(wg_mesh* g);
/* Mesh k's frame end from a host buffer (a name of the host's current context holding the bytes,
 * checked by the caller; one the host has mapped is refused, INVALID_ARGUMENT): n_verts x 3
 * floats at byte offset + i stride,
 * copied on the GPU and checked there (NaN, Inf, |coordinate| >= 1e30: WC_OK with *bad_vertex the
 * first bad vertex and bad its 3 floats, nothing changed; else *bad_vertex -1). The mesh becomes
 * resident (its frame start from core's copy when it was not); *moves 1 when the new end differs
 * from the frame's start in any bit (found in the same read-back as the check), so the body moves
 * this frame however often the end is taken before it. WC_ERROR_UNSUPPORTED (nothing changed)
 * when the range is too long for the raw texture: the caller reads the buffer back. */
wc_status wg_mesh_body_take(wg_mesh* g, int k, unsigned buffer, size_t offset, size_t stride, int* bad_vertex,
                            float bad[3], int* moves, wc_diag* d);
/* Core's copy of every resident body from the textures (from, to, read back for the bodies from a
 * host buffer only; the substep positions at from, as a snapshot's restore leaves them), and
 * each given back to the host. */
void wg_mesh_body_pull(wg_mesh* g);
/* Mesh k's n_verts x 3 positions x (rounded to float) into texture t's texels (from, to). */
void wg_mesh_body_put(wg_mesh* g, const wg_tex* t, int k, const double* x);
/* The refit's order (g->order, order_first) for the resident meshes. */
void wg_mesh_body_rebuild_order(wg_mesh* g);
/* Mark mesh k resident (its from and to texels written), the refit's order rebuilt. */
void wg_mesh_body_make_resident(wg_mesh* g, int k);

/* ---- the bodies core's copy moves, kept on the device (wg_mesh_host.c; g->host_fed) ---- */
/* At a frame's start, after the frame's inputs reached core: each mesh not from a host buffer
 * becomes resident (its from and to uploaded, core's substep_on_device set), or, resident
 * already, has its frame end uploaded when it moves (core's from != to): 16 bytes a vertex.
 * g NULL or without host_fed: nothing. */
void wg_mesh_host_frame(wg_mesh* g);
/* Mesh k's row in the colliders' texture (20 floats, contact_query.glsl). */
void wg_mesh_row(const wg_mesh* g, int k, float* row);

#endif
