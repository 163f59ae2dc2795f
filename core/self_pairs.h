/* Self-contacts inside the implicit solve (issue 13): a cloth vertex against a triangle, and a
 * cloth edge against an edge, of the same cloth (another layer, panel or fold), as one-sided
 * stiff springs (penalty) in the system of the substep, so that both sides of a contact move
 * together in the solve: a layer falling onto a layer the body holds is stopped by it, and pushes
 * it, within the substep's system. The self-collision stage after the solve (self_collide.h)
 * stays the guarantee (no crossing at the end of a substep); these pairs make what it has to
 * correct small. Only with self-collision on.
 *
 * The two sides share no spring, so the pattern (bsr.h) has no block between them: each pair is
 * a rank-one coupling (coupling.h): its diagonal blocks go into A, the off-diagonal ones into
 * the solvers' products (wc_solver_set_coupling).
 *
 * Detection (wc_self_pairs_find, at the substep's start, before the assembly), on the
 * self-collision trees refitted over the boxes of x_n and x_n + 1.5 h v_n inflated by the
 * thickness (so the broad phase covers the contact distance below): vertex i against triangle t
 * (i not in t) and edge e against edge f > e (no shared particle), pairs with a particle sewn to the other
 * side or made only of particles tangled at rest skipped (self_collide.h's rules). The closest
 * points at the start must be interior to both features (barycentric weights and edge
 * parameters above 1e-6: a vertex nearest an edge or a vertex is left to the stage) and closer
 * than th + thickness + 1.5 h a (a: the approach speed along the pair's direction at v_n, when
 * positive), with th = min(thickness, the pair's distance at rest) as in the stage. Frozen for
 * the substep: the weights w (vertex-triangle: 1, -b1, -b2, -b3; edge-edge: 1-s, s, -(1-t), -t),
 * and the unit normal n from the second feature to the first at the start.
 *
 * The term: gap g(x) = n . sum w_i x_i - th (linear in x), E = k/2 min(g, 0)^2, with
 * k = WC_SELF_PAIR_KAPPA m_eff / he^2 and m_eff = 1 / sum w_i^2 / m_i over the unpinned
 * particles (mesh_pairs.h's choice: the pair adds KAPPA times the point's inertia along n).
 * Active in the first system when its gap predicted at the substep's end (x_n + he (v* + he
 * f_ext / m)) is negative; without Newton iterations a pair whose solved gap disagrees is switched
 * and the system solved again (WC_SELF_PAIR_PASSES at most); with Newton iterations those see the
 * exact term (energy, gradient and linearisation at every iterate). The energy judge does not
 * count the pairs' energy. Frictionless. Pairs past the list's capacity are counted (overflow),
 * not silently dropped. Derived, not state: re-found every substep. Deterministic on any thread
 * count: the detection runs its queries (every vertex, then every edge) on sc->threads threads
 * in fixed ranges, counting first, then writing each query's pairs where the prefix sum of the
 * counts puts them (the serial list, in query order); the assembly and the coupling's product
 * are serial. */
#ifndef WEFT_CORE_SELF_PAIRS_H
#define WEFT_CORE_SELF_PAIRS_H
#include "alloc.h"
#include "coupling.h"

#define WC_SELF_PAIR_KAPPA 100.0   /* stiffness over inertia along n */
#define WC_SELF_PAIR_PASSES 3      /* re-solves at most when the active set changes (no Newton) */
#define WC_SELF_PAIR_MARGIN 1.1    /* the penalty holds a pair at this x its rest gap th, outside
                                      the stage's proximity band (< th) */

typedef struct wc_self_pairs {
    int cap;                   /* capacity (fixed at creation) */
    int n;                     /* pairs of the current substep */
    int overflow;              /* pairs found past cap in the current substep */
    wc_coupling_term* term;    /* (cap) cnt 4, p, w, n; c = he^2 k while active, else 0 */
    double* th;                /* (cap) m: the pair's rest gap */
    double* k;                 /* (cap) N/m */
    wc_coupling coupling;      /* the active terms, for the solver (n, term) */
    double* x_pred;            /* (n_particles x 3) scratch: x_n + 1.5 h v_n */
    int* start;                /* (n_particles + n_edges + 1) scratch of a parallel detection:
                                  where each query's pairs start in the list */
    int n_particles;
} wc_self_pairs;

struct wc_model;
struct wc_filter;
struct wc_self;

/* Capacity cap >= 1 for a cloth of n_particles whose self-collision list has n_edges edges.
 * NULL on out of memory. */
wc_self_pairs* wc_self_pairs_create(int cap, int n_particles, int n_edges, const wc_allocator* a);
void wc_self_pairs_destroy(wc_self_pairs* sp, const wc_allocator* a);

/* Detection (above): sc the cloth's self-collision list (its trees are refitted here), f (NULL:
 * no pins) the filter (ndof 3: pinned), x, v (n x 3) at the substep's start, h the substep, he
 * the system's step. Resets the list; returns the pairs found. */
int wc_self_pairs_find(wc_self_pairs* sp, struct wc_self* sc, const struct wc_model* m, const struct wc_filter* f,
                       const double* x, const double* v, double h, double he);

/* The first system (as wc_mesh_pairs_assemble): adds the active pairs' diagonal blocks to A and
 * he f to b (f_total, NULL: none, gets the forces at x_n); sets their coupling coefficients.
 * Returns the active pairs. */
int wc_self_pairs_assemble(wc_self_pairs* sp, const struct wc_model* m, const double* x, const double* vstar,
                           const double* f_ext, double he, double* A, double* b, double* f_total);

/* After a solve of the first system (dv): switches the pairs whose gap at x_n + he (v* + dv)
 * disagrees with their state, in A, b and the coupling. Returns the pairs switched. */
int wc_self_pairs_recheck(wc_self_pairs* sp, const struct wc_model* m, const double* x, const double* vstar,
                          const double* dv, double he, double* A, double* b);

/* Newton (newton.c): the pairs' energy at positions x, and their gradient (-he f into g_out) and
 * diagonal blocks into A where they touch at x, coupling coefficients set to match. Returns the
 * touching pairs. */
double wc_self_pairs_energy(const wc_self_pairs* sp, const double* x);
int wc_self_pairs_newton(wc_self_pairs* sp, const struct wc_model* m, const double* x, double he, double* A,
                         double* g_out);

/* Energy and forces of one pair at x (tests): f (4 x 3) and J = df/dx (4 x 4 blocks of 9). */
double wc_self_pair_eval(const wc_self_pairs* sp, int k, const double* x, double* f, double* J);

#endif
