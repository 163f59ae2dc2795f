/* Self-contacts in the implicit solve: a cloth vertex against a triangle, and a cloth edge
 * against an edge, of the same cloth (another layer, panel or fold), as penalty pairs
 * (penalty_pairs.h), so that both sides of a contact move together in the solve: a layer falling
 * onto a layer the body holds is stopped by it, and pushes it, within the substep's system. The
 * self-collision stage after the solve (self_collide.h) stays the guarantee (no crossing at the
 * end of a substep); these pairs make what it has to correct small. Only with self-collision on
 * and def.self_in_solve.
 *
 * The two sides share no spring, so the pattern (bsr.h) has no block between them: the list is a
 * coupled one, its off-diagonal blocks reach the solvers as the couplings `coupling` (coupling.h,
 * wc_solver_set_coupling). This file finds the pairs at each substep's start (the rules are in
 * self_pairs.c); the list enters them into the system. Frictionless. Derived, not state:
 * re-found every substep. Deterministic on any thread count. */
#ifndef WEFT_CORE_SELF_PAIRS_H
#define WEFT_CORE_SELF_PAIRS_H
#include "alloc.h"
#include "coupling.h"
#include "penalty_pairs.h"

#define WC_SELF_PAIR_MARGIN 1.1    /* the penalty holds a pair at this x its rest gap th, outside
                                      the stage's proximity band (< th) */

typedef struct wc_self_pairs {
    wc_penalty_pairs list;     /* the pairs of the current substep (coupled) */
    wc_coupling coupling;      /* the list's terms as the solvers' couplings (n, list.term) */
    double* x_pred;            /* (n_particles x 3) scratch: x_n + 1.5 h v_n */
    int n_particles;
    int threads;               /* detection threads (par.h's ranges; 1: serial) */
    wc_penalty_pairs* stage;   /* (threads) each thread's pairs before they are appended in order */
    int* resume;               /* (threads x 2) the query where a thread's stage filled up, its
                                  range's end: the rest of its range is found serially */
} wc_self_pairs;

struct wc_model;
struct wc_filter;
struct wc_self;

/* Capacity cap >= 1 for a cloth of n_particles whose self-collision list has n_edges edges, found
 * on `threads` threads (>= 1): each thread stages the pairs of its fixed range of queries in room
 * for stage_cap pairs (<= 0: cap over the threads, plus 64), and the ranges are appended in order,
 * so the list is the serial one on any thread count; a range whose stage fills up is finished
 * serially, in its place. NULL on out of memory. */
wc_self_pairs* wc_self_pairs_create(int cap, int n_particles, int n_edges, int threads, int stage_cap,
                                    const wc_allocator* a);
void wc_self_pairs_destroy(wc_self_pairs* sp, const wc_allocator* a);

/* Detection (self_pairs.c): sc the cloth's self-collision list (its trees are refitted here), f (NULL:
 * no pins) the filter (ndof 3: pinned), x, v (n x 3) at the substep's start, h the substep, he
 * the system's step. Empties the list first; returns the pairs found. */
int wc_self_pairs_find(wc_self_pairs* sp, struct wc_self* sc, const struct wc_model* m, const struct wc_filter* f,
                       const double* x, const double* v, double h, double he);
/* The same list from candidates found elsewhere (a GPU's walk, gpu/solver/wg_self_pairs.h):
 * cand (n_cand x 2) the pairs (query, element), a query a vertex q < n (its element a triangle)
 * or the edge q - n (an edge of sc), sorted by query and then by the element's leaf in its tree
 * (sc->tri_bvh / edge_bvh leaf_of: the order of wc_self_pairs_find's walks). Each candidate takes
 * the walk's leaf test (the boxes of x and x + 1.5 h v, the element's grown by the thickness,
 * overlap; an edge above the query's) and wc_self_pairs_find's rules, in double, in that order:
 * when the candidates hold every pair that test passes, the list (its pairs, order and overflow)
 * is wc_self_pairs_find's. The trees are not touched. */
int wc_self_pairs_from(wc_self_pairs* sp, const struct wc_self* sc, const struct wc_model* m,
                       const struct wc_filter* f, const double* x, const double* v, double h, double he,
                       const int* cand, int n_cand);

#endif
