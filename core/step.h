/* Advancing a state by one frame on the CPU: the frame driver (step_driver.h: schedule, retries,
 * stats, sleeping) with the CPU's substep. A substep of backward Euler, BDF2 or TR-BDF2's two
 * stages (bdf2.h): pins and contacts into the filter -> forces -> assembly -> friction -> solve,
 * with Newton iterations and a line search when def asks (newton.h) -> contacts' release ->
 * positions -> strain limit -> the colliders' projection -> self-collision, then judged
 * (step_judge.h, with "TR-BDF2's energy"); a substep that fails is rolled back by the driver. */
#ifndef WEFT_CORE_STEP_H
#define WEFT_CORE_STEP_H
#include "state.h"
#include "step_driver.h"
#include "step_stats.h"

/* For tests and benchmarks: build the constrained system of a substep of length h ending at
 * frame fraction alpha1 (pins and contacts into s->filter, then s->A and s->b), exactly as the
 * step does before it solves. Contacts may move particles out of colliders. */
void wc_substep_prepare(wc_state* s, double h, double alpha1, wc_step_stats* st);

/* Simulate dt seconds (> 0, finite). stats may be NULL. */
wc_status wc_step_frame(wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag);

#endif
