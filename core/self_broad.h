/* Self-collision's broad phase and adjacency rule, shared by the stage (self_collide.h) and the
 * in-solve self-contact pairs (self_pairs.h): the swept boxes of the triangles and the (unique)
 * edges, the two AABB trees over them (bvh.h: built at the stage's creation, refitted here),
 * the edge tree's query that visits each edge pair once, and the seam links. Seam links (sew.h):
 * particles joined by a sewing spring count as one for the adjacency rules (a vertex is never
 * tested against a triangle or edge it is sewn to): sewn panels are not welded, so their
 * elements overlap along the seam by construction, and pushing them apart would fight the seam.
 * Only wc_self_seam_links allocates. */
#ifndef WEFT_CORE_SELF_BROAD_H
#define WEFT_CORE_SELF_BROAD_H
#include "bvh.h"
#include "model.h"
#include "self_data.h"

/* The seam links of m: the CSR of each particle's seam partners (*start_out (n + 1), *nbr_out),
 * allocated from A; both NULL when the model has no seams, or on WC_ERROR_OUT_OF_MEMORY. */
wc_status wc_self_seam_links(const wc_model* m, const wc_allocator* A, int** start_out, int** nbr_out);

/* 1 when particles a and b are one particle or sewn together (start, nbr: wc_self_seam_links;
 * start NULL: no seams). */
static inline int wc_self_seam_linked(const int* start, const int* nbr, int a, int b) {
    if (a == b) return 1;
    if (!start) return 0;
    for (int k = start[a]; k < start[a + 1]; ++k)
        if (nbr[k] == b) return 1;
    return 0;
}

/* 1 when particles a and b are one particle or sewn together (sc's seam links); inline: every
 * visitor of the broad phase asks it of each candidate pair (~2M times in the suit's 6 frames) */
static inline int wc_self_linked(const wc_self* sc, int a, int b) {
    return wc_self_seam_linked(sc->seam_start, sc->seam_nbr, a, b);
}

/* On the stage's trees and seams:
 *   refit: both trees over the boxes of x0 U x1 (n x 3 each; x0 may be NULL) inflated by r, on
 *   sc->threads threads;
 *   edges_above: visit(user, f) for every edge f > e whose tree box overlaps box (each edge pair
 *   once from its lower edge; stops when visit returns non-zero and returns that); _masked: only
 *   in the nodes of the edge tree whose mask is set (mask NULL: all). */
void wc_self_refit(wc_self* sc, const wc_model* m, const double* x0, const double* x1, double r);
/* The trees' bottom-up sweeps on threads, each tree cut into subtrees (wc_self.tri_split,
 * edge_split; bvh.h's wc_bvh_split): trees_sweep, inside a parallel region (every thread calls
 * it), sweeps the subtrees, any to any thread; trees_top, after the region, the nodes above them.
 * mask_up: the masks (tri_mask, edge_mask, their leaves set) ORed up; refit: the boxes refitted
 * (with mask_up, only the masked nodes'). The same masks and boxes as one serial sweep. */
#define WC_SELF_SPLIT_DEPTH 5 /* 32 subtrees a tree */
void wc_self_trees_sweep(wc_self* sc, int mask_up, int refit);
void wc_self_trees_top(wc_self* sc, int mask_up, int refit);
int wc_self_edges_above(const wc_self* sc, int e, const double* box, wc_bvh_visit_fn visit, void* user);
int wc_self_edges_above_masked(const wc_self* sc, int e, const double* box, const unsigned char* mask,
                               wc_bvh_visit_fn visit, void* user);

/* b (6) = the box of the nv particles v at x_start (NULL: skipped) and at x, inflated by r (inline:
 * every pass of the stage takes one per query, ~118k on the dance). */
static inline void wc_self_swept_box(double* b, const int* v, int nv, const double* x_start, const double* x,
                                     double r) {
    wc_box_empty(b);
    for (int k = 0; k < nv; ++k) {
        wc_box_add(b, x + 3 * v[k]);
        if (x_start) wc_box_add(b, x_start + 3 * v[k]);
    }
    wc_box_inflate(b, r);
}
/* The boxes (wc_self_swept_box) of m's triangles into tri_box (n_tris x 6) and of the n_edges
 * edges (particle pairs) into edge_box (n_edges x 6; NULL: none). */
void wc_self_boxes(const wc_model* m, const int* edges, int n_edges, const double* x_start, const double* x, double r,
                   double* tri_box, double* edge_box);

#endif
