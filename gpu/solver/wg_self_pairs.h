/* The self-contact pairs (core/self_pairs.h) of a GPU cloth found on the GPU (compute passes,
 * GL 4.3; fragment passes keep core's wc_self_pairs_find on the host): the list core's detection
 * makes, pair for pair, in its order, from the same (float) start positions x and velocities v.
 *
 * Core's detection (core/self_pairs.c) refits its two self trees (the triangles', the unique
 * edges') over the boxes of x and x + 1.5 h v grown by the thickness, walks them for each query
 * (a particle against the triangles, an edge against the edges above it) with the query's box of
 * x and x + 1.5 h v, and keeps, of the elements the walk reaches, the pairs its rules keep
 * (adjacency, tangled, interior, the rest gap, the approach-speed distance, an unpinned particle,
 * the cap). Here the walk is on the GPU, over the trees the idle proof uploaded (wg_self_idle.h,
 * wg_self_idle_trees: their nodes, refitted here over those boxes, self_pairs_refit_groups.glsl),
 * each query's candidates (self_pairs_walk_groups.glsl) every element whose leaf box meets the
 * query's, both grown for float's rounding (4e-6 of the largest magnitude), that the adjacency
 * rules keep and that is not surely farther than core's keep allows (2 thickness + 1.5 h times
 * the largest relative speed of a particle of each feature: core's approach speed is at most
 * that, its weights convex on each side). The counter (4 bytes) and the candidates (8 bytes each: query, element) are
 * read back; sorted by query and leaf (the order of core's walks), core's wc_self_pairs_from tests
 * each in double exactly as wc_self_pairs_find does (the walk's box test at core's boxes, then its
 * rules), so the list, its order and its overflow are core's. More candidates than the room (16
 * a query, or 16 times the list's capacity if more), a walk deeper than its stack (which core's
 * median-split trees cannot reach: wg_self_pairs_find), or a non-finite x or v: core's
 * wc_self_pairs_find instead that substep (counted, wg_self_pairs_io).
 *
 * WEFT_GPU_SELF_PAIRS (read at the cloth's creation): unset or "gpu" this finder; "host" core's
 * detection on the host (the test's comparison); anything else is logged and the host's used.
 * Tests' mutations, WEFT_GPU_SELF_PAIRS_MUTATION: "no-motion" (x + 1.5 h v left out of the GPU's
 * boxes and reach), "no-pad" (the leaves not grown by the thickness), "no-rules" (the GPU's
 * adjacency rules off: more candidates, the same list). Calls are made with the cloth's GL
 * context current; everything is allocated at creation. */
#ifndef WEFT_GPU_SOLVER_SELF_PAIRS_H
#define WEFT_GPU_SOLVER_SELF_PAIRS_H

#include "filter.h"
#include "model.h"
#include "self_data.h"
#include "self_pairs.h"
#include "wg_runner.h"
#include "wg_self_idle.h"

typedef struct wg_self_pairs wg_self_pairs;

typedef enum wg_self_pairs_mode { WG_SELF_PAIRS_HOST, WG_SELF_PAIRS_GPU } wg_self_pairs_mode;

/* The mode WEFT_GPU_SELF_PAIRS asks for (HOST when the value is unknown); *known 0 then. */
wg_self_pairs_mode wg_self_pairs_env(int* known);

/* For the cloth m with core's stage sc and pairs sp; idle the idle proof whose uploads it shares
 * (NULL: it makes its own); 0 with err (GL, memory). Compute passes only. */
int wg_self_pairs_create(wg_runner* run, const wc_self* sc, const wc_self_pairs* sp, const wc_model* m,
                         wg_self_idle* idle, wg_self_pairs** out, char* err, size_t err_len);
void wg_self_pairs_destroy(wg_self_pairs* gp, int gl);   /* gl 0: the memory only */
size_t wg_self_pairs_bytes(const wg_self_pairs* gp);      /* GPU memory held (0 for NULL) */

/* Core's list sp->list (wc_self_pairs_find's) from the textures x, v (on the GPU) and their
 * values xd, vd (n x 3 doubles, the same floats: the host's tests), f the pins' filter, h the
 * substep, he the system's step. Returns the pairs; *bytes (may be NULL) the bytes read back;
 * *candidates (may be NULL) the candidates found (-1: core's detection ran: too many, or x or v
 * not finite, checked first: then nothing runs on the GPU and *bytes is 0). */
int wg_self_pairs_find(wg_self_pairs* gp, wc_self_pairs* sp, wc_self* sc, const wc_model* m, const wc_filter* f,
                       const wg_tex* x, const wg_tex* v, const double* xd, const double* vd, double h, double he,
                       size_t* bytes, int* candidates);

/* Since creation: substeps found (on the GPU or by core), those core found (by_core: over_room
 * + non_finite), of them those past the room or its walk's stack (the counter past the room) and
 * those with a non-finite x or v (nothing run on or read from the GPU), the candidates and the
 * bytes read back. A substep core found also gives *candidates -1. */
typedef struct wg_self_pairs_io {
    long long finds, by_core, over_room, non_finite, candidates, read_bytes;
} wg_self_pairs_io;
const wg_self_pairs_io* wg_self_pairs_transfers(const wg_self_pairs* gp);

#endif
