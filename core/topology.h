/* Mesh clean-up and topology queries on triangle lists: degenerate and duplicate triangles,
 * consistent winding per component, connected components, boundary loops. */
#ifndef WEFT_CORE_TOPOLOGY_H
#define WEFT_CORE_TOPOLOGY_H
#include "alloc.h"
#include "sort.h"
#include "winged_edge.h"

/* Area of triangle t (3 indices into pos, x 3). */
double wc_triangle_area(const double* pos, const int* t);

/* Flags each triangle (keep[t] = 0) that repeats a vertex or whose area is <= min_area, and
 * each later copy of an earlier triangle with the same three vertices (any order).
 * Counts go to *degenerate and *duplicates. Returns 0 on allocation failure. */
int wc_flag_bad_triangles(const int* tris, int n, const double* pos, double min_area,
                          unsigned char* keep, int* degenerate, int* duplicates,
                          const wc_allocator* alloc);

/* Make winding consistent across manifold edges (an edge shared by exactly two triangles is
 * traversed in opposite directions by them). Per connected piece the minority orientation is
 * flipped (v1 and v2 swapped, side_mask bits permuted along). *flipped counts flipped triangles,
 * *non_orientable the pieces where no consistent winding exists (e.g. a Moebius strip).
 * sides: wc_sorted_sides() of the triangles; their vals are updated for flipped triangles, so
 * the array stays valid for wc_winged_edge_build_sorted(). Returns 0 on allocation failure. */
int wc_orient_triangles(int* tris, unsigned char* side_mask, int n, wc_keyed* sides, int* flipped,
                        int* non_orientable, const wc_allocator* alloc);

/* The 3n triangle sides sorted by vertex pair (key lo * n_verts + hi; val 3 t + k for side k of
 * triangle t), the order the winged-edge build and the orientation pass both need. NULL on
 * allocation failure; free with wc_free. */
wc_keyed* wc_sorted_sides(int n_verts, const int* tris, int n, const wc_allocator* alloc);

/* Connected components over triangle edges; comp (n_verts) gets a component id per vertex in
 * first-appearance order, -1 for vertices in no triangle. Returns the count, -1 on failure. */
int wc_components(int n_verts, const int* tris, int n, int* comp, const wc_allocator* alloc);

/* Closed loops of boundary edges (undirected walk, so non-orientable pieces count right).
 * -1 on allocation failure. */
int wc_boundary_loops(const wc_winged_edge* we, const wc_allocator* alloc);

#endif
