/* One cloth in a host's scene: the model (immutable), its mutable state, its settings, and what
 * ties them to the host:
 *  - the host map: the host's vertex count and rest positions, outputs in the host's vertex
 *    order (cloth_output.c);
 *  - the transform history of the object, the attachments (bones), the analytic colliders and
 *    the mesh colliders, and what a frame does with them: inertia, TELEPORT, RESET, pin targets,
 *    collider placement, mesh-collider targets (cloth_frame.c, cloth_attach.c,
 *    cloth_colliders.c, cloth_mesh.c);
 *  - the whole-frame backup and rollback, and snapshots (cloth_snapshot.c);
 *  - the collision check (cloth_check.c) and the state's energies (cloth_energy.c).
 * Where the particles are stepped is the backend's (cloth_backend.h), chosen at creation.
 *
 * Creation (cloth_build.c) and a new binding of attachments (cloth_attach.c) allocate everything
 * a frame needs: a frame allocates nothing. Callers read the struct's fields and change the
 * cloth only through these functions. Host transforms given to a cloth are rigid and finite (the
 * caller checks them: xform.h). Errors come back as a status with the message in the diag; a
 * refused call changes nothing (a device failing a transfer aside: wc_cloth_restore). */
#ifndef WEFT_CORE_CLOTH_H
#define WEFT_CORE_CLOTH_H
#include <stdint.h>
#include "cloth_backend.h"
#include "mesh_collider.h"
#include "mesh_desc.h"
#include "model.h"
#include "state.h"
#include "step.h"
#include "xform.h"

/* The largest |coordinate| an output position may have (m in world space, mesh units in object
 * space): the outputs are float (at most 3.4e38), with a wide margin. */
#define WC_CLOTH_MAX_COORD 1e30

/* ---- what a cloth is made of ---------------------------------------------------------------- */

typedef struct wc_cloth_attachment_def {
    const int* vertices;        /* (n_vertices) host vertex indices */
    int n_vertices;
    const float* bind_transform;   /* 16, column-major: the bone's transform the binding is taken in */
    const float* free_axis;     /* 3, bone-local: zero (fully pinned) or a unit vector (a line) */
} wc_cloth_attachment_def;

typedef struct wc_cloth_collider_def {
    int type;                   /* WC_COLLIDER_PLANE, _SPHERE or _CAPSULE (cloth_colliders.c) */
    double radius, half_height, thickness, friction;
    const float* transform;     /* 16, column-major */
} wc_cloth_collider_def;

typedef struct wc_cloth_mesh_def {
    wc_mesh_desc mesh;          /* the body (polygons triangulated, nothing welded) */
    double thickness, friction, push_speed;
    const float* transform;     /* 16, column-major: where the rest shape stands */
} wc_cloth_mesh_def;

/* Settings apart from the state: fixed at creation. */
typedef struct wc_cloth_settings {
    double max_frame_time;      /* s: the longest dt a frame may take */
    double linear_inertia;      /* [0, 1]: 1 the object's linear motion does not carry the cloth */
    double angular_inertia;     /* [0, 1]: the same for its rotation */
    double unit_scale;          /* metres per host mesh unit applied at import (files: times the
                                   file's own unit); object-space outputs divide by it */
} wc_cloth_settings;

typedef struct wc_cloth_def {
    wc_mesh_desc mesh;
    wc_model_def model;         /* welding, material, seams */
    wc_sim_def sim;             /* with the backend's defaults resolved */
    const float* transform;     /* 16, column-major: the object's transform; particles start at
                                   transform x rest */
    double max_frame_time, linear_inertia, angular_inertia;   /* wc_cloth_settings */
    const wc_cloth_attachment_def* attachments;
    int n_attachments;
    const wc_cloth_collider_def* colliders;
    int n_colliders;
    const wc_cloth_mesh_def* mesh_colliders;
    int n_mesh_colliders;
} wc_cloth_def;

