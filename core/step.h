/* Advancing a state by one frame: substeps of backward Euler or BDF2 (bdf2.h) (forces -> assembly
 * -> constraints -> solve, with Newton iterations and a line search when def asks (newton.h) ->
 * contacts -> positions -> strain limit), each checked for failure: non-finite values, strain
 * above fail_strain, kinetic-energy blow-up, total energy rising with nothing to supply it (the
 * colliders' and self-collision's position corrections are collision responses that do work on
 * the cloth, and their energy is not charged to the step). A failed substep is rolled back and
 * retried with half the step (up to max_halvings times: 2, 4, 8 pieces), then with the direct
 * solver and the compressed springs' geometric term dropped (a positive-definite system): in the
 * finest pieces (judged on all but the energy gain), then in one piece accepted whenever it is
 * finite; if that also fails the state is left as it was before the substep and the frame
 * reports WC_ERROR_STEP_FAILED. Positions are never left non-finite.
 *
 * TR-BDF2's energy (bdf2.h): each stage is judged as a substep of its own length (finite,
 * strain, kinetic blow-up), but the total-energy gain is judged once, at the end of stage 2,
 * from the substep's start (the collision responses of both stages left out): stage 1, the
 * trapezoidal rule, does not dissipate, and where a swing passes its lowest point it may end
 * above the substep's start by more than the allowance while the composite step does not
 * (tests/test_sample_rollbacks.c). A substep gaining energy as a whole is still rolled back. The
 * Newton energy guard (newton.h) runs in stage 2 against that bound, in stage 1 against stage
 * 1's own, but stage 1 is not rolled back for it.
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
#ifndef WEFT_CORE_STEP_H
#define WEFT_CORE_STEP_H
#include "state.h"
#include "step_stats.h"

/* For tests and benchmarks: build the constrained system of a substep of length h ending at
 * frame fraction alpha1 (pins and contacts into s->filter, then s->A and s->b), exactly as the
 * step does before it solves. Contacts may move particles out of colliders. */
void wc_substep_prepare(wc_state* s, double h, double alpha1, wc_step_stats* st);

/* Simulate dt seconds (> 0, finite). stats may be NULL. */
wc_status wc_step_frame(wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag);

/* ---- the frame driver, shared with the GPU backend (gpu/solver) ------------------------------
 * wc_step_frame is wc_step_frame_ops with the CPU's operations. Another backend supplies its own
 * substep (which runs the state's arrays wherever it keeps them), save/restore of a substep's
 * start, the end-of-frame measures and the velocity reset of falling asleep; the schedule
 * (substeps or fixed-substep accumulator), the pins' interpolation, the retries (halvings, last
 * resorts), the judging of a substep, the stats and sleeping stay here, identical for both. */

/* How far a substep's result is judged. */
enum {
    WC_JUDGE_ALL = 0,      /* finite, strain, kinetic-energy blow-up, total-energy gain */
    WC_JUDGE_NO_GAIN = 1,  /* the first last resort: all but the total-energy gain */
    WC_JUDGE_FINITE = 2    /* the final last resort: finite values only (nothing else is left) */
};

/* What the judge needs of a substep's start (before) and end (after). */
typedef struct wc_substep_measure {
    int finite;                 /* after: every position and velocity finite */
    double kinetic;             /* J */
    double total;               /* J, wc_state_total_energy (only when the energy gain is judged) */
    double elastic;             /* before: kinetic + springs (J) */
    double strain;              /* after: largest stretch strain */
} wc_substep_measure;

/* 1 when a substep judged as `judge` also judges the total-energy gain (nothing in the frame can
 * supply energy and def.fail_energy_gain > 0). */
int wc_substep_judges_energy(const wc_state* s, int judge, double pin_energy);
/* The step's verdict on a substep (step.h's checks, in that order); non-OK with the message in
 * diag when it must be discarded. */
wc_status wc_substep_judge(const wc_state* s, const wc_substep_measure* before, const wc_substep_measure* after,
                             int judge, int judge_energy, double pin_energy, double h, const char* solver,
                             wc_diag* diag);

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

wc_status wc_step_frame_ops(wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag, const wc_step_ops* ops);

#endif
