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
 *      that moves rigidly: no crossing). After each rigid motion the stretch springs it stretched
 *      are relaxed (up to WC_SELF_RELAX_PASSES passes) to the larger of (1 + zone_strain) x rest
 *      and the length the solve left them, moving only particles outside the zones, and the next
 *      detection pass checks what that moved.
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
#include "bvh.h"
#include "filter.h"
#include "model.h"
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

typedef struct wc_self {
    double thickness;   /* m, > 0 */
    double eta;         /* m: CCD tolerance, thickness / 100 */
    int passes;         /* CCD impulse passes before the zones (WC_SELF_PASSES); tests set 0 (no
                           CCD impulse: every collision goes to the zones) to drive the zones */
    int detect_all;     /* tests: 1 = every pass checks every pair (default 0: after the first,
                           only the pairs with a dirty particle) */
    double zone_strain; /* the springs a zone stretched are relaxed to this strain, or what the
                           solve left, if more (WC_SELF_ZONE_STRAIN; infinity: not relaxed) */
    int n, n_tris, n_edges;
    int* edges;         /* (n_edges x 2) particle pairs, each vertex pair once */
    wc_bvh tri_bvh, edge_bvh;
    double* tri_box;    /* (n_tris x 6) */
    double* edge_box;   /* (n_edges x 6) */
    double* x_start;    /* (n x 3) m: positions at the start of the substep */
    double* x_old;      /* (n x 3) m: end positions before the stage */
    double* inv_mass;   /* (n) 1/kg, 0 for pinned, this substep */
    int* parent;        /* (n) union-find of the impact zones */
    unsigned char* in_zone; /* (n) 1: the particle is in a zone */
    unsigned char* active;  /* (n + n_edges) 1: the query (vertex i, then edge n + e) has a pair
                               that needs action this pass (parallel scan's result) */
    int* edge_max;      /* (edge_bvh.n_nodes) the largest edge index under each node: an edge's
                           query skips the subtrees of lower edges (each pair visited once) */
    unsigned char* dirty;     /* (n) each: 1 for a particle whose pairs the next pass must check */
    unsigned char* dirty_next; /* (wc_self_resolve: the dirty set and the one being marked) */
    unsigned char* tri_mask;  /* (tri_bvh.n_nodes), edge_mask (edge_bvh.n_nodes): 1 for a node */
    unsigned char* edge_mask; /* with an element of a dirty particle under it */
    int threads;        /* >= 1: detection threads (the state's wc_par; 1 at creation) */
    double* zone;       /* (n x WC_SELF_ZONE_STRIDE) per-zone accumulators (self_zones.h) */
    int* seam_start;    /* (n + 1) CSR of each particle's seam partners (self_broad.h; NULL: none): */
    int* seam_nbr;      /* a particle is never tested against an element it is sewn to */
    unsigned char* tangled; /* (n) 1: the particle belongs to an edge-triangle pair that crosses in
                           the rest shape; pairs made only of such particles are skipped */
    int tangled_pairs;  /* those crossing pairs (0 for a mesh that starts untangled) */
    wc_allocator alloc;
} wc_self;

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
