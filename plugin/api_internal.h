/* Private to libweft.so: the context and cloth objects behind the public handles, and the helpers
 * the plugin's files share. The public contract is include/weft/weft.h; nothing here is exported.
 *
 * Layout of the facade:
 *   context.c       context def/create/destroy, last error, logger and allocator bridges, handle table
 *   transform.c     float 4x4 column-major transforms -> double affine, rigidity checks
 *   cloth_def.c     defaults of the cloth/attachment/collider defs and the frame, def validation
 *   cloth_create.c  mesh -> model -> state, cloth create/destroy, info
 *   attach.c        attachments: host vertices -> pinned particles, bone-local binding, pin targets
 *   colliders.c     collider defs + transforms -> world wc_collider
 *   mesh_colliders.c triangle-mesh colliders: defaults, validation, import, per-frame targets,
 *                   weft_cloth_set_mesh_collider_vertices
 *   cloth_frame.c   weft_cloth_step: inertia, teleport, reset, pins, colliders, wind, step
 *   cloth_output.c  vertices, normals, triangles in host order
 *   snapshot.c      save/restore of the whole mutable state (also the step's rollback)
 *   render.c        weft_render: preview pictures through gpu/'s renderer (lazy EGL context)
 *   gpu_glue.c      the GPU backend: GL context + wg_device per context, wg_sim per cloth, the
 *                   step's GPU pieces, outputs, weft_cloth_write_gl_buffers */
#ifndef WEFT_PLUGIN_API_INTERNAL_H
#define WEFT_PLUGIN_API_INTERNAL_H
#include <stdatomic.h>
#include <stdint.h>
#include "model.h"
#include "state.h"
#include "step.h"
#include "weft/weft.h"
#include "call_guard.h"

/* Cookies the weft_default_*() functions put into internal_cookie: a def that skipped its
 * initialiser (zeroed, stack garbage, or a def of another type) is refused. */
#define WA_COOKIE_CONTEXT 0x57464331u    /* "WFC1" */
#define WA_COOKIE_CLOTH 0x57464c31u      /* "WFL1" */
#define WA_COOKIE_ATTACHMENT 0x57464131u /* "WFA1" */
#define WA_COOKIE_COLLIDER 0x57464f31u   /* "WFO1" */
#define WA_COOKIE_RENDER 0x57465231u     /* "WFR1" (weft_default_render_def, render code) */
#define WA_COOKIE_MESH_COLLIDER 0x57464d31u /* "WFM1" */

/* ---- transforms (transform.c) ---------------------------------------------------------------- */

/* An affine transform in double: p' = R p + t, R row-major. Built from a host float[16]. */
typedef struct wa_xform {
    double R[9];
    double t[3];
} wa_xform;

void wa_xform_identity(wa_xform* o);
/* From 16 floats, column-major (element (r, c) at m[4c + r]); no checks. */
void wa_xform_from_floats(wa_xform* o, const float* m);
/* Validate a host transform: every element finite (else NONFINITE), last row (0, 0, 0, 1) and
 * R rigid (|det R - 1| < 1e-3, max |R^T R - I| < 1e-3; else INVALID_ARGUMENT). On failure `why`
 * receives the reason ("[7] is NaN", "is not rigid: det 2"). */
weft_status wa_check_transform(const float* m, char* why, size_t why_size);
void wa_xform_point(const wa_xform* x, const double* p, double* out);   /* out = R p + t */
void wa_xform_vector(const wa_xform* x, const double* v, double* out);  /* out = R v */
/* Exact affine inverse (general 3x3 inverse, not the transpose); identity if singular. */
void wa_xform_inverse(const wa_xform* x, wa_xform* out);
/* Rotation by fraction c of the rotation in R (axis-angle, Rodrigues), into Rc (row-major 3x3);
 * c == 1 gives R itself (the host's matrix, rigid within 1e-3, not re-orthonormalised).
 * Returns 0 (and Rc = I) when R's rotation angle or c is 0, else 1. */
int wa_rotation_fraction(const double* R, double c, double* Rc);

/* ---- objects --------------------------------------------------------------------------------- */

typedef struct wa_attachment {
    int first_pin, n_pins;      /* its pins: wa_cloth.pin_* [first_pin, first_pin + n_pins) */
    double free_axis[3];        /* bone-local unit axis, zero: fully pinned */
} wa_attachment;

typedef struct wa_collider {
    int type;                   /* weft_collider_type */
    double radius, half_height, thickness, friction;
} wa_collider;

