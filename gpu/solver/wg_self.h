/* Self-collision of a GPU cloth: core's stage (core/self_collide.h, the function the CPU's
 * substep calls, with its kept candidates and its threads) run on the host at the end of every
 * GPU substep (TR-BDF2: every stage), where core's substep runs it: after the strain limit and
 * the colliders' projection, before the checks that the judge rules on. The GPU cloth keeps
 * core's guarantee exactly: a cloth that starts a substep free of crossings ends it free of them.
 *
 * With compute passes a GPU proof runs first (wg_self_idle.h): where it shows the stage idle,
 * neither wg_self_begin nor wg_self_end is called (4 bytes read back); elsewhere both, on the
 * start positions the proof copied.
 * Transfers: the positions are read back at the substep's start (the stage's x_start), the
 * positions and velocities at its end (3 arrays of n RGBA32F texels: 48 n bytes a substep). The
 * particles the stage moved go back as one span per array, from the first particle it moved to
 * the last (32 bytes a particle of the span: x and v); a stage that moved nothing uploads
 * nothing. The stage computes in double on the float state read back; what it moved is rounded
 * to float on the way back (far below the CCD's tolerance, thickness / 100).
 *
 * Pinned particles are the fully pinned pins: core's rule (filter ndof 3 and not a sticking
 * contact) reads the same there, since a sticking contact is never pinned and no contact is made
 * on a fully pinned particle (core/collide.c). So no filter or contact state is read back.
 * Everything is allocated at creation; nothing in a step. Calls are made with the cloth's GL
 * context current. */
#ifndef WEFT_GPU_SOLVER_SELF_H
#define WEFT_GPU_SOLVER_SELF_H

#include "self_collide.h"
#include "state.h"
#include "wg_layout.h"

typedef struct wg_self wg_self;

/* The transfers since creation (measurements and tests). */
typedef struct wg_self_io {
    long long runs;             /* stage runs (substeps, or TR-BDF2 stages) */
    long long uploads;          /* runs that moved a particle, so uploaded a span */
    long long read_bytes;       /* bytes read back */
    long long upload_bytes;     /* bytes uploaded */
    /* the idle proof (wg_self_idle.h): */
    long long proofs;           /* substeps (stages) it ran on */
    long long skipped;          /* those it proved idle, so the stage did not run */
    long long checked;          /* WEFT_GPU_SELF_IDLE=check: proved idle, and the stage run anyway */
    long long broken;           /* of those, runs that moved a particle (a broken proof: 0) */
    long long untried;          /* substeps (stages) it did not try, backing off after failures */
    /* the proximity pass on the GPU's listed pairs (wg_self_prox.h): */
    long long prox_settled;     /* substeps it settled (no host stage), of them prox_moved moved something */
    long long prox_moved;
} wg_self_io;

/* For a cloth of n particles in layout L (kept); NULL when out of memory. */
wg_self* wg_self_create(const wg_layout* L, int n, wc_allocator alloc);
void wg_self_destroy(wg_self* ws);

/* The substep's start: its positions x read back into core's stage (wc_self_begin). */
void wg_self_begin(wg_self* ws, wc_self* sc, const wg_tex* x);

/* The substep's end: x and v (the state's textures now) read back, core's stage run on them
 * (wc_self_resolve with s's model, threads and first n_pins pins, he the integrator's step), and
 * what it moved uploaded into x and v. Adds to st (the stage's counts). With judge_energy, *gain
 * is the total energy (J) the stage put in when positive (core/step.c: not charged to the step),
 * else 0. Non-finite positions or velocities: nothing is done (the judge rejects the substep). */
void wg_self_end(wg_self* ws, wc_self* sc, const wc_state* s, int n_pins, double he, const wg_tex* x,
                 const wg_tex* v, int judge_energy, wc_self_stats* st, double* gain);

const wg_self_io* wg_self_transfers(const wg_self* ws);
/* The idle proof's outcome on a substep: idle (1: proved idle), its bytes read back. */
void wg_self_count_proof(wg_self* ws, int idle, long long bytes);
/* A substep settled by the proximity pass on the listed pairs: moved (particles), bytes uploaded. */
void wg_self_count_prox(wg_self* ws, int moved, long long up_bytes);
/* WEFT_GPU_SELF_IDLE=check: the stage run where the proof said idle moved (1) or not (0). */
void wg_self_count_check(wg_self* ws, int moved);
/* A substep the proof did not try (its back-off). */
void wg_self_count_untried(wg_self* ws);

#endif
