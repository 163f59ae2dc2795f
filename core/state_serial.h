/* The state's part of a snapshot (serial.h): what a wc_state carries from one frame to the next,
 * in two pieces the snapshot format puts apart (the cloth's transform history sits between them).
 * Reading sets what derives from the fields read (the solver's rho cache, the sleep state). */
#ifndef WEFT_CORE_STATE_SERIAL_H
#define WEFT_CORE_STATE_SERIAL_H
#include "serial.h"
#include "state.h"

/* Clocks (time, accumulator, frame), x, v, dv, the pins (particle, target, free axis) and their
 * start-of-frame targets, the colliders' world geometry and velocity, the contacts (collider,
 * normal, released, active) and the air's wind. x, v, dv and the contact arrays are left out
 * with k->skip_mirror. A reader must hold as many pins and colliders as the state has now. */
void wc_state_serial(wc_state* s, wc_serial* k);
/* What earlier frames left: the solver's Chebyshev rho cache (valid, rho), the sleep state
 * (asleep, rest timer; read after the wind, since the cloth sleeps with it) and BDF2's history
 * (valid, h, x_prev, v_prev; the arrays always present, left out with k->skip_mirror). */
void wc_state_serial_history(wc_state* s, wc_serial* k);

#endif