typedef struct wa_cloth {
    weft_context* ctx;
    wc_model model;
    wc_state* state;
    int n_host;                 /* host vertices (= model.n_host_verts) */
    double* host_rest;          /* (n_host x 3) object-space metres of every host vertex (unused
                                   vertices are reported rigidly moved with the object) */
    double unit_scale;
    double max_frame_time;
    double linear_inertia, angular_inertia;

    /* the object's transform history (see cloth_frame.c) */
    wa_xform object;            /* T0: last object transform applied */
    double object_velocity[3];  /* V0: object origin velocity over the last frame (m/s) */
    int no_history;             /* 1: V0 is unknown (after create, teleport, reset) */

    /* attachments: current bone transforms, bone-local binding of each pinned particle */
    int n_attachments;
    wa_attachment* attachments;     /* (n_attachments) */
    wa_xform* attachment_xf;        /* (n_attachments) current (last applied) transforms */
    wa_xform* attachment_next;      /* (n_attachments) scratch of a frame */
    int n_pins;
    int* pin_particle;              /* (n_pins) */
    int* pin_attachment;            /* (n_pins) */
    double* pin_local;              /* (n_pins x 3) bone-local positions (m) */
    wc_pin* pins;                   /* (n_pins) scratch for wc_state_set_pins */

    /* colliders */
    int n_colliders;
    wa_collider* colliders;         /* (n_colliders) */
    wa_xform* collider_xf;          /* (n_colliders) current transforms */
    wa_xform* collider_next;        /* (n_colliders) scratch */
    wc_collider* wc_colliders;      /* (n_colliders) scratch for wc_state_set_colliders */

    /* triangle-mesh colliders (mesh_colliders.c): core objects (their from/to positions are
       snapshot state), rest shapes (object space, m), rigid transforms */
    int n_mesh;
    wc_mesh_collider** mesh;        /* (n_mesh) */
    wa_xform* mesh_xf;              /* (n_mesh) current (last applied) transforms */
    wa_xform* mesh_next;            /* (n_mesh) scratch of a frame */
    int* mesh_pending;              /* (n_mesh) 1: new vertices were set for the next frame */
    double* mesh_scratch;           /* (largest n_verts x 3) */
    double* scratch;                /* (n_particles x 3) positions for reset and normals */
    int* mark;                      /* (n_particles) scratch: attachment of each particle */
    uint64_t model_hash;            /* fingerprint of the model (snapshot.c) */
    size_t snapshot_size;
    unsigned char* backup;          /* (snapshot_size) state before the running step */
    void* gpu;                      /* wg_sim* on a GPU context (its state lives in textures and
                                       state's x, v, dv and contact arrays are a mirror that is
                                       filled only on demand: wa_gpu_download), else NULL */
} wa_cloth;

typedef struct wa_slot {
    uint32_t generation;        /* bumped at every destroy; never 0 */
    wa_cloth* cloth;            /* NULL when free */
} wa_slot;

struct weft_context {
    weft_context_def def;       /* as given (logger, level, threads) */
    weft_backend backend;       /* CPU or GPU (never AUTO) */
    wc_allocator alloc;         /* bridge of def.allocator (also gpu/'s allocator) */
    wc_diag core_diag;          /* handed to core calls: forwards core's DEBUG..WARN to the logger
                                   (core's ERRORs come back as statuses and are reported once,
                                   prefixed, by wa_fail) */
    weft_status last_status;
    char last_error[512];
    uint32_t tag;               /* per-context handle tag (16 bits) */
    int n_slots, cap_slots;
    wa_slot* slots;
    void* gl;                   /* wg_gl_context*: created with the context on the GPU backend,
                                   else by the first weft_render (render.c); one per context, shared
                                   by the solver and the renderer */
    void* renderer;             /* wg_renderer* in it */
    void* device;               /* wg_device* (GPU backend only): the solver's programs */
    _Atomic uintptr_t call_owner; /* in-call flag (call_guard.c): the calling thread's token, 0 idle */
    int call_depth;             /* nested calls of the owning thread */
};

/* ---- context.c helpers ----------------------------------------------------------------------- */

