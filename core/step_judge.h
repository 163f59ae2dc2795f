/* The verdict on a substep: kept, or discarded to be rolled back (step_driver.h). Its checks, in
 * order: non-finite positions or velocities, strain above def.fail_strain, kinetic-energy
 * blow-up, total energy rising with nothing to supply it. The colliders' and self-collision's
 * position corrections are collision responses that do work on the cloth: a substep leaves
 * their energy out of the total it hands the judge, so it is not charged to the step. Shared by
 * the CPU substep (step.c) and the GPU backend's (gpu/solver).
 *
 * TR-BDF2's energy (bdf2.h): each stage is judged as a substep of its own length (finite,
 * strain, kinetic blow-up), but the total-energy gain is judged once, at the end of stage 2,
 * from the substep's start (the collision responses of both stages left out): stage 1, the
 * trapezoidal rule, does not dissipate, and where a swing passes its lowest point it may end
 * above the substep's start by more than the allowance while the composite step does not
 * (tests/test_sample_rollbacks.c). A substep gaining energy as a whole is still rolled back. The
 * Newton energy guard (newton.h) runs in stage 2 against that bound, in stage 1 against stage
 * 1's own, but stage 1 is not rolled back for it. */
#ifndef WEFT_CORE_STEP_JUDGE_H
#define WEFT_CORE_STEP_JUDGE_H
#include "state.h"

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
/* The energy gain the judge allows a substep (J): def.fail_energy_gain x (M |g| D + the kinetic
 * and spring energy at its start, before->elastic), D the rest shape's bounding-box diagonal. */
double wc_substep_energy_allowance(const wc_state* s, const wc_substep_measure* before);
/* The verdict on a substep (the checks above, in that order); non-OK with the message in diag
 * when it must be discarded. */
wc_status wc_substep_judge(const wc_state* s, const wc_substep_measure* before, const wc_substep_measure* after,
                             int judge, int judge_energy, double pin_energy, double h, const char* solver,
                             wc_diag* diag);

#endif
