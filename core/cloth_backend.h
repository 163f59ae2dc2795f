/* The backend of a cloth: a table of the operations that run where the cloth's particles live.
 * The cloth (cloth.h) does everything else itself, on the CPU, the same for every backend:
 * the transform history, pins, colliders, snapshots, the host map, the range check. Two tables
 * exist: core's CPU step (wc_cloth_cpu, cloth_cpu.c: wc_step_frame on the wc_state itself) and
 * the GPU's (gpu/solver/wg_backend.h: wg_sim, the state's particle arrays in textures).
 *
 * The mirror. On a backend with `mirror` set, the wc_state's x, v, dv and contact arrays are a
 * copy of the device's that is filled only on demand (download) and sent back after the cloth
 * changed it (upload); everything else of the state (pins, colliders, clocks, sleep) is the
 * cloth's book-keeping, read by the backend's step. Without a mirror the state is the truth and
 * download / upload do nothing.
 *
 * Device and groups. A backend may need a per-context device (GL context and programs), made by
 * device_create and shared by the context's cloths; its operations on a cloth run between
 * begin and end (one GL begin/end around a group of operations: a frame, a transfer, an output).
 * A batch (cloth_batch.c) steps many cloths of one device inside one begin/end: one after the
 * other, or at once on several threads where the backend says `concurrent`.
 * Every entry is set (a backend that has nothing to do supplies a function that does nothing). */
#ifndef WEFT_CORE_CLOTH_BACKEND_H
#define WEFT_CORE_CLOTH_BACKEND_H
#include <stddef.h>
#include "alloc.h"
#include "diag.h"
#include "solve.h"
#include "step.h"
#include "xform.h"

struct wc_cloth;

/* A cloth as a backend is asked about it before it is handed over (supports): its model, its
 * settings with this backend's defaults resolved, its mesh colliders. */
typedef struct wc_backend_query {
    const wc_model* model;
    const wc_sim_def* sim;      /* max_colliders: its analytic colliders */
    int n_mesh_colliders;
} wc_backend_query;

/* What a device is made with. */
typedef struct wc_device_desc {
    int host_gl;                /* 1: the host's GL context, current at every begin; 0: the backend's own */
    int only_hardware;          /* 1: a software device is not wanted (reported by *software, not made) */
    wc_log_fn log;              /* the device's messages below ERROR (NULL: silent) */
    void* log_user;
    wc_allocator allocator;
} wc_device_desc;

/* What a backend's defaults may depend on: the cloth's size, whether its def names a
 * preconditioner, and its integrator. */
typedef struct wc_defaults_query {
    int n_particles;
    int preconditioner_named;         /* 1: the def names one (this backend's is not used) */
    wc_integrator integrator;         /* as the def resolved it (DEFAULT: backward Euler) */
} wc_defaults_query;

/* The backend's choices for what a cloth's def leaves to it (a def's DEFAULT / 0 / -1). */
typedef struct wc_backend_defaults {
    wc_precond_type preconditioner;   /* PCG's preconditioner */
    double newton_forcing;            /* inexact Newton's forcing term (wc_sim_def.newton_forcing) */
    double tolerance;                 /* the linear solves' relative residual (wc_solver_opts.tolerance) */
    int newton_iterations;            /* linearised solves per substep */
    int line_search;                  /* 0 or 1 */
    int garment_self_collision;       /* self-collision of a garment (a cloth with mesh colliders or
                                         seams); other cloths have none by default */
} wc_backend_defaults;

/* A rigid carry of the particles (the frame's inertia or teleport; cloth_frame.c). Each backend
 * keeps its own arithmetic: the CPU applies the pieces as separate passes, the GPU composes one
 * transform, so the two round differently and each stays bit-identical to itself. */
typedef struct wc_carry {
    int teleport;               /* 1: x <- dT x; v, dv <- dT.R (v, dv); BDF2's history dropped */
    wc_xform dT;
    int rotated;                /* inertia: x <- p0 + Rc (x - p0), v <- V0 + Rc (v - V0), dv <- Rc dv
                                   (BDF2's x_prev and v_prev as x and v when valid) */
    double Rc[9], p0[3], V0[3];
    int linear;                 /* inertia, after the rotation: v += clin dV (BDF2's history as if
                                   the cloth had always moved that much faster: v_prev += clin dV,
                                   x_prev -= hist_h clin dV) */
    double clin, dV[3];
} wc_carry;

/* Host-order positions and normals (either may be absent) of every host vertex, in world space
 * or in object space (cloth_output.c). Float arrays, or the host's GL buffer objects (names of
 * the host's current context, at byte offsets, 3 floats per vertex). */
typedef struct wc_output_request {
    int to_object;              /* 1: object space (T^-1 x / unit_scale), 0: world */
    float* positions;           /* (n_host x 3) or NULL */
    float* normals;
    unsigned position_buffer;   /* GL buffer names or 0 (write_gl only) */
    unsigned normal_buffer;
    size_t position_offset, normal_offset;   /* bytes */
} wc_output_request;

/* A deforming body's vertices in a host GL buffer object (a name of the host's current context):
 * n vertices of 3 floats, vertex i at byte offset + i * stride. */
typedef struct wc_gl_vertex_source {
    unsigned buffer;
    size_t offset, stride;      /* bytes: multiples of 4, stride >= 12 */
    int n;
} wc_gl_vertex_source;

