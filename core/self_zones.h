/* Impact zones of self-collision (self_collide.h, stage 4): a zone's rigid motion, and the
 * stretch springs it stretched relaxed by moving the particles outside the zones. A zone's
 * rigid motion keeps the springs inside it at their start length but stretches those that cross
 * its boundary when the solve moved their outer end away: a zone that holds a particle at every
 * substep (layers pressed together) would stretch its springs a little more each substep, up to
 * tearing. Relaxing them (Provot's strain limit, Gauss-Seidel) by moving only particles outside
 * the zones lets the cloth around a zone follow it instead of tearing from it; taking the
 * stretched spring's other end into the zone instead freezes the cloth (one zone ends up
 * holding a whole garment). Both allocate nothing. */
#ifndef WEFT_CORE_SELF_ZONES_H
#define WEFT_CORE_SELF_ZONES_H
#include <stdint.h>

#include "model.h"

#define WC_SELF_ZONE_STRIDE 20  /* doubles per zone accumulator */

/* For tests: replace the displacements d = x - x_start of the particles of each zone (parent, n:
 * union-find roots; only particles with in[i] != 0) by the zone's rigid motion (mass m, inverse
 * mass inv_m 0 = pinned): its centre of mass moves by the zone's mean displacement (linear
 * momentum kept exactly), and it turns about it by the angle and axis omega = I^-1 L of its
 * angular momentum over the start positions (kept to first order in the angle), an exact
 * rotation, so distances inside a zone keep their start length. acc: (n x WC_SELF_ZONE_STRIDE)
 * scratch. */
void wc_self_rigidify(int n, const double* x_start, double* x, const double* mass, const double* inv_m, int* parent,
                      const unsigned char* in, double* acc);

/* After wc_self_rigidify: shortens every stretch spring longer than rest x (1 + the larger of
 * floor and its strain at x_old, the positions before the zones) by moving its ends outside the
 * zones (in[] 0) in proportion to their inverse masses inv_m (0: pinned, never moved), up to
 * passes Gauss-Seidel passes in spring order (deterministic), stopping at a pass that moves
 * nothing; moved (may be NULL) gets 1 for each particle moved. Returns the corrections made. */
int wc_self_relax_zones(const wc_model* m, const double* x_old, double* x, const unsigned char* in,
                        const double* inv_m, double floor, int passes, unsigned char* moved);

/* The springs the relaxation's next pass must check (wc_self_relax_zones_due): bit s - start of
 * due for the stretch spring s. A spring whose ends have not moved since a check that corrected
 * nothing would correct nothing again (the check reads only its ends' positions, and x_old, in and
 * inv_m, which the caller keeps), so a pass that checks only the due springs, in spring order,
 * makes the same corrections, in the same order, as a pass over every spring. */
typedef struct wc_self_relax_set {
    uint64_t* due;  /* (words) the springs to check; left holding those the next call's first pass
                       must check (the last pass's corrected springs' neighbourhoods) */
    uint64_t* next; /* (words) scratch, all 0 between calls */
    int words;      /* (stretch springs + 63) / 64 */
} wc_self_relax_set;

/* Marks the stretch springs at particle i due (m's pattern: its per-row spring lists). */
void wc_self_relax_mark(const wc_model* m, const wc_self_relax_set* rs, int i);

/* wc_self_relax_zones over the due springs of rs only (the caller marks every spring whose ends
 * or their in[] changed since the last call, or all of them at a first call): the same
 * corrections, positions and moved[] bit for bit. Needs m's pattern (row_spring_start). */
int wc_self_relax_zones_due(const wc_model* m, const double* x_old, double* x, const unsigned char* in,
                            const double* inv_m, double floor, int passes, unsigned char* moved,
                            wc_self_relax_set* rs);

#endif
