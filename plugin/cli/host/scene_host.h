/* A scene (scene/scene.h) run as a host of the public API runs it: a context (or a borrowed
 * one), one cloth (the scene's mesh by path or as host arrays, its cloth def, its pins as
 * attachments, its colliders placed in the API's local conventions, its mesh colliders), and
 * every frame the transforms a host would pass (object, attachments, colliders, mesh colliders)
 * computed from the scene's motions and teleports. The simulation is the library's: `weft run`
 * and `weft bench` step it with weft_cloth_step and read it with weft.h's calls. */
#ifndef WEFT_CLI_SCENE_HOST_H
#define WEFT_CLI_SCENE_HOST_H
#include <stddef.h>

#include "scene.h"
#include "weft/weft.h"

typedef struct scene_host {
    weft_context* ctx;
    int own_ctx;                /* 1: made here (destroyed with the host), 0: borrowed */
    weft_cloth cloth;
    weft_cloth_info info;
    double object_rest[16];     /* the object's placement at creation */
    int n_attachments;          /* = scene pin groups */
    float* attachment_xf;       /* (n_attachments x 16) this frame's */
    int n_colliders;
    double* collider_rest;      /* (n_colliders x 16) placements at rest */
    float* collider_xf;         /* (n_colliders x 16) this frame's */
    int n_mesh;                 /* scene mesh colliders, then the opts' extra ones */
    int n_scene_mesh;           /* the scene's */
    float* mesh_xf;             /* (n_mesh x 16) this frame's transforms */
    float* mesh_verts;          /* (largest n_verts x 3) this frame's vertices (vertex animation) */
    float object_xf[16];        /* this frame's */
    double jump[3];             /* m: the teleports so far */
    int next_teleport;          /* index in scene.object.teleports */
    float* positions;           /* (info.n_vertices x 3) world positions after the last frame */
    char log_error[512];        /* the last ERROR the library logged (context creation) */
} scene_host;

typedef struct scene_host_opts {
    weft_context* ctx;          /* a context to create the cloth in (borrowed), or NULL: one is
                                   made with backend and threads */
    weft_backend backend;
    int threads;                /* 0: OpenMP's default */
    /* further mesh colliders beyond the scene's (host arrays or files), held where their
       transform puts them */
    const weft_mesh_collider_def* mesh_colliders;
    int n_mesh_colliders;
} scene_host_opts;

/* Create the context (unless borrowed) and the cloth for s (scene file name `name` for
 * messages) and read the rest positions into h->positions. On failure everything is released
 * and msg holds one line "NAME: what failed: the library's message". */
weft_status scene_host_create(scene_host* h, const scene* s, const scene_host_opts* opts, const char* name,
                              char* msg, size_t cap);
/* Destroy the cloth (and the context when made here). */
void scene_host_destroy(scene_host* h);

/* The weft_frame of frame `frame` (1-based, ending at frame dt seconds): dt, and the object,
 * attachment and collider transforms of the scene's motions and teleports at that time. The
 * arrays it points to live in h until the next call. Mesh colliders animated by file frames get
 * their vertices (weft_cloth_set_mesh_collider_vertices) here; a failure there is reported by
 * scene_host_error after the step that follows refuses nothing (the vertices are checked finite
 * at load, so it does not happen). */
weft_frame scene_host_frame(scene_host* h, const scene* s, int frame, double dt);

/* Read the cloth's world positions into h->positions. */
weft_status scene_host_read_positions(scene_host* h);

/* The library's message for the last failure on h's context. */
const char* scene_host_error(const scene_host* h);

#endif
