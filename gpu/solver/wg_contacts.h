/* Plane, sphere, capsule and triangle-mesh contacts with thickness and Coulomb friction on the
 * GPU: the five steps of core/collide.c as passes over one cloth, with the same rules, called by
 * the substep (wg_step.c) only when the state has colliders. Colliders come from the state's
 * mesh colliders (s->mesh, first, as core numbers them) and s->colliders at each hook that reads
 * them, with the meshes' continuous tests (a particle whose path crosses a moving triangle within
 * the substep). The meshes' sharp features as penalty pairs (core/mesh_pairs.h) are wg_pairs.h's.
 * Contact state (per particle: colliders, normals, released, stick) lives in the contacts' own
 * textures, in rings rolled back with the substep (save/restore) and backed up with the frame
 * (backup/restore_backup).
 *
 * The contacts receive the cloth's textures they read and change (wg_contact_cloth: pointers into
 * the cloth, which keep their addresses): a pass that changes the filter, b or A writes into a
 * scratch texture of the same format, which then trades values with the cloth's. Every function
 * takes NULL (a cloth without colliders) and does nothing; calls are made with the cloth's GL
 * context current. */
#ifndef WEFT_GPU_SOLVER_CONTACTS_H
#define WEFT_GPU_SOLVER_CONTACTS_H

#include "mesh_collider.h"
#include "state.h"
#include "status.h"
#include "wg_reduce.h"
#include "wg_ring.h"

typedef struct wg_contact_cloth {
    int n, nb;                  /* particles, blocks */
    wg_ring *x, *v;             /* begin and project write a new cur, never the ring's keep */
    wg_tex *S0, *S1, *z, *b;    /* the substep's filter and right-hand side */
    wg_tex *a_lo, *a_hi;        /* the substep's matrix A (symmetric blocks) */
    const wg_tex *mass, *ftot, *pblocks, *block;
    float* scratch;             /* n x 4 floats of staging (uploads, read-backs) */
} wg_contact_cloth;

typedef struct wg_contacts wg_contacts;
struct wg_pairs;

/* The contacts of a cloth with room for max_colliders analytic colliders and the n_mesh mesh
 * colliders mesh (borrowed: the state's; *out NULL and WC_OK when there are none): WC_OK, or
 * WC_ERROR_GPU (fewer than 8 draw buffers, too many colliders or mesh elements for the device's
 * textures, GL errors) or WC_ERROR_OUT_OF_MEMORY with err. */
wc_status wg_contacts_create(wg_runner* r, const wg_contact_cloth* cloth, int max_colliders,
                             wc_mesh_collider* const* mesh, int n_mesh, wg_contacts** out, char* err, size_t err_len);
void wg_contacts_destroy(wg_contacts* cs);
/* Free the memory only (the GL context is gone). */
void wg_contacts_forget(wg_contacts* cs);
/* GPU memory held (textures: the contacts', the mesh colliders' and their bodies'); 0 for NULL. */
size_t wg_contacts_bytes(const wg_contacts* cs);

/* 1: after the pins pass (S0, S1, z hold the pins): move the meshes to the substep from
 * s->sub_alpha0 to alpha1 of length h, find contacts, correct positions (a new x cur), write
 * their constraints into S0/S1/z. */
void wg_contacts_begin(wg_contacts* cs, const wc_state* s, double alpha1, double h);
/* The integrator's textures TR-BDF2's contact rule changes (the cloth's; their addresses kept). */
typedef struct wg_contact_integ {
    wg_tex *xb, *vstar, *mom;   /* the stage's base position, v*, momentum term */
    wg_ring* vp;                /* stage 1's start velocity v_n (a new cur in stage 1) */
} wg_contact_integ;

/* 1b, TR-BDF2's stage `stage` (1 or 2) of length h with system step he, after begin and the
 * integrator's xb, v*, mom (core/bdf2.c wc_integ_contacts): each particle in contact loses its
 * normal velocity relative to the colliders and lands on their shells at the stage's end (v: a
 * new cur; xb, v*, z; stage 1's v_prev or stage 2's mom). */
void wg_contacts_integ(wg_contacts* cs, const wg_contact_integ* io, int stage, double h, double he);
/* 2: after assembly (A in block layout, b, ftot): Coulomb friction; may change S0/S1/z, the
 * diagonal blocks of A and b. mom: TR-BDF2's momentum term in the particle's prediction
 * (core/collide.h wc_contacts_friction), NULL for backward Euler and BDF2. */
void wg_contacts_friction(wg_contacts* cs, const wc_state* s, double h, const wg_tex* mom);
/* 3b: after a solve whose result is dv: sticking contacts the solved cloth overloads slide;
 * returns 1 when something changed (the caller solves again). Reads back one texel. */
int wg_contacts_recheck(wg_contacts* cs, const wc_state* s, const wg_tex* dv);
/* The cloth's penalty pairs (wg_pairs.h; kept, NULL: none): end's residual A dv - b takes their
 * off-diagonal blocks, as core's does (friction's recheck does not: its pass has no texture unit
 * left for them). */
void wg_contacts_use_pairs(wg_contacts* cs, const struct wg_pairs* pairs);
/* 4: after v += dv (dv the solve's result): release contacts whose normal impulse pulls inward.
 * stage (TR-BDF2, core/bdf2.c wc_integ_contact_impulses): 1 releases nothing and holds each
 * contact's impulse; 2 adds stage 1's held impulses before the test; 0 for the others. */
void wg_contacts_end(wg_contacts* cs, const wc_state* s, const wg_tex* dv, int stage);
/* 5: after positions advanced and strain limiting: push x out of collider shells, remove inward
 * normal velocity (new x and v cur). */
void wg_contacts_project(wg_contacts* cs, const wc_state* s);
/* Particles in contact now (read back: one texel). */
int wg_contacts_active(wg_contacts* cs);
/* Particles whose contacts stick after the friction pass and its rechecks (read back: one texel). */
int wg_contacts_stuck(wg_contacts* cs);
void wg_contacts_save(wg_contacts* cs);             /* the substep's start */
void wg_contacts_restore(wg_contacts* cs);          /* rollback to it */
/* The mesh colliders' textures and bodies (wg_mesh.h); NULL when cs is NULL. */
struct wg_mesh* wg_contacts_mesh(wg_contacts* cs);
void wg_contacts_backup(wg_contacts* cs);           /* the frame's back-up (wg_sim_backup) */
void wg_contacts_restore_backup(wg_contacts* cs);
/* The contact arrays of the CPU mirror (s->contacts) from and to the textures (snapshots). */
void wg_contacts_download(wg_contacts* cs, wc_state* s);
void wg_contacts_upload(wg_contacts* cs, const wc_state* s);

#endif
