/* Bounding-volume hierarchy over axis-aligned boxes: the broad phase of the mesh colliders and of
 * self-collision. The tree's shape is built once, at creation, from the primitives' boxes then
 * (median split of the box centres along the widest axis; one primitive per leaf; depth at most
 * ceil(log2 n) + 1); every substep only refits the boxes (wc_bvh_refit, O(n), no allocation),
 * which keeps a cloth or a skinned body's tree valid however it deforms (looser, not wrong, when
 * it deforms far from the build shape). Queries are read-only and may run on many threads. */
#ifndef WEFT_CORE_BVH_H
#define WEFT_CORE_BVH_H
#include <math.h>
#include "alloc.h"
#include "diag.h"

#define WC_BVH_MAX_DEPTH 64   /* a median-split tree of up to 2^62 primitives */

typedef struct wc_bvh {
    int n_prims;
    int n_nodes;                /* 2 n_prims - 1 (0 when empty) */
    double* box;                /* (n_nodes x 6) min xyz, max xyz; node 0 is the root */
    int* child;                 /* (n_nodes x 2) internal: left, right (> the node: preorder);
                                   leaf: -1, primitive */
    int* leaf_of;               /* (n_prims) the leaf node of each primitive */
    wc_allocator alloc;
} wc_bvh;

/* Build the tree over n >= 0 boxes (n x 6: min xyz, max xyz, finite, min <= max). */
wc_status wc_bvh_build(wc_bvh* b, const double* boxes, int n, const wc_allocator* alloc, wc_diag* diag);
void wc_bvh_free(wc_bvh* b);
/* New boxes for the same primitives (n_prims x 6); the tree's shape is kept. */
void wc_bvh_refit(wc_bvh* b, const double* boxes);
/* The same for only the nodes whose mask (n_nodes, wc_bvh_mask_up's) is 1: the refit when only
 * the primitives under those changed their boxes (the others' nodes keep theirs, the same). */
void wc_bvh_refit_masked(wc_bvh* b, const double* boxes, const unsigned char* mask);

/* Calls visit(user, prim) for every primitive whose box overlaps box (6: min xyz, max xyz,
 * closed intervals); stops early when visit returns non-zero (then returns that value, else 0). */
typedef int (*wc_bvh_visit_fn)(void* user, int prim);
int wc_bvh_query(const wc_bvh* b, const double* box, wc_bvh_visit_fn visit, void* user);
/* The same, skipping every node whose mask (n_nodes bytes) is 0 (mask NULL: wc_bvh_query). */
int wc_bvh_query_masked(const wc_bvh* b, const double* box, const unsigned char* mask, wc_bvh_visit_fn visit,
                        void* user);
/* Nearest-point queries: the same traversal (preorder, left child first), also skipping every
 * node whose box lies farther from p than sqrt(*bound2); the visitor may lower *bound2 as it
 * finds nearer primitives (a node's box holds its primitives, so a skipped one is no nearer). */
int wc_bvh_query_near(const wc_bvh* b, const double* box, const double* p, const double* bound2,
                      wc_bvh_visit_fn visit, void* user);
/* mask (n_nodes): the caller set every leaf's byte (leaf_of[prim]); sets each internal node's to
 * the OR of its children's, so a node is 1 when a primitive under it is. */
void wc_bvh_mask_up(const wc_bvh* b, unsigned char* mask);
/* h (n_nodes): each node's height (a leaf 0, a node 1 + its children's highest), so a height's
 * nodes depend only on lower ones (the GPU's refits run one height a pass). Returns the highest
 * height, or -1 for an empty tree. */
int wc_bvh_heights(const wc_bvh* b, int* h);

/* A cut of the tree for bottom-up sweeps on threads: n_sub subtrees, the nodes down to a depth
 * (or leaves above it) with all below them, each a contiguous range of nodes in preorder
 * [sub[2k], sub[2k + 1]), and the n_top nodes above them in descending order (children first).
 * The subtrees' sweeps are independent: any thread may run any of them, then the top nodes,
 * for the same boxes bit for bit. Built once (allocates); the tree's shape never changes. */
typedef struct wc_bvh_split {
    int n_sub, n_top;
    int* sub;   /* (n_sub x 2) */
    int* top;   /* (n_top) */
} wc_bvh_split;
wc_status wc_bvh_split_build(wc_bvh_split* s, const wc_bvh* b, int depth, const wc_allocator* a);
void wc_bvh_split_free(wc_bvh_split* s, const wc_allocator* a);
/* wc_bvh_refit_masked (mask NULL: wc_bvh_refit) and wc_bvh_mask_up over the nodes [lo, hi) only:
 * a subtree's range (the nodes below it done), or the top nodes of a split after its subtrees. */
void wc_bvh_refit_span(wc_bvh* b, const double* boxes, const unsigned char* mask, int lo, int hi);
void wc_bvh_mask_up_span(const wc_bvh* b, unsigned char* mask, int lo, int hi);
void wc_bvh_refit_top(wc_bvh* b, const wc_bvh_split* s, const unsigned char* mask);
void wc_bvh_mask_up_top(const wc_bvh* b, const wc_bvh_split* s, unsigned char* mask);

/* Box helpers: an empty box (min +inf, max -inf), growing one by a point, inflating by r (inline:
 * the self-collision trees' boxes are recomputed several times a substep). */
static inline void wc_box_empty(double* box) {
    for (int k = 0; k < 3; ++k) {
        box[k] = INFINITY;
        box[3 + k] = -INFINITY;
    }
}
static inline void wc_box_add(double* box, const double* p) {
    for (int k = 0; k < 3; ++k) {
        if (p[k] < box[k]) box[k] = p[k];
        if (p[k] > box[3 + k]) box[3 + k] = p[k];
    }
}
static inline void wc_box_inflate(double* box, double r) {
    for (int k = 0; k < 3; ++k) {
        box[k] -= r;
        box[3 + k] += r;
    }
}
/* Squared distance from p to the box (0 inside). */
static inline double wc_box_dist2(const double* box, const double* p) {
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        double g = box[k] - p[k];
        if (g < 0.0) g = p[k] - box[3 + k];
        if (g > 0.0) s += g * g;
    }
    return s;
}
static inline int wc_box_overlap(const double* a, const double* b) {
    return a[0] <= b[3] && b[0] <= a[3] && a[1] <= b[4] && b[1] <= a[4] && a[2] <= b[5] && b[2] <= a[5];
}

#endif
