/* The sharp-feature pairs (core/mesh_pairs.h) of the bodies resident on the GPU (wg_mesh.h,
 * compute passes only), found on the GPU where core's copy of such a body is stale.
 *
 * At each substep's start, where wg_pairs_find runs core's detection for the bodies moved on the
 * host, three passes run over the resident bodies' current vertices and triangles (the mesh
 * textures, after wg_mesh_body_substep) and the cloth's positions and velocities (its
 * textures): mesh_sharp.glsl marks the sharp body edges and vertices by core's rule at the
 * substep's start; mesh_sharp_mask_groups.glsl marks the tree's nodes above a live triangle with
 * a sharp vertex (core's mask; one dispatch a tree height, as the refit); and
 * mesh_pairs_find_groups.glsl, one invocation a cloth feature (its winged edges, then its
 * triangles), walks a resident body's refitted tree (wg_mesh_body.c) through the marked nodes to
 * the triangles whose leaf boxes meet the feature's box, as core's walk does, and tests their
 * sharp edges and vertices, each once, by core's detection (the interior closest points, the
 * contact distance, the normal cone, the cloth point and particles in front of the body through
 * the tree: core/mesh_pairs.c keep); each pair it keeps (particles, weights, normal, off) goes to
 * a slot an atomic counter hands out. The counter (4 bytes) and the pairs (48 bytes each) are
 * read back, sorted by (cloth feature, body feature) so that the list does not depend on the
 * GPU's order, and appended to core's list by wc_mesh_pairs_add_found (the particles' masses,
 * k), after the host bodies' pairs; core's activation and assembly then take them as any other.
 * Everything is allocated at creation (the list's capacity); nothing in a step. */
#ifndef WEFT_GPU_SOLVER_MESH_SHARP_H
#define WEFT_GPU_SOLVER_MESH_SHARP_H

#include "mesh_pairs.h"
#include "model.h"
#include "wg_mesh.h"

typedef struct wg_mesh_sharp wg_mesh_sharp;

/* For the cloth m against g's meshes (g->body: compute passes; pp the state's mesh pairs, whose
 * edge tables are core's). 0 with err (GL, out of memory, textures too small). */
int wg_mesh_sharp_create(wg_runner* run, wg_mesh* g, const wc_mesh_pairs* pp, const wc_model* m, wg_mesh_sharp** out,
                         char* err, size_t err_len);
void wg_mesh_sharp_destroy(wg_mesh_sharp* ms, int gl);   /* gl 0: the memory only */
size_t wg_mesh_sharp_bytes(const wg_mesh_sharp* ms);     /* GPU memory held */

/* The resident bodies' pairs for the cloth at x, v (textures of its positions and velocities at
 * the substep's start) appended to pp's list (f, stick: wc_mesh_pairs_find's filter; h the
 * substep, he the system's step). Returns the pairs the GPU found (those past the list's capacity
 * counted in its overflow); *bytes (NULL: not asked) the bytes read back. Nothing without a
 * resident body. */
int wg_mesh_sharp_find(wg_mesh_sharp* ms, wc_mesh_pairs* pp, const wc_model* m, const struct wc_filter* f,
                       const unsigned char* stick, const wg_tex* x, const wg_tex* v, double h, double he,
                       size_t* bytes);

#endif
