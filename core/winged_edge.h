/* Winged-edge mesh in the thesis's integer-index style: three arrays (vertices, edges, faces)
 * whose elements refer to each other by index. Built from triangles in O(n log n). */
#ifndef WEFT_CORE_WINGED_EDGE_H
#define WEFT_CORE_WINGED_EDGE_H
#include "alloc.h"
#include "diag.h"

enum {
    WC_EDGE_POLYGON = 1,        /* an edge of a source polygon (a stretch edge) */
    WC_EDGE_NON_MANIFOLD = 2,   /* its vertex pair is shared by more than two triangles */
};

typedef struct wc_we_edge {
    int v[2];          /* endpoints, v[0] < v[1] */
    int f[2];          /* faces on each side; f[1] = -1 on the boundary */
    int prev[2];       /* in face f[k]: the edge before this one (a wing edge), -1 if no face */
    int next[2];       /* in face f[k]: the edge after this one (a wing edge), -1 if no face */
    int flags;         /* WC_EDGE_* */
} wc_we_edge;

typedef struct wc_we_face {
    int v[3];          /* corners, counter-clockwise as wound */
    int e[3];          /* e[k] joins v[k] and v[(k+1)%3] */
} wc_we_face;

typedef struct wc_winged_edge {
    int n_verts, n_edges, n_faces;
    int* vert_edge;        /* (n_verts) one incident edge, -1 for an isolated vertex */
    wc_we_edge* edges;     /* (n_edges) */
    wc_we_face* faces;     /* (n_faces) */
} wc_winged_edge;

/* Build from n_faces triangles (n_faces x 3 vertex indices). side_polygon (n_faces 3-bit masks, may be
 * NULL = all) marks which triangle sides are source-polygon edges (WC_EDGE_POLYGON).
 * A vertex pair shared by more than two triangles: the first two (in face order) share one
 * edge; each further triangle gets its own copy of the edge (a boundary on that side), all
 * copies flagged WC_EDGE_NON_MANIFOLD.
 * sides: wc_sorted_sides() of the triangles (topology.h), computed once and shared with the
 * orientation pass; only its grouping of equal keys and its vals (3 face + side) are used, so
 * any order-preserving renumbering of the vertices since then is fine. */
struct wc_keyed;
wc_status wc_winged_edge_build_sorted(wc_winged_edge* we, const wc_allocator* alloc, int n_verts,
                                        const int* tris, int n_faces, const unsigned char* side_polygon,
                                        const struct wc_keyed* sides, wc_diag* diag);
void wc_winged_edge_free(wc_winged_edge* we, const wc_allocator* alloc);

/* Edge e is a further copy of the previous edge's vertex pair (non-manifold): count pairs once. */
static inline int wc_we_repeats_previous(const wc_winged_edge* we, int e) {
    return e > 0 && we->edges[e - 1].v[0] == we->edges[e].v[0] && we->edges[e - 1].v[1] == we->edges[e].v[1];
}

/* The vertex of face f opposite its edge e (the "wing" vertex), -1 if e is not in f. */
int wc_we_opposite_vertex(const wc_winged_edge* we, int f, int e);

#endif
