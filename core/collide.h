/* The contacts of a substep between the cloth's particles and the colliders (collider.h: each
 * with a thickness and Coulomb friction), through the constraint filter (Baraff & Witkin
 * section 5):
 *   1. wc_contacts_begin    before the forces: find contacts, push particles out to the thickness
 *                           shell (position correction), constrain the normal direction
 *                           (S = I - n n^T; two contacts: 2 DOF; z cancels the relative normal
 *                           velocity).
 *   2. wc_contacts_friction after the assembly: Coulomb friction through the implicit system
 *                           (collide_friction.h): a contact that sticks gets its tangential DOF
 *                           constrained too, one that slides an implicit damping.
 *   3. (solve; then wc_contacts_friction_recheck: sticks the solved cloth overloads slide, and
 *      the system is solved again)
 *   4. wc_contacts_end      after the solve: the constraint force (A dv - b)_i / h along n of each
 *                           contact; a contact whose force pulls the particle towards the
 *                           collider is released for the next substep (TR-BDF2: after stage 2,
 *                           on both stages' forces together, bdf2.h wc_integ_contact_impulses).
 *   5. wc_contacts_project  after positions are advanced: any particle still inside a collider's
 *                           shell is moved to it and its inward relative normal velocity removed.
 * Pinned particles (filter ndof 3, not from a sticking contact) are never touched. */
#ifndef WEFT_CORE_COLLIDE_H
#define WEFT_CORE_COLLIDE_H
#include "collider.h"
#include "filter.h"
#include "par.h"

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
    struct wc_mesh_near* near; /* (n x n_near) each particle's candidate triangles of the mesh
                                  colliders 0 .. n_near - 1 (mesh_collider.h): the same answers,
                                  cheaper; not state. NULL: none */
    int n_near;
} wc_contacts;

/* Step 1. x is corrected in place; f gets the contact constraints of non-pinned particles.
 * On entry f must hold the step's pins only (free elsewhere): particles with ndof 2 (line pins)
 * or 3 get no contact, ndof 0 or 1 are (re)written. Returns the particles in contact (also
 * ct->active); a particle approaching the shell within this substep is prescribed the normal
 * velocity that lands it on the shell at the end of the substep (see collide.c). */
int wc_contacts_begin(wc_contacts* ct, const wc_collider* c, int nc, double* x, const double* v, double h,
                      wc_filter* f, wc_par* par);
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

/* ---- shared with the friction (collide_friction.c) ---- */
/* The free-direction projector of one or two (cnt) contact normals n (cnt x 3):
 * S = I - n1 n1^T (- e2 e2^T, e2 the unit part of n2 orthogonal to n1). */
void wc_contacts_free_projector(const double* n, int cnt, double* S);
/* The normal impulse of each of cnt contacts (N s; the constraint force times h): the components
 * of r (3) in the basis of their normals n (cnt x 3). */
void wc_contacts_normal_impulses(const double* r, const double* n, int cnt, double* imp);
/* The sum of the per-thread counts par->partial[8 t] of threads t < used, in thread order. */
int wc_contacts_sum_counts(const wc_par* par, int used);

#endif
