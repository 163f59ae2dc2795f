/* Colliders (plane, sphere, capsule; each with a thickness and Coulomb-like friction) and the
 * contact handling of a substep, through the constraint filter (Baraff & Witkin section 5):
 *   1. wc_contacts_begin   before the solve: find contacts, push particles out to the thickness
 *                          shell (position correction), constrain the normal direction
 *                          (S = I - n n^T; two contacts: 2 DOF; z cancels the relative normal
 *                          velocity).
 *   2. (solve)
 *   3. wc_contacts_end     after the solve: the constraint force (A dv - b)_i / h along n of each
 *                          contact; a contact whose force pulls the particle towards the
 *                          collider is released for the next substep; friction scales the
 *                          tangential relative velocity down by mu |normal impulse| / m.
 *   4. wc_contacts_project after positions are advanced: any particle still inside a collider's
 *                          shell is moved to it and its inward relative normal velocity removed.
 * Pinned particles (filter ndof 3) are never touched. */
#ifndef WEFT_CORE_COLLIDE_H
#define WEFT_CORE_COLLIDE_H
#include "filter.h"
#include "par.h"

typedef enum wc_collider_type {
    WC_COLLIDER_PLANE = 0,     /* {x : normal.x = offset}; free side normal.x > offset */
    WC_COLLIDER_SPHERE = 1,    /* center, radius */
    WC_COLLIDER_CAPSULE = 2    /* segment a-b, radius */
} wc_collider_type;

typedef struct wc_collider {
    int type;                  /* wc_collider_type */
    double normal[3];          /* plane: unit normal */
    double offset;             /* plane: m */
    double center[3];          /* sphere: m */
    double a[3], b[3];         /* capsule: segment end points (m) */
    double radius;             /* sphere, capsule: m, >= 0 */
    double thickness;          /* m, >= 0: the cloth stays this far outside the surface */
    double friction;           /* Coulomb coefficient, >= 0 */
    double velocity[3];        /* m/s: rigid translation velocity of the collider this substep */
} wc_collider;

/* Signed distance from p to the collider's surface (negative inside; thickness not included) and
 * the outward unit normal at the closest surface point. */
double wc_collider_distance(const wc_collider* c, const double* p, double* normal);

/* Persistent per-particle contact state (lives in wc_state). */
typedef struct wc_contacts {
    int n;                     /* particles */
    int* collider;             /* (n x 2) colliders in contact, -1 for none */
    double* normal;            /* (n x 6) their normals */
    unsigned char* released;   /* (n) a contact was released last substep: not re-constrained
                                  while the particle is outside the shell */
    int active;                /* number of particles with at least one contact */
} wc_contacts;

/* Step 1. x is corrected in place; f gets the contact constraints of non-pinned particles.
 * On entry f must hold the step's pins only (free elsewhere): particles with ndof 2 (line pins)
 * or 3 get no contact, ndof 0 or 1 are (re)written. Returns the particles in contact (also
 * ct->active); a particle approaching the shell within this substep is prescribed the normal
 * velocity that lands it on the shell at the end of the substep (see collide.c). */
int wc_contacts_begin(wc_contacts* ct, const wc_collider* c, int nc, double* x, const double* v, double h,
                      wc_filter* f, wc_par* par);
/* Step 3. r = A dv - b (n x 3) for the solved system; v_new (n x 3) = v + dv, modified in place by
 * friction; mass (n). */
void wc_contacts_end(wc_contacts* ct, const wc_collider* c, int nc, const double* r, const double* mass, double h,
                     double* v_new, wc_par* par);
/* Step 4. Every particle but the pinned ones (ndof 3; f may be NULL). Returns the number of
 * particles moved. */
int wc_contacts_project(const wc_contacts* ct, const wc_collider* c, int nc, const wc_filter* f, double* x,
                        double* v, wc_par* par);

#endif
