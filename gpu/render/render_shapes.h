/* Tessellation of collider shapes in their local frames (gpu/ internal). Vertices are
 * interleaved (position xyz, unit normal xyz); triangles counter-clockwise seen from outside
 * (planes: from +y). */
#ifndef WEFT_GPU_RENDER_SHAPES_H
#define WEFT_GPU_RENDER_SHAPES_H

/* Floats per vertex: position and normal. */
#define WG_VERTEX_FLOATS 6

/* A capsule (segment (0, -half_height, 0)..(0, half_height, 0) swept by radius) as two
 * hemispheres of `stacks` rings each joined by a cylinder; half_height 0 gives a sphere. `slices`
 * around the Y axis. Counts of what wg_capsule_build writes: */
void wg_capsule_counts(int slices, int stacks, int* n_vertices, int* n_indices);
void wg_capsule_build(float radius, float half_height, int slices, int stacks, float* vertices,
                      unsigned* indices);

/* The square [cx - half, cx + half] x [cz - half, cz + half] of the plane y = 0: 4 vertices,
 * 6 indices. */
void wg_plane_build(float cx, float cz, float half, float* vertices, unsigned* indices);

/* The largest 1, 2 or 5 x 10^k not above x (x > 0): checker cell sizes. */
float wg_nice_step(float x);

#endif
