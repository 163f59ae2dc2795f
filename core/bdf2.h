/* The time integrator of one substep: backward Euler, BDF2 (Choi & Ko 2002) with its history, or
 * TR-BDF2 (two stages, no history; at the end of this comment).
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
 * wc_state_set_positions, falling asleep (wc_state_set_sleep, the rest timer), and by the cloth's
 * RESET and TELEPORT; the cloth's inertia carry transforms it with x and v (cloth_cpu.c); a
 * snapshot holds it (cloth_snapshot.c).
 * Contacts: the position correction of wc_contacts_begin moves x_n by c; x_{n-1} is taken moved
 * by the same c (xb = x_n + (x_n^uncorrected - x_prev) / 3), so a correction is not extrapolated
 * into a velocity. Pins: z and the final snap put x_{n+1} = xb + he v_{n+1} on the target.
 * Friction and strain limiting see he as the step of the velocity update.
 *
 * TR-BDF2 (Bank et al. 1985; Hosea & Shampine 1996), gamma = 2 - sqrt(2): a substep of length h is
 * two stages, each a backward-Euler-like solve of the same form x_new = xb + he v_new,
 * M (dv - mom) = he f(x_new, v_new), dv = v_new - v_start (so the assembly, Newton, PCG, pins,
 * contacts, friction and strain limiting are the ones above, with these coefficients):
 *   stage 1, trapezoidal rule from t_n to t_g = t_n + gamma h (length gamma h):
 *     he = gamma h / 2, xb = x_n + he v_n, mom = he M^-1 f(x_n, v_n), vstar = 2 v_n
 *   stage 2, BDF2 through t_n, t_g, t_n + h (length (1 - gamma) h):
 *     he = (1 - gamma) / (2 - gamma) h  (= gamma h / 2: both stages have the same matrix form),
 *     c2 = (1 - gamma)^2 / (gamma (2 - gamma)),  xb = x_g + c2 (x_g - x_n),  mom = c2 (v_g - v_n)
 * L-stable and second order; one-step: nothing is carried from one substep to the next, so
 * teleports, resets, sleep and snapshots need nothing new (hist_valid stays 0). Each stage is
 * prepared, solved, advanced, strain-limited, projected and judged as a substep of its own length
 * (pins and colliders interpolated to its end, contacts filtered per stage), except for the
 * total-energy gain, judged over the whole substep at stage 2's end (step.h "TR-BDF2's energy");
 * a failed stage rolls the whole substep back (robust_substep). Stage 1's corrected start x_n,
 * v_n are kept in x_prev, v_prev (unused by a TR-BDF2 cloth otherwise), and stage 1's x_g as its
 * solve gave it (x = xb + he v, pins snapped) in xs (wc_integ_solved): the position corrections
 * that follow a solve (strain limiting, the colliders' projection, the self-collision stage) and stage 2's
 * contact correction move x_g but do not enter c2 (x_g - x_n), so a push out of a collider or
 * another layer is not extrapolated into stage 2's motion (as BDF2's contact correction moves
 * x_n with x_g). The velocities' corrections do enter mom = c2 (v_g - v_n) (docs/design/solver.md
 * has the alternatives measured). f(x_n, v_n) is the assembly's f0 (springs with damping,
 * gravity, air); a particle of zero mass gets mom = 0.
 * Contacts (TR-BDF2; wc_integ_contacts). Begin prescribes backward Euler's landing: the normal
 * velocity vc.n - gap / h (gap: what is left between the particle and the shell after the push
 * out, closed over the stage) that puts x_n + h v_new on the shell. In the xb form that is wrong:
 * the trapezoidal stage's x_g = x_n + he (v_n + v_g) carried the approach speed he v_n.n into the
 * collider, the projection put the particle back, and stage 2 extrapolated the solved motion into
 * it again (c2 (x_g - x_n)); a prescribed end velocity that lands exactly instead (2 vc.n - v_n.n
 * - gap / he) reflects the particle: the trapezoidal rule keeps energy, contacts must not. So for
 * each particle in contact with a collider: its normal velocity relative to the collider is set to
 * 0 at the stage's start (the inelastic impact; inside the energy judge's collision window, as
 * begin's push out), xb's normal part to x.n + (h - he) vc.n - gap and z's to 0, so that
 * x_new = xb + he v_new with v_new.n = vc.n lands on the shell as it is at the stage's end and the
 * particle leaves the stage at the collider's normal velocity; vstar = v + (xb - x) / he, mom and
 * (stage 1) v_prev follow the new v. The tangential motion is the stage's own; friction's
 * prediction includes the stage's momentum (collide.h wc_contacts_friction's mom). BDF2's contacts
 * keep backward Euler's landing.
 * Air drag: BE and BDF2 take it explicitly (the force at the substep's start, a first-order
 * term). TR-BDF2 makes it implicit in velocity with the geometry of the stage's start,
 * f_air(v_new) ~ f_air(v_start) - L dv with L the row-sum (lumped) drag Jacobian per particle
 * (forces.h wc_air_lumped): A += he L; Newton's potential gains he/2 w^T L w (newton.h); Newton's
 * further iterations refresh the geometry and the force to the iterate (newton.h "Refreshed"). Exact
 * for a velocity change shared by a triangle's vertices (the swing); without it, explicit drag
 * over-damps by (r h)^2 / 2 per step (r = drag / mass, 3.3 1/s for the default cloth). */
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
    int stage;              /* TR-BDF2: 1 (trapezoidal) or 2 (BDF2 stage); 0 for BE and BDF2 */
    int xb_form;            /* 1: x_{n+1} = xb + he v_{n+1} with xb in s->xb (BDF2, TR-BDF2) */
    int air_implicit;       /* 1: air drag implicit through s->air_lump (TR-BDF2 with air) */
} wc_integ;

