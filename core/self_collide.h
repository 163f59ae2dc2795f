/* Self-collision of one cloth (one model: its panels, layers and separate components included),
 * after Bridson, Fedkiw & Anderson 2002 ("Robust treatment of collisions, contact and friction
 * for cloth animation") with Harmon et al. 2008's rigid impact zones. A stage at the very end of
 * every substep (after the strain limit and the colliders' projection, so that nothing after it
 * can bring a crossing back), on the substep's start positions x_start (copied by
 * wc_self_begin at the top of the substep: the end of the previous, accepted substep) and its end
 * positions x (the integrator's result):
 *   1. Broad phase (self_broad.h): two AABB trees (bvh.h), over the triangles and over the
 *      (unique) edges, built once at creation and refitted over the swept boxes x_start U x
 *      inflated by the thickness. Pairs sharing a particle, or a particle and one it is sewn to,
 *      are excluded; so are pairs whose particles all belong to edge-triangle pairs that cross in
 *      the rest shape (self_crossings.h; a garment that starts tangled: preventing new crossings
 *      cannot undo those, and fighting them locks impact zones and stretches the cloth).
 *   2. Proximity (at x_start): vertex-triangle and edge-edge pairs closer than the pair's
 *      thickness (min(thickness, the pair's distance at rest), so a mesh finer than the thickness
 *      is not pushed against itself) get their relative normal displacement over the substep
 *      raised to at least 0.1 (thickness - distance): an inelastic impulse when they approach,
 *      and a bounded repulsion that separates them to the thickness over a few substeps.
 *   3. Continuous (x_start -> x, linear): up to WC_SELF_PASSES passes of inelastic impulses on
 *      the pairs that collide (geom.h's CCD within eta = thickness / 100).
 *   4. Impact zones for what is left (self_zones.h): the particles of every colliding pair are
 *      merged (union-find); each zone's displacements are replaced by its rigid motion (linear
 *      momentum kept, angular momentum to first order; an exact rotation); detect again (pairs
 *      inside one zone cannot collide: along the linear path x_start -> x they move by one
 *      affine map, (1 - t) I + t R, invertible for turns under half a revolution), merge,
 *      repeat, at most WC_SELF_ZONE_ITERS times (in the worst case everything ends in one zone
 *      that moves rigidly: no crossing). After each rigid motion the stretch springs the zones
 *      stretched are relaxed (up to WC_SELF_RELAX_PASSES passes) to the larger of
 *      (1 + zone_strain) x rest and the length the solve left them, moving only particles outside
 *      the zones, and the next detection pass checks what that moved.
 * Stages 2 to 4 run as passes over the candidate pairs (self_pass.h: the parallel scan, and the
 * later passes' dirty sets; bit-identical for any number of threads).
 * Impulses are distributed over the 4 particles with the barycentric / edge weights w and the
 * inverse masses (Bridson section 7.1): a change D of the relative normal displacement moves
 * particle i by w_i inv_m_i D / sum_j (w_j^2 inv_m_j) along the normal. Pinned particles (filter
 * ndof 3 that is not a sticking contact) have inverse mass 0 (in a zone: a mass 1e8 x their
 * own, and their own motion is kept).
 * Corrections are position changes dx of the end positions, turned into velocity changes
 * dv = dx / he (he = h for backward Euler, 2h/3 for BDF2), which keeps x = xb + he v of both
 * integrators (bdf2.h). The stage allocates nothing: its candidates are visited in the trees
 * (no pair buffers), and its zone accumulators are (n) arrays allocated at creation.
 * The close pairs are also penalty terms of the substep's implicit solve (self_pairs.h, on by
 * default with self-collision: sim def self_in_solve), so both sides of a contact move together in
 * the solve and this stage has little left to correct; it stays the guarantee.
 * A cloth that starts a substep free of crossings ends it free of them, unless the zone loop
 * runs out of iterations (stats.unresolved counts the pairs still colliding then; with pins
 * that move against each other inside one zone this can happen).
 * Measured cost and behaviour: docs/design/self_collision.md. */
#ifndef WEFT_CORE_SELF_COLLIDE_H
#define WEFT_CORE_SELF_COLLIDE_H
#include "filter.h"
#include "model.h"
#include "self_data.h"
/* the stage's parts, each with its contract: users of the stage get them with it */
#include "self_broad.h"
#include "self_crossings.h"
#include "self_zones.h"

#define WC_SELF_PASSES 4        /* CCD impulse passes before impact zones */
#define WC_SELF_ZONE_ITERS 200  /* impact-zone merge iterations at most */
#define WC_SELF_ZONE_STRAIN 0.1 /* wc_self.zone_strain's default */
#define WC_SELF_RELAX_PASSES 8  /* relaxation passes after each rigid motion, at most */

typedef struct wc_self_stats {
    int proximity;      /* pairs given a proximity impulse (repulsion or inelastic) */
    int impacts;        /* CCD collisions found by the impulse passes (each given an impulse
                           where one applies) */
    int zones;          /* impact zones formed (sets of 2+ particles at the end of the loop) */
    int unresolved;     /* pairs still colliding when the zone loop gave up (0 normally) */
    int relaxed;        /* stretch-spring corrections after the zones' rigid motions */
} wc_self_stats;

/* thickness: m, finite and > 0. */
wc_status wc_self_create(wc_self** out, const wc_model* m, double thickness, const wc_allocator* alloc,
                           wc_diag* diag);
void wc_self_destroy(wc_self* sc);

/* Start of a substep: x (n x 3) is the start position. */
void wc_self_begin(wc_self* sc, const double* x);

/* End of a substep: corrects x and v (n x 3) in place (stages 1-4 above). filter and stick (may
 * be NULL: nothing pinned) say which particles are pinned; he the integrator's step (s). Adds to
 * st (may be NULL). Returns st->unresolved's contribution (0 when no crossing is left). */
int wc_self_resolve(wc_self* sc, const wc_model* m, const wc_filter* filter, const unsigned char* stick, double he,
                    double* x, double* v, wc_self_stats* st);

#endif
