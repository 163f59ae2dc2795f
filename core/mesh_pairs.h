/* The mesh colliders' feature contacts inside the implicit solve (issue 13): the cloth's edges
 * against the body's edges and vertices, and the body's vertices against the cloth's
 * triangles, as one-sided stiff springs (penalty) in the system of the substep. The particles'
 * own contacts (collide.h) keep every cloth vertex out of the body; these keep the body's sharp features (a ridge, a box
 * rim, a thin limb, a corner) out of the cloth between its vertices.
 *
 * Only sharp features (the point of the pairs; on a smooth or finely tessellated body the
 * particles' contacts carry the cloth, with friction): a body edge is sharp in a substep when it
 * is convex (the other triangle's far vertex behind the first's plane) and its triangles' normals
 * at the substep's start turn by more than 30 degrees (WC_MESH_PAIR_SHARP_COS), or when it is a
 * boundary or non-manifold edge; a body vertex is sharp when one of its edges is. (Every body
 * edge at first: the frictionless pairs held a sheet on the tessellated icosphere and on a UV
 * sphere off its particles' contacts, 256 -> 14 particles in contact, and the Newton-2 drop on
 * the icosphere never slept, 0.14 m/s after 5 s; a body vertex moving along a flat collider
 * dragged a frictionless cloth.)
 *
 * Detection (wc_mesh_pairs_find, at the substep's start, after wc_contacts_begin and before the
 * forces; serial, in index order): for every cloth edge (p, q) the sharp body edges (r, s) and
 * the sharp body vertices r of the body triangles whose swept box its box (start and inertial
 * end, inflated by the reach) meets, and for every cloth triangle (p, q, u) the sharp body
 * vertices; each body feature once per cloth feature. A pair is kept when the closest points at
 * the start (cloth at x_n, body at xa) are interior to both features (a closest point at a cloth
 * vertex is that particle's own contact; a body vertex nearest a cloth triangle's edge is the
 * vertex-edge pair's) and closer than the contact distance d_c = 2 thickness + 1.5 h (approach
 * speed along the pair's direction, cloth at v_n against the body point's velocity, when
 * positive): the pair is in the system before it touches. The cloth point and every particle
 * of the cloth feature must be in front of the body at the start (signed distance >= 0), and an
 * edge-edge pair's direction within the body edge's normal cone (between its two triangles'
 * normals): a garment that starts through the body comes out by its particles' push-out, which
 * a pair must not fight; and a pair found deeper than push_speed x h inside the thickness is let
 * out at push_speed as the particles are (its rest moved to g0 + push_speed h; test_api_mesh_push).
 * Frozen for the substep: the cloth point's weights w (edge: 1 - a, a; triangle: barycentric),
 * the unit normal n from the body point to the cloth point at the start (the body triangle's
 * normal when they coincide), and the body point at the substep's END, b1 (xb, the same weights
 * on the body feature: the body moves linearly, the pair sees where it will be).
 *
 * The term: c(x) = sum_i w_i x_i, gap g(x) = n.(c(x) - b1) - thickness (linear in x),
 *   E = k/2 min(g, 0)^2,   f_i = -k g w_i n,   dF_i/dx_j = -k w_i w_j n n^T   (g < 0).
 * k = WC_MESH_PAIR_KAPPA m_eff / he^2 (he: the system's step, bdf2.h; h for backward Euler),
 * m_eff = 1 / sum_i w_i^2 / m_i over the pair's unpinned particles: the pair adds KAPPA times
 * the point's own inertia to the system along n, so it
 * holds its load F at a penetration F h^2 / (KAPPA m_eff) (a particle's weight: g h^2 / KAPPA,
 * 0.1 mm at h = 1/30 s), and the system's conditioning grows by at most that factor along n.
 * No damping (backward Euler's own dissipation damps the stiff spring), no friction (the pair is
 * frictionless; the particles' own contacts carry Coulomb friction).
 * In the first solve (wc_mesh_pairs_assemble; b = he (f0 + he K v*), A += he^2 k w_i w_j n n^T,
 * linearised at x_n exactly as the springs, assemble.h) a pair is active when its gap predicted
 * at the end of the substep (x_n + he (v* + he f_ext / m)) is negative; after the solve
 * (wc_mesh_pairs_recheck), when the step takes no Newton iterations, a pair whose solved gap
 * disagrees with its state is switched (activated when negative, released when positive: a
 * penalty never pulls) and the system solved again, WC_MESH_PAIR_PASSES times at most. With
 * Newton iterations (newton.c) those see the exact term instead, at every iterate (its potential
 * and its linearisation at x(w), active where g(x(w)) < 0): re-solving there as well made
 * suit_on_body's frames 7.5 times slower (the active set chattered between the passes).
 * The energy judge (step.c) does not count the pairs' energy (at most k/2 g^2 with g the small
 * penetration): measured, no rollback comes from it (test_mesh_features).
 * A pair whose particles lack a block in the pattern (bsr.h: blocks exist for particles sharing a
 * spring) is skipped and counted. The list has a fixed capacity (allocated at creation); pairs
 * past it are counted (wc_mesh_pairs.overflow), not silently dropped. Derived, not state: re-found
 * every substep (a rollback, a snapshot restore find them again). Deterministic on any thread
 * count (serial, in index order). */
#ifndef WEFT_CORE_MESH_PAIRS_H
#define WEFT_CORE_MESH_PAIRS_H
#include "alloc.h"
#include "mesh_collider.h"