/* ---- the cloth ------------------------------------------------------------------------------ */

typedef struct wc_cloth_attachment {
    int first_pin, n_pins;      /* its pins: [first_pin, first_pin + n_pins) */
    double free_axis[3];        /* bone-local unit axis, zero: fully pinned */
} wc_cloth_attachment;

/* An analytic collider's own shape (placed in the world by its transform every frame). */
typedef struct wc_cloth_collider {
    int type;                   /* wc_collider_type */
    double radius, half_height, thickness, friction;
} wc_cloth_collider;

typedef struct wc_cloth {
    wc_allocator alloc;
    wc_model model;
    wc_state* state;
    wc_cloth_settings settings;

    /* the host map */
    int n_host;                 /* host vertices (= model.n_host_verts) */
    double* host_rest;          /* (n_host x 3) object-space metres of every host vertex (unused
                                   vertices are reported rigidly moved with the object) */

    /* the object's transform history (cloth_frame.c) */
    wc_xform object;            /* T0: last object transform applied */
    double object_velocity[3];  /* V0: object origin velocity over the last frame (m/s) */
    int no_history;             /* 1: V0 is unknown (after create, teleport, reset) */

    /* attachments: current bone transforms, bone-local binding of each pinned particle */
    int n_attachments;
    wc_cloth_attachment* attachments;   /* (n_attachments) */
    wc_xform* attachment_xf;    /* (n_attachments) current (last applied) transforms */
    wc_xform* attachment_next;  /* (n_attachments) scratch of a frame */
    int n_pins;
    int* pin_particle;          /* (n_pins) */
    int* pin_attachment;        /* (n_pins) */
    double* pin_local;          /* (n_pins x 3) bone-local positions (m) */
    wc_pin* pins;               /* (n_pins) scratch for wc_state_set_pins */

    /* analytic colliders */
    int n_colliders;
    wc_cloth_collider* colliders;   /* (n_colliders) */
    wc_xform* collider_xf;      /* (n_colliders) current transforms */
    wc_xform* collider_next;    /* (n_colliders) scratch */
    wc_collider* world_colliders;   /* (n_colliders) scratch for wc_state_set_colliders */

    /* triangle-mesh colliders (cloth_mesh.c): core objects (their from/to positions are state),
       rest shapes (object space, m), rigid transforms */
    int n_mesh;
    wc_mesh_collider** mesh;    /* (n_mesh) */
    wc_xform* mesh_xf;          /* (n_mesh) current (last applied) transforms */
    wc_xform* mesh_next;        /* (n_mesh) scratch of a frame */
    int* mesh_pending;          /* (n_mesh) 1: new vertices were set for the next frame */
    double* mesh_scratch;       /* (largest n_verts x 3) */
    float* mesh_read;           /* (largest n_verts x 3) a body read from a host GL buffer */

    double* scratch;            /* (n_particles x 3) positions for reset and normals */
    int* mark;                  /* (n_particles) scratch: attachment of each particle, -1 */

    /* snapshots (cloth_snapshot.c) */
    uint64_t model_hash;        /* fingerprint of the model */
    size_t snapshot_size;
    unsigned char* backup;      /* (snapshot_size) state before the running frame */

    /* the backend */
    const wc_cloth_backend* backend;
    void* device;               /* the backend's per-context device (borrowed) */
    void* sim;                  /* the backend's own object for this cloth (NULL on the CPU) */
} wc_cloth;

/* Build the cloth: read the mesh, build the model and the state, place the particles at
 * transform x rest, the colliders, the mesh colliders, bind the attachments, check the outputs'
 * range, then hand it to the backend (its refusals come back as its create's). Messages name
 * the def's field ("def->mesh: ..."). */
wc_status wc_cloth_create(wc_cloth** out, const wc_cloth_def* def, const wc_cloth_backend* backend, void* device,
                          const wc_allocator* alloc, wc_diag* d);
