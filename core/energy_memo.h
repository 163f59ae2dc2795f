/* The energy judge's memo: the total energy (kinetic + springs + gravity's potential, the measure
 * of wc_state_total_energy) of the last state the step measured, keyed on that state itself.
 *
 * A substep measures its state's total energy up to four times (its start, Newton's energy cap
 * after the pins and contacts, Newton's guard at the accepted iterate, its end), and on a cloth
 * the pins hold still and nothing projects, most of them measure a state measured just before
 * (the previous substep's end is this one's start; the guard's iterate is the end when the pins'
 * snap, the strain limit and the projections move nothing). The memo keeps copies of the
 * measured x and v and the gravity and seam scale of the measure; a measure of the same bits
 * returns the stored energy (the same function of the same inputs: the same bits), anything
 * else measures afresh and replaces it. The model (masses, springs, stiffness) is fixed for a
 * state's life. wc_state.judge_fresh (tests) bypasses it. */
#ifndef WC_ENERGY_MEMO_H
#define WC_ENERGY_MEMO_H

#include "model.h"

struct wc_state;

typedef struct wc_energy_memo {
    int valid;
    double total, elastic;     /* J: the stored measure (elastic: kinetic + springs) */
    double gravity[3], seam_scale;
    double *x, *v;             /* (n x 3) the measured state's copies */
    long hits, misses;         /* measures taken over / made (tests, bench) */
} wc_energy_memo;

/* Total energy of (x, v) under gravity g with seam scale seam_scale, summed as
 * wc_state_total_energy sums it; *elastic (may be NULL) receives kinetic + springs. */
double wc_total_energy_xv(const wc_model* m, const double* x, const double* v, const double g[3], double seam_scale,
                          double* elastic);

/* The total energy of (x, v) (s's gravity and seam scale): the memo's when it holds these bits,
 * else measured and stored. x, v: s->x, s->v or any (n x 3) state (Newton's iterate). */
double wc_state_judge_energy(struct wc_state* s, const double* x, const double* v, double* elastic);

#endif
