/* Sewing: seams that join panels (connected components) of a garment.
 *
 * A seam ties particle p to the point (1 - t) q0 + t q1 of segment (q0, q1) (q0 == q1 and t = 0 for
 * a vertex-to-vertex seam) with a zero-rest-length spring of energy
 *     E = k/2 |g|^2,   g = p - (1 - t) q0 - t q1   (the seam gap, m)
 * and Rayleigh damping d/2 |dg/dt|^2, with k, d = material.k/d[WC_SPRING_SEAM]. E is quadratic in
 * positions, so its force and Jacobian (-k w w^T (x) I3, w = (1, -(1-t), -t)) are exact and
 * constant. Since the weights sum to one,
 *     |g|^2 = (1-t) |p - q0|^2 + t |p - q1|^2 - t (1-t) |q0 - q1|^2,
 * so a seam is represented EXACTLY by three zero-rest-length pair springs of type WC_SPRING_SEAM
 * with stiffness weights (1-t), t and -t(1-t) (the negative one on the panel's own edge; their sum
 * is positive semi-definite). Seam springs are ordinary springs of the model (spring.w holds the
 * weight): the block pattern, assembly, Newton energy, AMG (as strong, like stretch) and snapshot
 * model hash all see them without special cases. Pair springs repeated by several seams are
 * merged (weights summed).
 *
 * Sources:
 *   - by distance (sew_distance > 0, metres): every boundary vertex p sews to the closest point of
 *     a boundary edge of ANOTHER component (panel) within sew_distance. A closest point within
 *     WC_SEW_SNAP of an edge end (fraction of the edge) snaps to that vertex; a vertex-to-vertex
 *     pair found from both sides is kept once. Candidates come from a uniform grid over boundary
 *     vertices (cell = max(sew_distance, mean boundary edge length)), cells sorted by key and
 *     looked up by binary search: O(n log n), not O(n^2).
 *   - host pairs (seam_a[i], seam_b[i]): host vertex indices, sewn vertex to vertex (t = 0).
 */
#ifndef WEFT_CORE_SEW_H
#define WEFT_CORE_SEW_H
#include "alloc.h"
#include "diag.h"
#include "winged_edge.h"

#define WC_SEW_SNAP 1e-3

typedef struct wc_seam {
    int p, q0, q1;   /* particles; q1 == q0 for vertex to vertex */
    double t;        /* [0, 1]: the sewn point is (1 - t) q0 + t q1 */
} wc_seam;

typedef struct wc_sew_input {
    int n_particles;
    const double* pos;              /* (n_particles x 3) rest positions, m */
    const wc_winged_edge* we;
    const int* component;           /* (n_particles) component id, 0 .. n_components-1 */
    int n_components;
    double sew_distance;            /* m; 0 = no distance sewing */
    int n_pairs;                    /* host-supplied pairs, already mapped to particles */
    const int* pair_a;              /* (n_pairs) particles */
    const int* pair_b;              /* (n_pairs) particles, != pair_a */
} wc_sew_input;

/* Finds the seams. *out (allocated, n_out entries; NULL when none) and *n_panels (components left
 * once seams join them). 0 on success, -1 out of memory. */
int wc_sew_find(const wc_sew_input* in, wc_seam** out, int* n_out, int* n_panels, const wc_allocator* alloc);

/* Gap |g| of seam s at positions x (n_particles x 3), metres. */
double wc_seam_gap(const wc_seam* s, const double* x);

#endif