/* wc_cloth_create in two calls, for a caller that chooses the backend (and so def->sim's
 * defaults) by the model: the first reads the mesh and builds the model and the host map (*out
 * holds nothing else yet: the caller reads c->model, then calls the second, or destroys it); the
 * second builds the rest from the same def and hands the cloth to the backend. After a failure
 * of the second the caller destroys the cloth. */
wc_status wc_cloth_create_model(wc_cloth** out, const wc_cloth_def* def, const wc_allocator* alloc, wc_diag* d);
wc_status wc_cloth_create_rest(wc_cloth* c, const wc_cloth_def* def, const wc_cloth_backend* backend, void* device,
                               wc_diag* d);
/* Not WC_OK (d says why) when the backend had to leave its objects to the host's GL context;
 * everything is freed either way. NULL is ignored. */
wc_status wc_cloth_destroy(wc_cloth* c, wc_diag* d);

/* ---- a frame (cloth_frame.c) ---------------------------------------------------------------- */

typedef struct wc_cloth_frame {
    double dt;                  /* s, in (0, max_frame_time] */
    int reset;                  /* 1: back to rest at the object's transform (wins over teleport) */
    int teleport;               /* 1: carried fully by the object's jump, no motion across it */
    const float* object_transform;          /* 16 at the end of the frame; NULL: unchanged */
    const float* attachment_transforms;     /* (n_attachments x 16); NULL: unchanged */
    const float* collider_transforms;       /* (n_colliders x 16); NULL: unchanged */
    const float* mesh_collider_transforms;  /* (n_mesh x 16); NULL: unchanged */
    const double* wind;                     /* 3, m/s world; NULL: unchanged */
} wc_cloth_frame;

/* One frame. On failure (no recovery worked, or the step would take a host vertex beyond
 * WC_CLOTH_MAX_COORD) the cloth is restored to its state before the call and the message says
 * so. *st receives the step's statistics. */
wc_status wc_cloth_step(wc_cloth* c, const wc_cloth_frame* fr, wc_step_stats* st, wc_diag* d);

/* ---- many cloths in one call (cloth_batch.c) ------------------------------------------------ */

/* One cloth of a batch: its frame in, its result out. */
typedef struct wc_cloth_batch_item {
    wc_cloth* cloth;
    wc_cloth_frame frame;
    wc_step_stats stats;        /* out: wc_cloth_step's */
    wc_status status;           /* out: wc_cloth_step's */
    double ms;                  /* out: wall time of this cloth's own step */
    wc_diag diag;               /* the cloth's own: its failure's message; its logger is called from
                                   the thread that steps the cloth (not always the caller's) */
    int index;                  /* the caller's (not read) */
} wc_cloth_batch_item;

/* Step every item's cloth with its frame: distinct cloths, in groups of one backend and device
 * (the group of the first item's cloth, then of the first left over, ...), each group inside one
 * begin/end of its device. Each cloth's result, status and message are wc_cloth_step's, bit for
 * bit. In a group of a backend with `concurrent`, when there are at least as many cloths as
 * threads (the cloths' own thread count) and more than one of each, the cloths are stepped at
 * once, one per thread, each on one thread (the step gives the same bits on any thread count:
 * core/par.h), the largest first; otherwise one after the other, each on all its threads. The
 * items may be reordered. Not WC_OK when a group could not begin: then d says why, every item
 * of that group has it as its status and diag and its cloths did not change (the other groups
 * stepped). Allocates nothing. */
wc_status wc_cloth_step_batch(wc_cloth_batch_item* items, int n, wc_diag* d);
/* Put the items back in the order of their `index` (after wc_cloth_step_batch). Allocates nothing. */
void wc_cloth_batch_sort_by_index(wc_cloth_batch_item* items, int n);

/* ---- attachments and mesh colliders (cloth_attach.c, cloth_mesh.c) ------------------------- */

/* Bind attachments to the cloth's current positions, replacing the old ones; `what` names the
 * array in messages ("attachments"). Refused: a vertex outside the host mesh or used by no
 * polygon, a particle in two attachments (welded twins and repeats within one merge). */
