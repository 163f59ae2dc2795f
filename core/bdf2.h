/* The time integrator of one substep: backward Euler, or BDF2 (Choi & Ko 2002) with its history.
 *
 * BDF2 with step h, history x_{n-1}, v_{n-1} of the previous substep (same h):
 *   x_{n+1} = 4/3 x_n - 1/3 x_{n-1} + 2/3 h v_{n+1}
 *   v_{n+1} = 4/3 v_n - 1/3 v_{n-1} + 2/3 h M^-1 f(x_{n+1}, v_{n+1})
 * With he = 2h/3, xb = 4/3 x_n - 1/3 x_{n-1}, mom = (v_n - v_{n-1}) / 3 and dv = v_{n+1} - v_n this is
 * backward Euler's system with h -> he, the positions advanced from xb instead of x_n and M mom
 * added to the momentum:
 *   x_{n+1} = xb + he (v_n + dv),   M (dv - mom) = he f(x_{n+1}, v_{n+1}).
 * Linearised at x_n as Baraff & Witkin do (f ~ f0 + K (x_{n+1} - x_n) + D dv):
 *   (M - he D - he^2 K) dv = he (f0 + he K vstar) + M mom,   vstar = v_n + (xb - x_n) / he
 * so the assembly is backward Euler's (assemble.h) with he and vstar for h and v. Backward Euler is
 * the same with he = h, xb = x_n, vstar = v_n, mom = 0 (and takes exactly the old code path).
 *
 * History rules. A substep is BDF2 when def.integrator is BDF2, the history is valid and its
 * length hist_h equals this substep's h exactly; otherwise it is one backward-Euler step (fixed-
 * step BDF2: a halved retry, a frame of another length, the first substep all fall back once).
 * Every substep of a BDF2 cloth that gets past its contact correction moves the history on
 * (x_prev = x_n after the correction, v_prev = v_n, hist_h = h); the step's save/restore keeps it
 * with the substep's start, so a rolled-back try leaves it as it was. It is invalidated by
 * wc_state_set_positions, falling asleep (wc_state_set_sleep, the rest timer), and by the plugin's
 * RESET and TELEPORT; the plugin's inertia carry transforms it with x and v (cloth_frame.c); a
 * snapshot holds it (plugin/snapshot.c).
 * Contacts: the position correction of wc_contacts_begin moves x_n by c; x_{n-1} is taken moved
 * by the same c (xb = x_n + (x_n^uncorrected - x_prev) / 3), so a correction is not extrapolated
 * into a velocity. Pins: z and the final snap put x_{n+1} = xb + he v_{n+1} on the target.
 * Friction and strain limiting see he as the step of the velocity update. */
#ifndef WEFT_CORE_BDF2_H
#define WEFT_CORE_BDF2_H
#include "state.h"

typedef struct wc_integ {
    int bdf2;               /* 1: this substep is a BDF2 step; 0: backward Euler */
    double h;               /* s: substep length */
    double he;              /* s: effective step of the system: h (BE), 2h/3 (BDF2) */
    const double* xb;       /* (n x 3) m: x_{n+1} = xb + he v_{n+1} (BE: s->x) */
    const double* vstar;    /* (n x 3) m/s: velocity of the assembly's he K v term (BE: s->v) */
    const double* mom;      /* (n x 3) m/s: M mom is added to b; NULL for BE */
} wc_integ;

/* Start of a substep of length h, before pins and contacts: BE or BDF2 (rules above); a BDF2
 * cloth's positions are kept in s->xs. */
void wc_integ_begin(wc_state* s, double h, wc_integ* ig);
/* Base position xb of particle i before the contact correction (pins). */
void wc_integ_base(const wc_state* s, const wc_integ* ig, int i, double* out);
/* After the contact correction: xb, vstar, mom; a BDF2 cloth's history moves on. */
void wc_integ_prepare(wc_state* s, wc_integ* ig);
/* The history into / back from the substep's start copy (no-ops for a BE cloth). */
void wc_integ_save(wc_state* s);
void wc_integ_restore(wc_state* s);

#endif