/* What a backend did with a body's vertices from a host GL buffer (read_gl). */
typedef struct wc_gl_vertex_result {
    int taken;                  /* 0: read into the caller's floats; 1: kept on the device as the body's
                                   frame end (the collider on_device, mesh_collider.h), nothing read */
    int bad_vertex;             /* taken: -1, or the first vertex whose coordinates are not finite or
                                   reach 1e30 (nothing changed; its 3 floats in bad) */
    int moves;                  /* taken, no bad vertex: 1 when the new frame end differs from the
                                   body's frame start on the device (any bit), so the body moves this
                                   frame (the collider's device_moves) */
    float bad[3];
} wc_gl_vertex_result;

/* Statistics of a backend's cloth (zero where a backend has none). */
typedef struct wc_backend_stats {
    size_t device_bytes;        /* device memory held by the cloth */
    long long passes;           /* device passes run since creation */
} wc_backend_stats;

typedef struct wc_cloth_backend {
    const char* name;           /* "CPU", "GPU" */
    int mirror;                 /* 1: the state's particle arrays are a mirror (see the top) */
    int concurrent;             /* 1: different cloths of a device may step at once on different
                                   threads (nothing shared between them); 0: one at a time */

    /* ---- the device, per context ---- */
    /* Make the device (*out; NULL where a backend needs none). With only_hardware and a software
     * device: WC_OK, *out NULL, *software 1, and info its renderer's name; otherwise info
     * receives a description, or the failure. */
    wc_status (*device_create)(const wc_device_desc* desc, void** out, int* software, char* info, size_t info_len);
    /* Release it (NULL: nothing). Not WC_OK (d says why) when its objects had to be left to the
     * host's GL context; the memory is freed either way. */
    wc_status (*device_destroy)(void* device, wc_diag* d);
    void (*defaults)(const void* device, const wc_defaults_query* q, wc_backend_defaults* out);
    /* A group of operations on the device's cloths. A failed begin needs no end. */
    wc_status (*begin)(void* device, wc_diag* d);
    void (*end)(void* device);

    /* Whether create would take a cloth of q: WC_OK, or create's refusal (WC_ERROR_UNSUPPORTED
     * and its message) of what the backend lacks. No device work, nothing changes; what only the
     * device can tell (its texture limits, GL errors) stays create's to find. Outside begin/end. */
    wc_status (*supports)(const void* device, const wc_backend_query* q, wc_diag* d);

    /* ---- one cloth (c->device, c->sim); inside begin/end unless said otherwise ---- */
    /* Take the built cloth to the backend (c->sim), refusing what the backend lacks with
     * WC_ERROR_UNSUPPORTED and a message naming it. Outside begin/end. */
    wc_status (*create)(struct wc_cloth* c, wc_diag* d);
    /* Release c->sim; not WC_OK as device_destroy. Outside begin/end. */
    wc_status (*destroy)(struct wc_cloth* c, wc_diag* d);
    /* The frame on the backend: wc_step_frame's contract. */
    wc_status (*step_frame)(struct wc_cloth* c, double dt, wc_step_stats* st, wc_diag* d);
    /* The device's part of the whole-frame backup, and its restore (which leaves the mirror
     * holding the restored particles). */
    void (*backup)(struct wc_cloth* c);
    void (*restore_backup)(struct wc_cloth* c);
    void (*carry)(struct wc_cloth* c, const wc_carry* k);
    /* The mirror from the device (x, v, dv, contacts; exact) and the device from the mirror. */
    wc_status (*download)(struct wc_cloth* c, wc_diag* d);
    wc_status (*upload)(struct wc_cloth* c, wc_diag* d);
    /* A bound on every |coordinate| of the positions (+inf: none known, or one is not finite). */
    double (*max_abs)(struct wc_cloth* c);
    /* Positions and normals into r's float arrays. */
    wc_status (*output)(struct wc_cloth* c, const wc_output_request* r, wc_diag* d);
    /* Into r's GL buffers (checked first: names, sizes, overlap). Outside begin/end. */
    wc_status (*write_gl)(struct wc_cloth* c, const wc_output_request* r, wc_diag* d);
    void (*stats)(const struct wc_cloth* c, wc_backend_stats* out);
    /* Mesh collider `index`'s next frame end from src, the buffer checked first (its name, its
     * size): kept on the device where the backend moves bodies there (res->taken; checked there,
     * a bad vertex reported in res with nothing changed), else read into out (src->n x 3 floats);
     * backends without the host's GL context refuse it. Outside begin/end. */
    wc_status (*read_gl)(struct wc_cloth* c, int index, const wc_gl_vertex_source* src, float* out,
                         wc_gl_vertex_result* res, wc_diag* d);
    /* Core's copy of every body kept on the device (read_gl's taken ones: from, to; a body whose
     * substeps only the device computes, substep_on_device: its substep arrays at from) brought
     * back and each body handed back to the host (on_device and substep_on_device 0). Core calls
     * it before it reads or writes a body: the snapshot, the collision check, a host's array, a
     * rigid transform, a teleport or reset. Inside begin/end. */
    void (*mesh_pull)(struct wc_cloth* c);
} wc_cloth_backend;

/* Core's CPU backend (cloth_cpu.c). Below WC_CPU_IC0_BELOW particles its default preconditioner
 * is block IC(0) with every Newton solve to the tolerance (forcing 0), above it the multigrid with
 * the first solve to 1e-2; below WC_CPU_LOOSE_BELOW particles backward Euler's tolerance is 1e-3,
 * else 1e-4 (measured to 4,096 particles; the 30k dance kept 1e-4: docs/bench/precond_by_size.md). */
#define WC_CPU_IC0_BELOW 800
#define WC_CPU_LOOSE_BELOW 5000
extern const wc_cloth_backend wc_cloth_cpu;

#endif