wc_status wc_cloth_set_attachments(wc_cloth* c, const wc_cloth_attachment_def* a, int n, const char* what,
                                   wc_diag* d);
/* Mesh collider `index`'s world positions (n_verts x 3, m) at the end of the next frame. */
wc_status wc_cloth_set_mesh_vertices(wc_cloth* c, int index, const float* positions, wc_diag* d);
/* Mesh collider `index`'s next frame end from a host GL buffer (src->n must be its n_verts),
 * through the backend (read_gl): kept on the device (res->taken: the collider's next target
 * there, its device_moves res->moves, the cloth woken when it moves; unless res->bad_vertex >= 0,
 * when nothing changed), or read into c->mesh_read and returned in *positions for the caller's
 * checks and wc_cloth_set_mesh_vertices (nothing else changes). Backends without the host's GL
 * context refuse it (UNSUPPORTED). */
wc_status wc_cloth_read_mesh_gl(wc_cloth* c, int index, const wc_gl_vertex_source* src, const float** positions,
                                wc_gl_vertex_result* res, wc_diag* d);

/* ---- outputs (cloth_output.c) --------------------------------------------------------------- */

/* Host-order positions and normals (either may be NULL) into float arrays (n_host x 3). */
wc_status wc_cloth_vertices(wc_cloth* c, int to_object, float* positions, float* normals, wc_diag* d);
/* The same into the host's GL buffers (r's buffer fields); backends without GL refuse it. */
wc_status wc_cloth_write_gl_buffers(wc_cloth* c, const wc_output_request* r, wc_diag* d);
/* Triangles as host vertex indices (model.n_tris x 3). */
void wc_cloth_triangles(const wc_cloth* c, int* indices);
void wc_cloth_backend_stats(const wc_cloth* c, wc_backend_stats* out);

/* ---- the collision check (cloth_check.c) ---------------------------------------------------- */

/* Crossings of the cloth with itself at its current positions, and the deepest particle behind
 * the surface of any collider (m, thickness not included). */
wc_status wc_cloth_check_collisions(wc_cloth* c, int* self_intersections, double* max_penetration, wc_diag* d);

/* ---- energies (cloth_energy.c) ------------------------------------------------------------- */

typedef struct wc_cloth_energy {
    double kinetic;             /* J: sum of m |v|^2 / 2 */
    double elastic;             /* J: the springs' potential energy */
    double gravity;             /* J: sum of -m g . x, relative to the world origin */
    double mass;                /* kg */
    double center_of_mass[3];   /* m, world */
} wc_cloth_energy;

/* The current state's energies, mass and centre of mass. */
wc_status wc_cloth_energy_of(wc_cloth* c, wc_cloth_energy* out, wc_diag* d);

/* ---- snapshots (cloth_snapshot.c) ----------------------------------------------------------- */

/* What identifies the library that wrote a snapshot: written into it and required of one
 * restored (a mismatch is WC_ERROR_SNAPSHOT_MISMATCH naming both). */
typedef struct wc_snapshot_stamp {
    uint32_t abi, version;
} wc_snapshot_stamp;

/* Write the cloth's whole mutable state (c->snapshot_size bytes) into buf. */
wc_status wc_cloth_save(wc_cloth* c, const wc_snapshot_stamp* stamp, void* buf, wc_diag* d);
/* Restore a snapshot of `size` bytes (at least the snapshot's own); refused (nothing changes):
 * truncated, not a snapshot of this format, another library (SNAPSHOT_MISMATCH), damaged
 * (checksum or implausible content), another model (SNAPSHOT_MISMATCH). A device that then fails
 * the upload leaves the state restored and its own particles as they were (the status says so). */
wc_status wc_cloth_restore(wc_cloth* c, const wc_snapshot_stamp* stamp, const void* buf, size_t size, wc_diag* d);

#endif
