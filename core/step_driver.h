/* The frame driver, shared by the CPU step (step.h) and the GPU backend (gpu/solver): the
 * schedule of a frame (def.substeps, or the fixed-substep accumulator), the pins' motion over
 * it, the retries, the stats and sleeping, identical for both. A backend supplies, through
 * wc_step_ops, its substep (which runs the state's arrays wherever it keeps them and is judged by
 * step_judge.h), save/restore of a substep's start, the end-of-frame measures and the velocity
 * reset of falling asleep.
 *
 * Retries. A failed substep is rolled back and retried with half the step (up to max_halvings
 * times: 2, 4, 8 pieces), then with the last-resort solver (the CPU's direct one) and the
 * compressed springs' geometric term dropped (a positive-definite system): in the finest pieces
 * (judged on all but the energy gain), then in one piece accepted whenever it is finite; if that
 * also fails the state is left as it was before the substep and the frame reports
 * WC_ERROR_STEP_FAILED. Positions are never left non-finite.
 *
 * Sleeping (state.h has the wake rules). A frame first compares def.gravity and def.air with the
 * previous frame's (a change wakes the cloth). A sleeping cloth's frame then only advances time
 * (as the substeps would have: the fixed-substep accumulator included) and frame, and reports
 * stats.asleep with zero substeps and iterations, zero kinetic energy and the strain of the
 * sleeping positions; positions stay bit-identical, velocities zero; it allocates nothing and
 * costs O(1) (O(substeps) additions of the time). After a successful active frame, the rest
 * timer grows by dt when the fastest particle is slower than def.sleep_speed (else restarts at
 * 0); when it reaches def.sleep_time the velocities are zeroed and the cloth sleeps from the
 * next frame on (stats.fell_asleep). A failed frame restarts the timer. */
#ifndef WEFT_CORE_STEP_DRIVER_H
#define WEFT_CORE_STEP_DRIVER_H
#include "state.h"
#include "step_judge.h"
#include "step_stats.h"

typedef struct wc_step_ops {
    void* user;
    /* One try of a substep of length h ending at frame fraction alpha1 with `solver`, judged as
     * `judge`; non-OK discards it (the driver then calls restore). Positions and velocities of s
     * need not be kept current by a backend that holds them elsewhere. */
    wc_status (*substep)(void* user, wc_state* s, double h, double alpha1, wc_solver_type solver, int judge,
                           double pin_energy, wc_step_stats* st, wc_diag* diag);
    void (*save)(void* user, wc_state* s);      /* remember the substep's start */
    void (*restore)(void* user, wc_state* s);   /* go back to it */
    /* At the end of an active frame: largest particle speed, kinetic energy, largest stretch strain. */
    void (*measure)(void* user, const wc_state* s, double* max_speed, double* kinetic, double* max_strain);
    /* Falling asleep: the driver zeroes s->v; a backend holding velocities elsewhere zeroes them
     * there too (NULL: nothing more). */
    void (*sleep)(void* user, wc_state* s);
    wc_solver_type last_resort_solver;          /* CPU: DIRECT */
} wc_step_ops;

/* Simulate dt seconds (> 0, finite, at most 1000) with the backend's ops. stats may be NULL. */
wc_status wc_step_frame_ops(wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag, const wc_step_ops* ops);

#endif