#define WC_TRBDF2_GAMMA 0.58578643762690485   /* 2 - sqrt(2) */
#define WC_TRBDF2_C2 0.20710678118654752      /* (1 - gamma)^2 / (gamma (2 - gamma)) = (sqrt(2) - 1) / 2 */

/* The coefficients of a substep of length h (TR-BDF2: of its stage `stage`, 1 or 2; ignored for
 * the others) without touching the state's arrays: bdf2, h, he, stage, xb_form, air_implicit, and
 * the pointers as wc_integ_begin leaves them (a BDF2 step's xb, vstar, mom are set by
 * wc_integ_prepare: they are in use where bdf2 or stage is set). The GPU backend takes its
 * coefficients from here. */
void wc_integ_coefficients(const wc_state* s, double h, int stage, wc_integ* ig);

/* Start of a substep of length h, before pins and contacts: BE or BDF2 (rules above); a BDF2
 * cloth's positions are kept in s->xs. A TR-BDF2 cloth: the start of the substep's stage 1. */
void wc_integ_begin(wc_state* s, double h, wc_integ* ig);
/* After a stage's positions are solved (x = xb + he v, pins snapped), before the corrections that
 * follow them (strain limiting, the colliders' projection, self-collision): TR-BDF2's stage 1
 * keeps x in s->xs as stage 2's x_g, so that those corrections are not extrapolated into stage
 * 2's motion (above); nothing for the others. */
void wc_integ_solved(wc_state* s, const wc_integ* ig);
/* TR-BDF2: the start of stage 2 of the substep of length h (after stage 1 advanced x, v). */
void wc_integ_begin_stage2(wc_state* s, double h, wc_integ* ig);
/* After the assembly (s->f = f0 at the stage's start): TR-BDF2 stage 1's mom = he M^-1 f0, and
 * with air_implicit the drag blocks he L_i (s->air_lump at the stage's start x) added to A's
 * diagonal; nothing for the others. */
void wc_integ_forces(wc_state* s, const wc_integ* ig);
/* Base position xb of particle i before the contact correction (pins). */
void wc_integ_base(const wc_state* s, const wc_integ* ig, int i, double* out);
/* After the contact correction: xb, vstar, mom; a BDF2 cloth's history moves on. */
void wc_integ_prepare(wc_state* s, wc_integ* ig);
/* TR-BDF2, after wc_contacts_begin and wc_integ_prepare: the collider contacts of the stage in the
 * xb form (above, "Contacts"): v, xb, vstar, mom, v_prev (stage 1) and the filter's z of each
 * particle in contact. Nothing for backward Euler, BDF2 or a particle without contact. */
void wc_integ_contacts(wc_state* s, const wc_integ* ig);
/* TR-BDF2's contact release, after a stage's solve with contacts (s->r = A dv - b): returns 1 when
 * wc_contacts_end is to release contacts on s->r now. Stage 1 keeps its particles' impulses and
 * returns 0: its contacts are held into stage 2; stage 2 adds them to its own s->r, so a contact is
 * released on the substep's impulse. The trapezoidal stage does not damp a stiff mode: the
 * constraint force of a particle resting on a collider under a ringing neighbour flips sign from
 * stage to stage, and released on one stage's pull it fell into the collider in the next (free,
 * d = 0 is not re-caught after a release), the projection pushing it back out with spring energy
 * that kept the cloth from ever coming to rest (docs/design/solver.md). Backward Euler and BDF2:
 * returns 1. */
int wc_integ_contact_impulses(wc_state* s, const wc_integ* ig);
/* The history into / back from the substep's start copy (no-ops for a BE cloth). */
void wc_integ_save(wc_state* s);
void wc_integ_restore(wc_state* s);

#endif
