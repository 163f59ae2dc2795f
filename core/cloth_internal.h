/* What the cloth's own files (cloth*.c) call of each other; not for the cloth's callers. */
#ifndef WEFT_CORE_CLOTH_INTERNAL_H
#define WEFT_CORE_CLOTH_INTERNAL_H
#include "cloth.h"

/* ---- cloth_attach.c ---- */
/* Bind as wc_cloth_set_attachments, to the state's positions as they are (no download). */
wc_status wc_cloth_bind(wc_cloth* c, const wc_cloth_attachment_def* a, int n, const char* what, wc_diag* d);
/* Pin targets from the given bone transforms into c->pins (count c->n_pins). */
void wc_cloth_pin_targets(const wc_cloth* c, const wc_xform* bones);

/* ---- cloth_frame.c ---- */
/* wc_cloth_step's frame inside a begin/end the caller holds (a batch's group: cloth_batch.c). */
wc_status wc_cloth_step_grouped(wc_cloth* c, const wc_cloth_frame* fr, wc_step_stats* st, wc_diag* d);

/* ---- cloth_colliders.c ---- */
/* Allocate and place the analytic colliders of the def (at rest) and give them to the state. */
wc_status wc_cloth_build_colliders(wc_cloth* c, const wc_cloth_collider_def* defs, int n, wc_diag* d);
/* World colliders from the shapes and the given transforms into c->world_colliders, with
 * velocity (origin(next) - origin(prev)) / dt, or zero when dt <= 0. */
void wc_cloth_place_colliders(const wc_cloth* c, const wc_xform* next, const wc_xform* prev, double dt);

/* ---- cloth_mesh.c ---- */
/* Import and create the def's mesh colliders and attach them to the state. */
wc_status wc_cloth_build_mesh_colliders(wc_cloth* c, const wc_cloth_mesh_def* defs, int n, wc_diag* d);
void wc_cloth_free_mesh_colliders(wc_cloth* c);
/* A frame's targets: colliders without new vertices get transform x rest (the frame's transform,
 * or the last one); jump (TELEPORT / RESET): from = to, no motion across the frame. A target the
 * state refuses is logged through d's logger (a warning) and the collider stays. With transforms
 * or a jump the caller has brought the bodies on a device back first (mesh_pull). */
void wc_cloth_mesh_frame(wc_cloth* c, const float* transforms, int jump, const wc_diag* d);
/* After a successful frame: the transforms become current, pending flags clear. */
void wc_cloth_mesh_frame_done(wc_cloth* c);

/* ---- cloth_output.c ---- */
/* 1 when every host vertex's output position, world and object space, with T as the object
 * transform, is within WC_CLOTH_MAX_COORD (and finite); else 0 with the first host vertex
 * outside and the offending value. Reads the state's positions. */
int wc_cloth_outputs_in_range(const wc_cloth* c, const wc_xform* T, int* vertex, double* value);
/* 1 when a bound M on every |world coordinate| of the particles proves the same (the unused
 * host vertices checked exactly); 0 when it cannot. */
int wc_cloth_outputs_bounded(const wc_cloth* c, const wc_xform* T, double M);
/* Host-order positions and normals of r's float arrays from the state's positions (the CPU's
 * output; normals use c->scratch). */
void wc_cloth_host_vertices(wc_cloth* c, const wc_output_request* r);

/* ---- cloth_snapshot.c ---- */
/* The snapshot's size for the cloth's attachments and pins (c->n_pins, before the state holds
 * them), and the model's fingerprint. */
size_t wc_cloth_snapshot_measure(wc_cloth* c);
uint64_t wc_cloth_fingerprint(const wc_cloth* c);
/* The whole-frame backup into c->backup (the device's part through the backend) and its
 * restore. Inside the backend's begin/end. */
void wc_cloth_backup(wc_cloth* c);
void wc_cloth_rollback(wc_cloth* c);

/* ---- the device's mirror around one transfer (cloth_backend.h "The mirror") ---- */
static inline wc_status wc_cloth_download(wc_cloth* c, wc_diag* d) {
    wc_status st = c->backend->begin(c->device, d);
    if (st != WC_OK) return st;
    st = c->backend->download(c, d);
    c->backend->end(c->device);
    return st;
}

static inline wc_status wc_cloth_upload(wc_cloth* c, wc_diag* d) {
    wc_status st = c->backend->begin(c->device, d);
    if (st != WC_OK) return st;
    st = c->backend->upload(c, d);
    c->backend->end(c->device);
    return st;
}

/* The bodies kept on the device back in core (cloth_backend.h mesh_pull), outside a group: those
 * whose frame is the device's (on_device) and those whose substeps are (substep_on_device). */
static inline wc_status wc_cloth_mesh_pull(wc_cloth* c, wc_diag* d) {
    int any = 0;
    for (int k = 0; k < c->n_mesh; ++k) any |= c->mesh[k]->on_device | c->mesh[k]->substep_on_device;
    if (!any) return WC_OK;
    wc_status st = c->backend->begin(c->device, d);
    if (st != WC_OK) return st;
    c->backend->mesh_pull(c);
    c->backend->end(c->device);
    return WC_OK;
}

#endif
