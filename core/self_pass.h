/* One pass of the self-collision stage (self_collide.h) over every vertex-triangle and edge-edge
 * candidate pair of the stage's trees (self_broad.h), from the substep's start sc->x_start to
 * its end positions x: proximity and CCD impulses, or the impact zones' detection. It allocates
 * nothing: candidates are visited in the trees (no pair buffers).
 *
 * Parallel detection (threads > 1, OpenMP; core/par.h's chunks of queries, any to any thread): every pass
 * first scans all vertices and edges read-only, on as many threads as sc->threads, and marks in
 * active[] (n + n_edges bytes, allocated at creation: nothing can overflow) each query that has
 * at least one pair needing action at the pass's starting positions (a proximity impulse, a CCD
 * collision, in the zone loop a collision between two zones); a query's mark stops at its
 * first such pair. Then one thread visits the marked queries alone, in index order, with the
 * serial code (re-evaluated on the current positions, impulses applied in place). A mark
 * depends only on the positions, never on the thread count, so the result is bit-identical
 * for any number of threads. A pair that only starts needing action after an earlier impulse
 * of the same pass waits for the next pass (the serial stage caught it in the same pass); the
 * guarantee is unchanged: the loop still ends only on a pass that found nothing to do (its
 * scan then covered every pair at the final positions) or in the zones, whose detection
 * passes visit exactly the pairs the serial loop did (a pair skipped at a pass's start as
 * inside one zone stays so: zones only grow within a pass).
 *
 * Cost: O((n + edges) log n) queries per pass; a cloth not touching itself does one pass (the
 * proximity and CCD tests at once; an edge queries only the edges of higher index, a pair whose
 * start boxes are far apart relative to its motion skips the closest-point tests, and the CCD's
 * cubic runs only when the pair's relative motion can close its start distance). Every pass
 * after the first scans only the pairs with a dirty particle (one of a pair an earlier pass
 * acted on or counted, a zone's member, one the relaxation moved): a clean vertex or edge visits
 * only the tree nodes with a dirty element below (wc_bvh_query_masked). A pair with no dirty
 * particle has not moved since a pass found it needing nothing, so the scan marks the queries
 * the unfiltered one would, and the serial visit of a marked query is unfiltered: the result is
 * that of checking every pair (detect_all), bit for bit. A clean query whose box meets no cell of
 * the dirty elements' grid (self_grid.h) skips its walk (it would visit nothing), and when the
 * stage says only dirty particles moved since the last pass's refit (wc_self.refit_dirty), the
 * pass refits only the dirty elements' boxes and the nodes above them (the same boxes). The first pass's queries go through
 * their kept candidates (self_near.h) while those still hold: the same visits as the trees'. */
#ifndef WEFT_CORE_SELF_PASS_H
#define WEFT_CORE_SELF_PASS_H
#include "model.h"
#include "self_data.h"

/* What a pass does with the pairs that need action. */
enum {
    WC_SELF_PASS_PROXIMITY = 0, /* proximity impulses, then CCD impulses, on each pair (the first pass) */
    WC_SELF_PASS_IMPULSE = 1,   /* CCD impulses */
    WC_SELF_PASS_DETECT = 2     /* CCD collisions merged into zones (sc->parent, in_zone), nothing moved */
};

/* One pass in `mode` over the candidates (dirty non-NULL: only those with a particle i dirty[i])
 * at the end positions x (n x 3, corrected in place but in WC_SELF_PASS_DETECT); refits the
 * trees first (only under the dirty nodes when sc->refit_dirty, which the pass clears). Returns the CCD collisions found (given an impulse where one applies); *prox (may
 * be NULL) gets the proximity impulses; touched (may be NULL) 1 for the particles of every pair
 * acted on or counted (the next pass's dirty set). */
int wc_self_pass(wc_self* sc, const wc_model* m, double* x, int mode, int* prox, const unsigned char* dirty,
                 unsigned char* touched);
/* One pair of a pass in mode (PROXIMITY or IMPULSE), as wc_self_pass's serial visit of query q
 * (a vertex q < n against triangle elem, else the edge q - n against the edge elem) gives it:
 * the adjacency rules, the proximity impulse (PROXIMITY; added to *prox, may be NULL) on x, then
 * too_far and the CCD, but a CCD hit is only counted (no impulse); touched (may be NULL) as
 * wc_self_pass's. Reads only the pair's particles of x, sc->x_start and sc->inv_mass. Returns
 * the CCD hits (0 or 1): the GPU's proximity pass over its listed pairs (gpu/solver/wg_self_prox.h)
 * falls back to the whole stage on one. mode | WC_SELF_PAIR_DRY: the pass's read-only scan instead
 * (nothing moved; 1 when the pair needs action: its query is one the serial visit takes). */
#define WC_SELF_PAIR_DRY 16
int wc_self_pass_pair(wc_self* sc, const wc_model* m, double* x, int mode, int q, int elem, int* prox,
                      unsigned char* touched);

#endif
