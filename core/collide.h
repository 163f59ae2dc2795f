/* Colliders (plane, sphere, capsule; each with a thickness and Coulomb friction) and the contact
 * handling of a substep, through the constraint filter (Baraff & Witkin section 5):
 *   1. wc_contacts_begin    before the forces: find contacts, push particles out to the thickness
 *                           shell (position correction), constrain the normal direction
 *                           (S = I - n n^T; two contacts: 2 DOF; z cancels the relative normal
 *                           velocity).
 *   2. wc_contacts_friction after the assembly: Coulomb friction, decided per particle by the
 *                           impulse law of the particle alone and applied through the implicit
 *                           system: a contact that sticks gets its tangential DOF constrained too
 *                           (S = 0, it moves with its collider); one that slides gets kinetic
 *                           friction as an implicit damping (A and b).
 *   3. (solve; then wc_contacts_friction_recheck: sticks the solved cloth overloads slide, and
 *      the system is solved again)
 *   4. wc_contacts_end      after the solve: the constraint force (A dv - b)_i / h along n of each
 *                           contact; a contact whose force pulls the particle towards the
 *                           collider is released for the next substep.
 *   5. wc_contacts_project  after positions are advanced: any particle still inside a collider's
 *                           shell is moved to it and its inward relative normal velocity removed.
 * Pinned particles (filter ndof 3, not from a sticking contact) are never touched.
 *
 * Why friction lives in the system: applied after the solve as a velocity change (as it once
 * was), a stuck particle loses only its own momentum (m |v_t|, tiny), while the springs that
 * pulled it along in the solve, relaxed there by moving it, never pull back on the rest of the
 * cloth: a cloth hanging from one stuck particle then stretches without bound (in the report
 * that found it, the stuck particle "held" 420-1400 N of spring force against a Coulomb bound of
 * 10-60 N, 2.6 N being the whole cloth's weight). As a constraint of the solve the holding force
 * reaches the neighbours, and the stick is judged on the real forces. */
#ifndef WEFT_CORE_COLLIDE_H
#define WEFT_CORE_COLLIDE_H
#include "filter.h"
#include "par.h"

typedef enum wc_collider_type {
    WC_COLLIDER_PLANE = 0,     /* {x : normal.x = offset}; free side normal.x > offset */
    WC_COLLIDER_SPHERE = 1,    /* center, radius */
    WC_COLLIDER_CAPSULE = 2,   /* segment a-b, radius */
    WC_COLLIDER_MESH = 3       /* a triangle mesh (mesh_collider.h; its own thickness and friction
                                  are copied here): built by the step, never set by a caller */
} wc_collider_type;

struct wc_mesh_collider;

typedef struct wc_collider {
    int type;                  /* wc_collider_type */
    double normal[3];          /* plane: unit normal */
    double offset;             /* plane: m */
    double center[3];          /* sphere: m */
    double a[3], b[3];         /* capsule: segment end points (m) */
    double radius;             /* sphere, capsule: m, >= 0 */
    double thickness;          /* m, >= 0: the cloth stays this far outside the surface */
    double friction;           /* Coulomb coefficient (static = kinetic), >= 0 */
    double velocity[3];        /* m/s: rigid translation velocity of the collider this substep
                                  (mesh: unused, the velocity is per point) */
    double push_speed;         /* m/s, >= 0: a particle found inside the shell is moved out by at
                                  most push_speed x h per substep (begin's and project's
                                  corrections together; collide.c); 0: at once */
    const struct wc_mesh_collider* mesh; /* mesh: the collider (borrowed), else NULL */
} wc_collider;

/* Signed distance from p to the collider's surface (negative inside; thickness not included) and
 * the outward unit normal at the closest surface point. A mesh: at its substep end positions. */
double wc_collider_distance(const wc_collider* c, const double* p, double* normal);

/* Persistent per-particle contact state (lives in wc_state). */
typedef struct wc_contacts {
    int n;                     /* particles */
    int* collider;             /* (n x 2) colliders in contact, -1 for none */
    double* normal;            /* (n x 6) their normals */
    unsigned char* released;   /* (n) a contact was released last substep: not re-constrained
                                  while the particle is outside the shell */
    unsigned char* stick;      /* (n) this substep, from wc_contacts_friction: 1 when the contact
                                  sticks (filter ndof 3); not state: begin clears it */
    int active;                /* number of particles with at least one contact */
    double* vel;               /* (n x 6) velocity of each contact's collider surface at the contact
                                  point (m/s; a mesh's is per point), written by begin and read by
                                  friction; not state. NULL: each collider's rigid velocity */
    double* pushed;            /* (n) m: how far begin's position correction moved each particle
                                  this substep (project's share of a push_speed cap is the rest);
                                  not state. NULL: no cap applies */
    double h;                  /* s: the substep begin ran for (the caps' length) */
} wc_contacts;

/* Step 1. x is corrected in place; f gets the contact constraints of non-pinned particles.
 * On entry f must hold the step's pins only (free elsewhere): particles with ndof 2 (line pins)
 * or 3 get no contact, ndof 0 or 1 are (re)written. Returns the particles in contact (also
 * ct->active); a particle approaching the shell within this substep is prescribed the normal
 * velocity that lands it on the shell at the end of the substep (see collide.c). */
int wc_contacts_begin(wc_contacts* ct, const wc_collider* c, int nc, double* x, const double* v, double h,
                      wc_filter* f, wc_par* par);
/* Step 2, after wc_assemble, for the particles begin put in contact: v (n x 3) the velocities at
 * the start of the substep, mass (n), f (n x 3) the forces of the substep (wc_assemble's
 * f_total), A / diag / b the assembled system (BSR values, index of each row's diagonal block,
 * right-hand side), filter the constraints begin wrote. Coulomb friction, decided per particle
 * (collide.c has the rules): it sticks when the constraint impulse it needs to end the substep
 * without slip is within mu times its normal impulse, predicted alone (m (z - u) - h f) and
 * held by its springs (A_ii (z - u) - b_i): S = 0, z -= u, ndof 3, ct->stick; otherwise it slides
 * with friction as the implicit damping force -c S (v_new - vc) (A_ii += h c S, b_i -= h c u)
 * sized so that the particle alone gets exactly Coulomb's impulse (never a reversed slip). A
 * stuck particle moves with its collider. mom (n x 3, m/s; NULL for none): the integrator's
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
int wc_contacts_friction_recheck(wc_contacts* ct, const wc_collider* c, int nc, const double* v, const double* mass,
                                 const double* r, wc_filter* filter, double* A, const int* diag, double* b,
                                 wc_par* par);
/* Step 4. r = A dv - b (n x 3) for the solved system, nc the colliders: releases contacts whose
 * normal impulse is negative. */
void wc_contacts_end(wc_contacts* ct, int nc, const double* r, wc_par* par);
/* Step 5. Every particle but the pinned ones (ndof 3 without ct->stick; f may be NULL). Returns
 * the number of particles moved. */
int wc_contacts_project(const wc_contacts* ct, const wc_collider* c, int nc, const wc_filter* f, double* x,
                        double* v, wc_par* par);
/* Step 5 with the positions at the start of the substep x0 (n x 3, after begin's correction; NULL:
 * as wc_contacts_project): a particle whose path x0 -> x crossed a mesh collider's moving
 * triangle (wc_mesh_ccd) is first put back in front of the triangle it crossed first, at the
 * thickness, with no inward velocity relative to it; then as wc_contacts_project. */
int wc_contacts_project_from(const wc_contacts* ct, const wc_collider* c, int nc, const wc_filter* f,
                             const double* x0, double* x, double* v, wc_par* par);

#endif
