/* Coulomb friction of the contacts of a substep (collide.h's steps 2 and 3), decided per particle
 * by the impulse law of the particle alone and applied through the implicit system: a contact
 * that sticks gets its tangential DOF constrained too (S = 0, it moves with its collider); one
 * that slides gets kinetic friction as an implicit damping (A and b). collide_friction.c has the
 * rules.
 *
 * Why friction lives in the system: applied after the solve as a velocity change, a stuck
 * particle loses only its own momentum (m |v_t|, tiny), while the springs that pulled it along
 * in the solve, relaxed there by moving it, never pull back on the rest of the cloth: a cloth
 * hanging from one stuck particle then stretches without bound (the stuck particle "holds" far
 * more spring force than its Coulomb bound; docs/design/contacts.md). As a constraint of the
 * solve the holding force reaches the neighbours, and the stick is judged on the real forces. */
#ifndef WEFT_CORE_COLLIDE_FRICTION_H
#define WEFT_CORE_COLLIDE_FRICTION_H
#include "collide.h"

/* Step 2, after wc_assemble, for the particles begin put in contact: v (n x 3) the velocities at
 * the start of the substep, mass (n), f (n x 3) the forces of the substep (wc_assemble's f_total),
 * A / diag / b the assembled system (BSR values, index of each row's diagonal block, right-hand
 * side), filter the constraints begin wrote. Coulomb friction, decided per particle
 * (collide_friction.c has the rules): it sticks when the constraint impulse it needs to end the
 * substep without slip is within mu times its normal impulse, predicted alone (m (z - u) - h f)
 * and held by its springs (A_ii (z - u) - b_i): S = 0, z -= u, ndof 3, ct->stick; otherwise it
 * slides with friction as the implicit damping force -c S (v_new - vc) (A_ii += h c S,
 * b_i -= h c u) sized so that the particle alone gets exactly Coulomb's impulse (never a reversed
 * slip). A stuck particle moves with its collider. mom (n x 3, m/s; NULL for none): the integrator's
 * momentum term, M mom on the right-hand side besides h f (TR-BDF2's stages, bdf2.h: in the
 * trapezoidal stage M mom = h f_n, the explicit half of the force), so the particle alone is
 * predicted as m (z - u - mom) - h f. Returns the number of sticking particles. */
int wc_contacts_friction(wc_contacts* ct, const wc_collider* c, int nc, const double* v, const double* mass,
                         const double* f, const double* mom, double h, wc_filter* filter, double* A,
                         const int* diag, double* b, wc_par* par);
/* Step 3b, after a solve, r = A dv - b (n x 3): the particle alone was only a prediction. A
 * sticking particle whose holding impulse in the solved cloth (r_i in its free directions)
 * exceeds mu times its normal impulses (r_i on the normals) slides instead, as in step 2 with
 * q = r_i. The caller solves again while this changes something (the stuck set only shrinks).
 * Returns the number changed. */
int wc_contacts_friction_recheck(wc_contacts* ct, const wc_collider* c, int nc, const double* v,
                                 const double* mass, const double* r, wc_filter* filter, double* A, const int* diag,
                                 double* b, wc_par* par);

#endif
