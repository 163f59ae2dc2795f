/* Core's proximity pass on the GPU's listed pairs (compute passes): where the idle proof
 * (wg_self_idle.h) fails only on a few pairs, its walk lists them with their particles' x,
 * x_start and v (13 texels a pair, wg_self_idle_list), and the host runs core's proximity pass on
 * those pairs alone (wc_self_pass_pair: core's rule, in double, in core's order: by query, then
 * by the element's leaf), uploads the particles it moved (x, and v += dx / he) and runs the
 * refined proof (wg_self_idle_refined: every pair too_far at the new end positions). Where that
 * holds, core's stage would end after its proximity pass (its impulse pass finds no CCD
 * collision), so the substep is settled without reading back the state: the result is core's
 * stage's. Else (a CCD hit among the listed pairs, a list past its room, the refined proof
 * failing) the moved particles are restored and core's stage runs on the host as without it.
 *
 * What is not core's: a pair the GPU did not list (proved idle at the end positions before the
 * impulses) whose particle an impulse moved is not revisited as core's serial visit would (at
 * the intermediate positions); the refined proof checks it at the final ones, so no crossing can
 * appear (every pair too_far: no pair comes within eta along the substep's motion).
 * WEFT_GPU_SELF_PROX (read at creation): "on" uses it (with the idle proof on), anything else
 * not. Where the substep is judged on energy and the pass moved something, the energy it put in
 * (not charged, as the stage's) is summed over the moved particles and their springs, their
 * neighbours' x read back one texel each (docs/design/gpu_self_prox.md). Everything is
 * allocated at creation; calls are made with the cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_SELF_PROX_H
#define WEFT_GPU_SOLVER_SELF_PROX_H

#include "self_collide.h"
#include "state.h"
#include "wg_layout.h"
#include "wg_self_idle.h"

typedef struct wg_self_prox wg_self_prox;

/* The pass's own counts since creation (measurements and tests). */
typedef struct wg_self_prox_io {
    long long refined_walks;    /* moving passes proved by the refined walk */
    long long refined_skipped;  /* moving passes proved by the listing's margin (no refined walk) */
    long long local_gains;      /* energy gains from the moved particles and their springs */
    long long full_gains;       /* from the whole state read back (WEFT_GPU_SELF_PROX_GAIN=full|both) */
    double gain_diff_max;       /* =both: the largest |local - full| (J, before clamping at 0) */
    double gain_max;            /* =both: the largest |full gain| (J, before clamping) */
    double total_max;           /* =both: the largest |total energy| the full gain differenced (J) */
    long long margin_checked;   /* REFINED=check: margin proofs checked by the refined walk */
    long long margin_missed;    /* ... of them where it listed a pair with a touched particle that the
                                   first list lacked (or more than the room): a wrong proof */
    long long margin_pairs;     /* the pairs with a touched particle it listed (so compared) */
} wg_self_prox_io;

#define WG_SELF_PROX_CAP 512 /* the listed pairs' most room */

/* The list's room for n particles: n / 8 pairs (at 208 bytes a pair, at most 26 bytes a particle
 * read back, where the host's stage reads 48), between 16 and WG_SELF_PROX_CAP; env (from
 * wg_self_prox_env) > 0: env. */
int wg_self_prox_cap(int n, int env);
/* WEFT_GPU_SELF_PROX: "on" -1 (the room by the cloth's size), a number N > 0 the room N (at
 * most WG_SELF_PROX_CAP: tests), anything else 0 (off). */
int wg_self_prox_env(void);
/* For the cloth m (its particles, its springs for the local gain); NULL when out of memory.
 * WEFT_GPU_SELF_PROX_REFINED=walk (tests): the refined walk after every moving pass (no margin
 * skip); =check (tests): the margin decides, and after each pass it proved the refined walk runs
 * anyway (nothing changed by it): every pair it lists with a touched particle must be one of the
 * first list's, which the pass's CCD checked (wg_self_prox_io's margin_missed counts where not); WEFT_GPU_SELF_PROX_GAIN=full: the gain from the whole state read back, =both: both,
 * compared (wg_self_prox_io), the local one used. Read at creation. */
wg_self_prox* wg_self_prox_create(const wg_layout* L, const wc_model* m, wc_allocator alloc);
void wg_self_prox_destroy(wg_self_prox* p);

const wg_self_prox_io* wg_self_prox_transfers(const wg_self_prox* p);

/* The list's room (52 floats a pair, WG_SELF_PROX_CAP pairs) for wg_self_idle_list. */
float* wg_self_prox_buffer(wg_self_prox* p);

/* The pass on the count pairs listed in the buffer (1..cap) at the end of a substep: returns 1
 * when settled (x and v on the GPU are core's stage's result; its proximity impulses added to
 * st->proximity, *moved the particles moved), 0 when core's stage must run on the host (x and v
 * as they were). Adds the bytes read back to *bytes, the uploads to *up_bytes. With gain (the
 * energy judge on) and a particle moved: *gain the energy the pass put in, as wg_self_end gives
 * the stage's but summed locally (else 0). A moving pass whose largest move is at most half the
 * listing's margin (wg_self_idle_margin) is proved without the refined walk. */
int wg_self_prox_run(wg_self_prox* p, wg_self_idle* si, wc_self* sc, const wc_state* s, int n_pins, double he,
                     int count, const wg_tex* x, const wg_tex* v, wc_self_stats* st, long long* bytes,
                     long long* up_bytes, int* moved, double* gain);

#endif
