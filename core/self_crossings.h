/* Edge-triangle crossings of a cloth's mesh: an edge passing through a triangle's interior. The
 * stage (self_collide.h) marks at its creation the pairs that already cross in the rest shape;
 * the counters check a cloth for crossings (cloth_check.c, tests). Pairs sharing a particle or
 * sewn together (self_broad.h's seam links) are excluded. */
#ifndef WEFT_CORE_SELF_CROSSINGS_H
#define WEFT_CORE_SELF_CROSSINGS_H
#include "model.h"

/* 1 when the segment between particles a and b passes through the interior of triangle t
 * (strictly), at positions x (n x 3); 0 when the edge and the triangle share a particle or are
 * sewn together (ls, ln: the seam links, wc_self_seam_links). */
int wc_self_edge_tri_cross(const wc_model* m, const int* ls, const int* ln, const double* x, int a, int b, int t);

/* Edge-triangle pairs that cross (every unique edge against every triangle) at positions x
 * (n x 3), through a temporary BVH (allocates: not for inside a step). *count receives the
 * number. */
wc_status wc_self_intersections(const wc_model* m, const double* x, const wc_allocator* alloc, int* count,
                                  wc_diag* diag);
/* The same by brute force, O(edges x triangles) (tests); -1 when out of memory. */
int wc_self_intersections_brute(const wc_model* m, const double* x);

#endif