#define WC_MESH_PAIR_KAPPA 100.0   /* stiffness over inertia along n (see the top) */
#define WC_MESH_PAIR_PASSES 3      /* re-solves at most when the active set changes */
#define WC_MESH_PAIR_SHARP_COS 0.866 /* a body edge is sharp when its triangles' normals turn by
                                       more than 30 degrees over it (cos below this) and it is convex */

typedef struct wc_mesh_pair {
    int cnt;                   /* cloth particles: 2 (a cloth edge against a body edge or vertex)
                                  or 3 (a cloth triangle against a body vertex) */
    int p[3];                  /* cloth particles */
    double w[3];               /* their weights (sum 1) */
    double n[3];               /* unit normal, body -> cloth, frozen */
    double off;                /* m: n.b1 + thickness, so that g(x) = n.sum w_i x_i - off */
    double k;                  /* N/m */
    int blk[9];                /* pattern block (p[a], p[b]) at a * 3 + b */
    int active;                /* 1: in the current system */
} wc_mesh_pair;

/* A mesh collider's edges (built at creation from its immutable topology) and which of its
 * edges and vertices are sharp in the current substep (from the normals at its start). */
typedef struct wc_mesh_sharp {
    int n_edges;               /* distinct edges */
    int* tri_edge;             /* (n_tris x 3) edge of each triangle's edge k (vertices k, k + 1) */
    int* edge_tri;             /* (n_edges x 2) its triangles (second -1: a boundary edge) */
    unsigned char* edge_many;  /* (n_edges) 1: more than two triangles (non-manifold) */
    unsigned char* sharp_edge; /* (n_edges) this substep */
    unsigned char* sharp_vert; /* (n_verts) this substep */
} wc_mesh_sharp;

typedef struct wc_mesh_pairs {
    int cap;                   /* capacity (fixed at creation) */
    int n;                     /* pairs of the current substep */
    int overflow;              /* pairs found past cap in the current substep */
    int skipped;               /* pairs without the pattern's blocks in the current substep */
    wc_mesh_pair* pair;        /* (cap) */
    int n_mesh;
    wc_mesh_sharp* sharp;      /* (n_mesh) */
    int n_particles;
    signed char* behind;       /* (n_particles) scratch of a detection: -1 not looked at, 1 the
                                  particle is behind the body's surface at the start, 0 not */
} wc_mesh_pairs;

struct wc_model;
struct wc_filter;

/* Capacity cap >= 1, for a cloth of n_particles against the nm mesh colliders mc (their
 * topology; the same colliders, in the same order, at every wc_mesh_pairs_find). NULL on out of
 * memory. */
wc_mesh_pairs* wc_mesh_pairs_create(int cap, int n_particles, const wc_mesh_collider* const* mc, int nm,
                                    const wc_allocator* a);
void wc_mesh_pairs_destroy(wc_mesh_pairs* p, const wc_allocator* a);

/* Detection (above) against the nm mesh colliders (each after wc_mesh_collider_substep of this
 * substep, length h s; he the system's step, bdf2.h, for k): x, v (n x 3, m, m/s) the cloth at
 * the substep's start; f (NULL: no
 * pins) the filter, ndof 3 without stick = pinned (infinite mass). Resets the list. Returns the
 * pairs found (pp->n). */
int wc_mesh_pairs_find(wc_mesh_pairs* pp, const wc_mesh_collider* const* mc, int nm, const struct wc_model* m,
                       const struct wc_filter* f, const unsigned char* stick, const double* x, const double* v,
                       double h, double he);

/* The first system: x (n x 3) the linearisation point x_n, vstar (n x 3) v* (x(w) = x_n + he
 * (v* + w)), f_ext (n x 3, N, NULL: none) for the active-set prediction, he (s). Adds the active
 * pairs' blocks to A (pattern.n_blocks x 9) and he f to b (n x 3); f_total (n x 3, NULL: none)
 * gets the forces. Returns the active pairs. */
int wc_mesh_pairs_assemble(wc_mesh_pairs* pp, const struct wc_model* m, const double* x, const double* vstar,
                           const double* f_ext, double he, double* A, double* b, double* f_total);

/* After a solve of the first system (dv, n x 3): switches the pairs whose gap at x_n + he (v* +
 * dv) disagrees with their state, adding or removing their terms in A and b (and in fa, the (n x
 * 9) diagonal blocks, and fb (n x 3), when not NULL: Newton's captured copies, newton.h).
 * Returns the pairs switched. */
int wc_mesh_pairs_recheck(wc_mesh_pairs* pp, const double* x, const double* vstar,
                          const double* dv, double he, double* A, double* b, double* fa, double* fb);

/* Newton (newton.c): the pairs' energy sum k/2 min(g(x), 0)^2 at positions x (n x 3), J. */
double wc_mesh_pairs_energy(const wc_mesh_pairs* pp, const double* x);
/* Newton's system at positions x: for every pair with g(x) < 0, A += he^2 k w_i w_j n n^T and
 * g_out += he f_i (g_out: -grad of the potential). Returns the pairs in contact. */
int wc_mesh_pairs_newton(const wc_mesh_pairs* pp, const double* x, double he, double* A, double* g_out);

/* One pair's energy, forces (f, cnt x 3, N) and force Jacobian blocks (J, cnt x cnt x 9, N/m,
 * dF_a/dx_b at (a * cnt + b) * 9) at positions x: for tests. Returns the energy (J). */
double wc_mesh_pair_eval(const wc_mesh_pair* pr, const double* x, double* f, double* J);

#endif
