/* The idle proof of a GPU cloth's self-collision stage (compute passes, GL 4.3): a chain of
 * passes that proves, conservatively, that core's stage (wg_self.h, core/self_collide.h) would
 * move nothing this substep, so that its read-backs and its host run are skipped; when the proof
 * fails the stage runs exactly as without it (the same read-backs, the same core call).
 *
 * When core's stage acts (core/self_pass.c): only if its first pass (proximity) acts on a pair,
 * a vertex-triangle or edge-edge pair of the cloth not excluded by the adjacency rules (a shared
 * or sewn particle; all four particles tangled at rest). Such a pair acts only if its distance
 * d0 at the substep's START positions is under the thickness (a proximity impulse: th <=
 * thickness) or if core's too_far does not hold (d0 - max_rel <= eta = thickness / 100, max_rel
 * the largest |d_i - d_j| of a particle of each feature, d = x - x_start; only then does the CCD
 * run). A pass that acts on nothing leaves the positions as they were and the velocities get
 * (x - x_old) / he = 0: nothing moves. So the stage is idle when every kept pair has
 *     d0 >= thickness  and  d0 - max_rel > eta.
 * The proof: core's two trees (the triangles', the unique edges'; their shapes uploaded at
 * creation) refitted on the GPU over each element's start box grown by its particles' largest
 * displacement delta and the reach R = thickness (1 + rel) (self_idle_refit_groups.glsl); each
 * query (a particle against the triangles, an edge against the edges above it) walks them with
 * its start box grown by its own delta (self_idle_walk_groups.glsl). A pair the walk does not
 * reach has d0 > delta_a + delta_b + R >= max_rel + R: idle. A pair it reaches is tested in
 * float: a lower bound L of d0 (the support bound of the start positions' difference set along
 * the float closest points' direction, less margins for float's rounding: 4e-6 of the pair's
 * extent, mu = 1e-3 thickness) against thickness (1 + rel) and L - max_rel (grown by rounding's
 * bound) against eta (1 + rel), rel = 1e-3. Every pair that may act adds one to a counter, read
 * back (4 bytes, a synchronisation) before the end's checks: the stage's result is what they
 * measure, so the decision must come first.
 *
 * The substep's start positions are copied on the GPU at its start (one copy pass), so that
 * core's x_start (wc_self_begin) is read back only when the stage runs. Nothing new is state:
 * the copy is made at every substep's (TR-BDF2: stage's) start, after any rollback. Core's kept
 * candidate lists (self_near.h) are not state either: they give the same answers as the trees'
 * walk whichever runs they served, so skipped runs change nothing later.
 *
 * WEFT_GPU_SELF_IDLE (read at creation): unset or "on" the proof; "off" no proof (the stage
 * every substep, as on fragment passes); "check" the proof, and core's stage run anyway where it
 * proved idle, counting the runs where the stage moved something (a broken proof). Tests'
 * mutations, WEFT_GPU_SELF_IDLE_MUTATION: "no-delta" (the displacement left out of the proof),
 * "no-shared" (pairs sharing a particle tested too), "no-margin" (the rounding margins 0).
 * With a list's room (wg_self_prox.h, WEFT_GPU_SELF_PROX) the walk also lists the pairs that may
 * act, for core's proximity pass on them and a refined proof after it.
 * Calls are made with the cloth's GL context current; everything is allocated at creation. */
#ifndef WEFT_GPU_SOLVER_SELF_IDLE_H
#define WEFT_GPU_SOLVER_SELF_IDLE_H

#include "model.h"
#include "self_data.h"
#include "wg_runner.h"

typedef struct wg_self_idle wg_self_idle;

typedef enum wg_self_idle_mode { WG_SELF_IDLE_OFF, WG_SELF_IDLE_ON, WG_SELF_IDLE_CHECK } wg_self_idle_mode;

/* The mode WEFT_GPU_SELF_IDLE asks for (OFF when the value is unknown). */
wg_self_idle_mode wg_self_idle_env(void);

/* For the cloth m with core's stage sc (its trees, edges, seam links and tangled flags), n
 * particles; 0 with err (GL, memory, textures too small). Compute passes only. */
int wg_self_idle_create(wg_runner* run, const wc_self* sc, const wc_model* m, wg_self_idle_mode mode, int cap,
                        wg_self_idle** out, char* err, size_t err_len);
void wg_self_idle_destroy(wg_self_idle* si, int gl);   /* gl 0: the memory only */
size_t wg_self_idle_bytes(const wg_self_idle* si);      /* GPU memory held (0 for NULL) */
wg_self_idle_mode wg_self_idle_get_mode(const wg_self_idle* si);

/* The substep's (stage's) start: 1 if the proof is tried at its end, its positions x then
 * copied; 0 while it backs off (the caller reads the start back for the stage as without it).
 * The back-off: after k >= 2 proofs failed in a row, the next min(2^(k-2), 8) substeps are not
 * tried (a cloth whose stage acts on every substep pays for the proof about once in 9); a proof
 * that succeeds resets it. The check mode tries every substep. Which substeps are tried changes no
 * result (an idle stage moves nothing), so the back-off is not state. */
int wg_self_idle_begin(wg_self_idle* si, const wg_tex* x);
/* The copy (core's x_start, read back when the stage runs). */
const wg_tex* wg_self_idle_start(const wg_self_idle* si);
/* The proof at the end positions x of a substep whose start tried it: the pairs that may act
 * (0: the stage is idle). Reads back 4 bytes (added to *bytes). */
int wg_self_idle_count(wg_self_idle* si, const wg_tex* x, long long* bytes);
/* The GPU's proximity pass (wg_self_prox.h), with a list's room cap > 0 given at creation (the
 * argument cap; 0: none): the same proof listing the pairs that may act, 13 texels (52 floats) a
 * pair into out when the count (returned) is 1..cap: (q, element, -, -), then x, xs and v of its
 * 4 particles; a count past cap: no list (the host's stage). refined 1: the proof after that
 * pass's impulses, the thickness test left out (a pair listed where too_far may fail). The
 * back-off is not updated (wg_self_idle_outcome). */
int wg_self_idle_list(wg_self_idle* si, const wg_tex* x, const wg_tex* v, int refined, float* out, long long* bytes);
int wg_self_idle_cap(const wg_self_idle* si);
/* The listing walk (refined 0) proves an unlisted pair too_far with this margin to spare (m):
 * d0 - max_rel > eta (1 + rel) + margin, so that after the pass's impulses, each moving a particle
 * by at most margin / 2, every unlisted pair is still too_far and the refined walk is not needed
 * (wg_self_prox.h). WG_SELF_IDLE_MARGIN thicknesses with a list's room, else 0. */
#define WG_SELF_IDLE_MARGIN 0.25
double wg_self_idle_margin(const wg_self_idle* si);
/* The back-off's count: acted 1 after a substep the stage ran on the host. */
void wg_self_idle_outcome(wg_self_idle* si, int acted);

/* The uploads the self pairs' GPU finder shares (wg_self_pairs.h): tree k (0 the triangles', 1
 * the edges') as its nodes (2 texels each: (min, left child), (max, right child or element);
 * rewritten whole by either refit before its walk, so the two share them) and its order by
 * height (first: n_heights + 1 offsets); the elements (triangles, then edges), the particles'
 * (seam links' first, end, tangled) and the seam links. */
typedef struct wg_self_trees {
    const wg_tex *node[2], *order[2];
    const int* first[2];
    int n_heights[2];
    const wg_tex *elem, *part, *seam;
} wg_self_trees;
void wg_self_idle_trees(const wg_self_idle* si, wg_self_trees* out);

#endif
