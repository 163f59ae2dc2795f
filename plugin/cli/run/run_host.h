/* `weft run` as a host of the public API (weft/weft.h): a scene becomes a context, one cloth
 * (mesh, material, settings, pins as attachments, colliders in the API's local conventions),
 * and every frame the transforms a host would pass (object, attachments, colliders) computed
 * from the scene's motions. The scene (loaded by the CLI's own parser) is read; nothing here
 * calls the core: the simulation is the library's. */
#ifndef WEFT_CLI_RUN_HOST_H
#define WEFT_CLI_RUN_HOST_H
#include <stddef.h>

#include "scene.h"
#include "weft/weft.h"

typedef struct run_host {
    weft_context* ctx;
    weft_cloth cloth;
    weft_cloth_info info;
    double object_rest[16];     /* the object's placement at creation */
    int n_attachments;          /* = scene pin groups */
    float* attachment_xf;       /* (n_attachments x 16) this frame's */
    int n_colliders;
    double* collider_rest;      /* (n_colliders x 16) placements at rest */
    float* collider_xf;         /* (n_colliders x 16) this frame's */
    int n_mesh;                 /* = scene mesh colliders */
    float* mesh_xf;             /* (n_mesh x 16) this frame's transforms */
    float* mesh_verts;          /* (largest n_verts x 3) this frame's vertices (vertex animation) */
    float object_xf[16];        /* this frame's */
    double jump[3];             /* m: the teleports so far */
    int next_teleport;          /* index in scene.object.teleports */
    float* positions;           /* (info.n_vertices x 3) world positions after the last frame */
    char log_error[512];        /* the last ERROR the library logged (context creation) */
} run_host;

typedef struct run_host_opts {
    weft_backend backend;
    int threads;                /* 0: OpenMP's default */
} run_host_opts;

/* Create the context and the cloth for s (scene file name `name` for messages) and read the
 * rest positions into h->positions. On failure everything is released and msg holds one line
 * "NAME: what failed: the library's message". */
weft_status run_host_create(run_host* h, const scene* s, const run_host_opts* opts, const char* name, char* msg,
                            size_t cap);
void run_host_destroy(run_host* h);

/* The weft_frame of frame `frame` (1-based, ending at frame dt seconds): dt, and the object,
 * attachment and collider transforms of the scene's motions and teleports at that time. The
 * arrays it points to live in h until the next call. Mesh colliders animated by file frames get
 * their vertices (weft_cloth_set_mesh_collider_vertices) here; a failure there is reported by
 * run_host_error after the step that follows refuses nothing (the vertices are checked finite at
 * load, so it does not happen). */
weft_frame run_host_frame(run_host* h, const scene* s, int frame, double dt);

/* Read the cloth's world positions into h->positions. */
weft_status run_host_read_positions(run_host* h);

/* The library's message for the last failure on h's context. */
const char* run_host_error(const run_host* h);

#endif