/* Core's (and gpu/'s) status as the ABI's. */
weft_status wa_status(wc_status s);
/* Record a failed call (status, message, logger at ERROR); returns status. */
weft_status wa_fail(weft_context* ctx, weft_status status, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
/* Record a successful call; returns WEFT_OK. */
weft_status wa_ok(weft_context* ctx);
/* Log at a level (filtered by the context's log_level). */
void wa_log(weft_context* ctx, weft_log_level level, const char* fmt, ...) __attribute__((format(printf, 3, 4)));
/* A core diag for one call (no logger for errors; warnings forwarded). */
wc_diag wa_core_diag(weft_context* ctx);
/* The logger bridge of wa_core_diag, a wc_log_fn with user = the weft_context: core's and gpu/'s
 * DEBUG..WARN go to the context's logger (level mapped, filtered by def.log_level); ERRORs are
 * dropped (they come back as statuses and are reported once, prefixed, by wa_fail). */
void wa_core_log(wc_log_level level, const char* message, void* user);
/* The cloth a handle names, or NULL (then the failure is recorded, prefixed with fn). */
wa_cloth* wa_lookup(weft_context* ctx, weft_cloth h, const char* fn);
/* Register a cloth in a free slot; 0 on allocation failure. */
int wa_register(weft_context* ctx, wa_cloth* c, weft_cloth* out);
/* Release the slot of a handle that wa_lookup accepted. */
void wa_unregister(weft_context* ctx, weft_cloth h);

/* ---- cloth_def.c ------------------------------------------------------------------------------ */

/* Validate everything of the def that can be checked before the mesh is read; status + message
 * (naming the field) into msg. */
weft_status wa_validate_cloth_def(const weft_cloth_def* def, char* msg, size_t msg_size);
/* Validate attachment defs (cookie, counts, transforms, axis); vertex indices against n_host
 * when n_host >= 0. prefix names the array ("def->attachments", "attachments"). */
weft_status wa_validate_attachments(const weft_attachment_def* a, int n, int n_host, const char* prefix, char* msg,
                                    size_t msg_size);
weft_status wa_validate_colliders(const weft_collider_def* c, int n, const char* prefix, char* msg, size_t msg_size);

/* ---- cloth_create.c / attach.c / colliders.c ------------------------------------------------- */

void wa_cloth_free(wa_cloth* c);
/* Bind attachments to the cloth's current positions, replacing the old ones. Validated already
 * except for the particle checks (welded twins merge, a particle in two attachments is an
 * error, an unused host vertex is an error), which are done here before anything changes. */
weft_status wa_bind_attachments(weft_context* ctx, wa_cloth* c, const weft_attachment_def* a, int n,
                                const char* fn, const char* prefix);
/* Pin targets from the given bone transforms into c->pins (count c->n_pins). */
void wa_pin_targets(const wa_cloth* c, const wa_xform* bones);
/* World colliders from the collider defs and the given transforms into c->wc_colliders, with
 * velocity (origin(next) - origin(prev)) / dt, or zero when dt <= 0. */
void wa_world_colliders(const wa_cloth* c, const wa_xform* next, const wa_xform* prev, double dt);

/* ---- mesh_colliders.c ------------------------------------------------------------------------ */
weft_status wa_validate_mesh_colliders(const weft_mesh_collider_def* m, int n, char* msg, size_t msg_size);
/* Import and create the def's mesh colliders and attach them to c->state (creation). */
weft_status wa_build_mesh_colliders(weft_context* ctx, wa_cloth* c, const weft_cloth_def* def, const char* fn);
void wa_free_mesh_colliders(wa_cloth* c);
/* Validate fr->mesh_collider_transforms (recorded with fn). */
weft_status wa_check_mesh_frame(weft_context* ctx, const wa_cloth* c, const weft_frame* fr, const char* fn);
/* A frame's targets: colliders without new vertices get transform x rest (fr's transform or the
 * last one); jump (TELEPORT / RESET): from = to, no motion across the frame. */
void wa_mesh_frame(wa_cloth* c, const weft_frame* fr, int jump);
/* After a successful frame: the transforms become current, pending flags clear. */
void wa_mesh_frame_done(wa_cloth* c);

/* ---- cloth_output.c -------------------------------------------------------------------------- */

/* The largest |coordinate| an output position may have (m in world space, mesh units in object
 * space): the outputs are float (at most 3.4e38), with a wide margin. */
#define WA_MAX_OUTPUT_COORD 1e30
/* 1 when every host vertex's output position, world and object space, with T as the object
 * transform, is within WA_MAX_OUTPUT_COORD (and finite); else 0 with the first host vertex
 * outside and the offending value. */
int wa_outputs_in_range(const wa_cloth* c, const wa_xform* T, int* vertex, double* value);

/* ---- render.c -------------------------------------------------------------------------------- */

/* Release the context's GL context and renderer (nothing when it never rendered). */
void wa_render_release(weft_context* ctx);

/* ---- gpu_glue.c: the GPU backend (WEFT_HAVE_GPU; stubs failing with UNSUPPORTED otherwise) ---- */

/* Create the context's GL context and solver device (weft_context_create); on failure the
 * message goes into err and nothing is kept. software: set to the device's software flag. */
/* The context's GL context (a wg_gl_context*: headless or the host's, per def.gl_mode, with the
 * context's logger and allocator); UNSUPPORTED without WEFT_GPU. */
weft_status wa_gl_context_new(weft_context* ctx, void** out, char* err, size_t err_len);
weft_status wa_gpu_context_init(weft_context* ctx, int probe_only_hardware, int* software, char* err, size_t err_len);
/* Destroy the device (inside wg_gl_begin/end); the GL context is released by wa_render_release. */
void wa_gpu_context_release(weft_context* ctx);
/* 1 when the context's GPU device runs compute-shader passes, the ones that have the multigrid
 * preconditioner (gpu/solver/wg_amg.h); 0 otherwise (fragment passes, no device). */
int wa_gpu_has_multigrid(const weft_context* ctx);
/* Upload a freshly built cloth (weft_cloth_create); failures recorded with fn. */
weft_status wa_gpu_cloth_create(weft_context* ctx, wa_cloth* c, const char* fn);
void wa_gpu_cloth_destroy(wa_cloth* c);
/* Read the GPU state (x, v, dv, contacts) into the CPU mirror / send the mirror. Recorded. */
weft_status wa_gpu_download(weft_context* ctx, wa_cloth* c, const char* fn);
weft_status wa_gpu_upload(weft_context* ctx, wa_cloth* c, const char* fn);
/* GL access around a group of calls: begin records a failure with fn. */
weft_status wa_gl_begin(weft_context* ctx, const char* fn);
void wa_gl_end(weft_context* ctx);
/* The same transfers inside wa_gl_begin/end (recorded with fn on failure). */
weft_status wa_gpu_download_raw(weft_context* ctx, wa_cloth* c, const char* fn);
weft_status wa_gpu_upload_raw(weft_context* ctx, wa_cloth* c, const char* fn);
/* The step's pieces, inside wa_gl_begin/end: the textures' backup and its restore, the rigid
 * change x' = Rx x + tx, v' = Rv v + dv (row-major), the frame, and the output range check
 * (the GPU's max |coordinate| as a bound; the positions are downloaded only when the bound could
 * pass WA_MAX_OUTPUT_COORD; a failed download sets *st and d). */
/* upload (1) or download (0) with the failure in d only. */
weft_status wa_gpu_transfer(wa_cloth* c, int upload, wc_diag* d);
void wa_gpu_backup(wa_cloth* c);
void wa_gpu_restore_backup(wa_cloth* c);
void wa_gpu_transform(wa_cloth* c, const double* Rx, const double* tx, const double* Rv, const double* dv);
weft_status wa_gpu_step_frame(wa_cloth* c, double dt, wc_step_stats* ss, wc_diag* d);
int wa_gpu_outputs_in_range(wa_cloth* c, const wa_xform* T, int* vertex, double* value, weft_status* st,
                            wc_diag* d);
/* Host-order positions/normals of a GPU cloth (world, or object space with c->object and
 * unit_scale) into float arrays or GL buffers (wg_sim_output). Inside wa_gl_begin/end. */
weft_status wa_gpu_vertices(weft_context* ctx, wa_cloth* c, int object, float* positions, float* normals,
                            unsigned position_buffer, size_t position_offset, unsigned normal_buffer,
                            size_t normal_offset, const char* fn);

/* ---- snapshot.c ------------------------------------------------------------------------------ */

size_t wa_snapshot_size(const wa_cloth* c);
uint64_t wa_model_hash(const wa_cloth* c);
/* Write the snapshot (size wa_snapshot_size) with or without the checksum (the step's internal
 * backup skips it); restore one written by this cloth without any check. */
void wa_snapshot_write(const wa_cloth* c, unsigned char* buf, int checksum);
void wa_snapshot_apply(wa_cloth* c, const unsigned char* buf);
/* The step's backup of a GPU cloth: everything but x, v, dv and the contact arrays (those are
 * backed up in textures by wg_sim_backup). Fits in the snapshot_size buffer. */
void wa_snapshot_write_small(const wa_cloth* c, unsigned char* buf);
void wa_snapshot_apply_small(wa_cloth* c, const unsigned char* buf);

#endif
