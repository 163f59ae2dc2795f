/* One host frame of a cloth (wc_cloth_step).
 *
 * Everything happens inside one backend begin/end (wc_cloth_step's own, or a batch's group:
 * cloth_batch.c). The whole mutable state is first saved into the cloth's preallocated backup
 * (cloth_snapshot.c; a backend with a mirror backs its particles up on the device), so that a
 * frame failing every recovery leaves the cloth exactly as before the call. Nothing is
 * allocated.
 *
 * The object transform (T1 at the end of the frame; T0 the previous one, p its origin, R its
 * rotation) moves the simulation only through inertia, teleport and reset; the cloth itself is
 * simulated in world space.
 *  - Normal frame: V1 = (p1 - p0) / dt. When there is no history (after create, teleport or
 *    reset) V0 := V1: no linear impulse from a velocity the cloth never saw change.
 *    Angular: c = 1 - angular_inertia; dR = R1 R0^-1; Rc = rotation by c x (dR's angle) about
 *    dR's axis (Rodrigues; c = 1: dR itself, so the carry matches the host's matrices); around
 *    the old origin p0: x <- p0 + Rc (x - p0), v <- V0 + Rc (v - V0); the solver's warm start dv
 *    and the pins' start-of-frame targets are carried the same way (so a cloth carried by the
 *    object is in the same state, relative to it, as one on a resting object); so is BDF2's
 *    history (bdf2.h: x_prev as x, v_prev as v).
 *    Linear: v += (1 - linear_inertia) (V1 - V0): the cloth is given that part of the object's
 *    velocity change (a constant velocity adds nothing); BDF2's history gets it as if the cloth
 *    had always moved that much faster: v_prev += c dV, x_prev -= hist_h c dV.
 *    Defaults (1, 1): c = 0 and 1 - linear = 0, both skipped: the object transform does not
 *    touch the simulation (bit-exact).
 *  - TELEPORT: dT = T1 T0^-1 carries everything fully: x <- dT x (points), v and dv rotated by
 *    dT's rotation (velocities relative to the object kept); the pins' start targets are set to
 *    their new targets (no interpolation across the jump) and colliders get zero velocity this
 *    frame. The history is reset (V0 after the frame is 0 and unknown), and so is BDF2's: its
 *    next substep is backward Euler.
 *  - RESET: x = T1 rest (the model's rest positions are object space, metres), v = dv = 0,
 *    contacts cleared, pins start at their targets, colliders at rest, time / frame / substep
 *    accumulator, the Chebyshev rho estimate and BDF2's history reset, then the frame is
 *    stepped. RESET with TELEPORT is a RESET.
 * The carries of inertia and teleport are the backend's (wc_carry, cloth_backend.h); a reset is
 * made on the state and uploaded.
 * Attachments: the frame's transforms (or the previous ones) give the end-of-frame pin targets
 * A_i local (cloth_attach.c); pins move linearly from their start targets across the frame.
 * Colliders: world geometry from the frame's transforms (or the previous ones), velocity
 * (origin1 - origin0) / dt (cloth_colliders.c). Mesh colliders (cloth_mesh.c): end-of-frame
 * positions from wc_cloth_set_mesh_vertices, else the frame's transforms x rest, else
 * unchanged; TELEPORT / RESET put them there at once. Wind: the frame's wind replaces the air's.
 * Sleeping (state.h): the core wakes the cloth itself when the pins' targets, the colliders or
 * the wind differ from the last frame's; RESET, TELEPORT and an inertia carry (rotated, or a
 * linear velocity change given to the cloth) wake it here. With the default inertia (1, 1) the
 * object transform does not touch the simulation, so it does not wake it either.
 * After the step every host vertex's output must stay within WC_CLOTH_MAX_COORD: a backend's
 * bound on the positions proves it where it can, else the positions are checked exactly
 * (downloaded first from a device). */
#include <stdio.h>
#include <string.h>
#include "cloth_internal.h"
#include "vec3.h"

#define RESTORED " (the cloth was restored to its state before the call)"

static void reset_state(wc_cloth* c, const wc_xform* T1) {
    wc_state* s = c->state;
    const wc_model* m = &c->model;
    int n = m->n_particles;
    for (int i = 0; i < n; ++i) wc_xform_point(T1, m->rest_pos + 3 * i, s->x + 3 * i);
    memset(s->v, 0, 3 * (size_t)n * sizeof(double));
    memset(s->dv, 0, 3 * (size_t)n * sizeof(double));
    for (int i = 0; i < 2 * n; ++i) s->contacts.collider[i] = -1;
    memset(s->contacts.normal, 0, 6 * (size_t)n * sizeof(double));
    memset(s->contacts.released, 0, (size_t)n);
    s->contacts.active = 0;
    s->time = 0.0;
    s->accumulator = 0.0;
    s->frame = 0;
    s->hist_valid = 0;
    wc_solver_invalidate_rho(s->solver);
    wc_solver_invalidate_bounds(s->solver);
    wc_state_wake(s);
}

static void teleport(wc_cloth* c, const wc_xform* T1) {
    wc_carry k;
    memset(&k, 0, sizeof k);
    k.teleport = 1;
    wc_xform inv0;
    wc_xform_inverse(&c->object, &inv0);
    m3_mul(k.dT.R, T1->R, inv0.R);
    wc_xform_point(T1, inv0.t, k.dT.t);
    c->backend->carry(c, &k);
    wc_state_wake(c->state);
}

/* Inertia of a normal frame (see the top of the file); V1 and the history are handled by the
 * caller. Returns 1 with Rc when the angular carry was applied (the pins' start targets follow). */
static int inertia(wc_cloth* c, const wc_xform* T1, const double* V1, double* Rc) {
    wc_carry k;
    memset(&k, 0, sizeof k);
    v3_copy(k.p0, c->object.t);
    v3_copy(k.V0, c->object_velocity);
    double cang = 1.0 - c->settings.angular_inertia;
    if (cang != 0.0) {
        wc_xform inv;
        double dR[9];
        wc_xform_inverse(&c->object, &inv);
        m3_mul(dR, T1->R, inv.R);
        k.rotated = wc_rotation_fraction(dR, cang, k.Rc);
    }
    k.clin = 1.0 - c->settings.linear_inertia;
    if (k.clin != 0.0) {
        v3_sub(k.dV, V1, k.V0);
        k.linear = k.dV[0] != 0.0 || k.dV[1] != 0.0 || k.dV[2] != 0.0;
    }
    if (k.rotated || k.linear) c->backend->carry(c, &k);
    if (k.linear) wc_state_wake(c->state);
    if (k.rotated) wc_state_wake(c->state);
    memcpy(Rc, k.Rc, sizeof k.Rc);
    return k.rotated;
}

/* The frame's inputs after the carry: pins, colliders, mesh colliders, wind. */
static wc_status set_inputs(wc_cloth* c, const wc_cloth_frame* fr, int jump, int rotated, const double* Rc,
                            wc_diag* d) {
    wc_state* s = c->state;
    wc_cloth_pin_targets(c, c->attachment_next);
    wc_status st = wc_state_set_pins(s, c->pins, c->n_pins, d);
    if (st != WC_OK) return st;
    if (jump) {
        for (int k = 0; k < c->n_pins; ++k) v3_copy(s->pin_from + 3 * k, s->pins[k].target);
    } else if (rotated) {
        wc_rotate_points(s->pin_from, c->n_pins, Rc, c->object.t);
    }
    wc_cloth_place_colliders(c, c->collider_next, c->collider_xf, jump ? 0.0 : fr->dt);
    st = wc_state_set_colliders(s, c->world_colliders, c->n_colliders, d);
    if (st != WC_OK) return st;
    wc_cloth_mesh_frame(c, fr->mesh_collider_transforms, jump, d);
    if (fr->wind) v3_copy(s->def.air.wind, fr->wind);
    return WC_OK;
}

/* The outputs' range after the step, with T1 the object's transform. */
static wc_status check_range(wc_cloth* c, const wc_xform* T1, wc_diag* d) {
    if (wc_cloth_outputs_bounded(c, T1, c->backend->max_abs(c))) return WC_OK;
    /* the bound could exceed the limit: the exact check on the positions */
    wc_status st = c->backend->download(c, d);
    if (st != WC_OK) return st;
    int vertex = -1;
    double value = 0.0;
    if (wc_cloth_outputs_in_range(c, T1, &vertex, &value)) return WC_OK;
    return wc_fail(d, WC_ERROR_STEP_FAILED,
                   "the step took host vertex %d to a coordinate of %g, beyond the %g the float outputs hold", vertex,
                   value, WC_CLOTH_MAX_COORD);
}

/* 1 when core moves a body on a device this frame: a jump, or a rigid transform for one whose
   host gave no vertices this frame. */
static int bodies_come_back(const wc_cloth* c, const wc_cloth_frame* fr) {
    if (fr->reset || fr->teleport) return 1;
    if (!fr->mesh_collider_transforms) return 0;
    for (int k = 0; k < c->n_mesh; ++k)
        if (c->mesh[k]->on_device && !c->mesh_pending[k]) return 1;
    return 0;
}

/* The frame inside the backend's begin/end (wc_cloth_step, and a batch's group). */
wc_status wc_cloth_step_grouped(wc_cloth* c, const wc_cloth_frame* fr, wc_step_stats* ss, wc_diag* d) {
    memset(ss, 0, sizeof *ss);
    if (!(fr->dt > 0.0) || fr->dt > c->settings.max_frame_time)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "dt = %g s must be in (0, max_frame_time = %g s]", fr->dt,
                       c->settings.max_frame_time);
    const wc_cloth_backend* b = c->backend;
    wc_status st = WC_OK;
    /* core moves the bodies itself this frame (rigid transforms, a jump): those on a device come
       back first, before the frame's backup holds them */
    if (bodies_come_back(c, fr)) b->mesh_pull(c);
    wc_cloth_backup(c);
    const double dt = fr->dt;
    const int reset = fr->reset != 0;
    const int jump = reset || fr->teleport;

    wc_xform T1 = c->object;
    if (fr->object_transform) wc_xform_from_floats(&T1, fr->object_transform);
    for (int i = 0; i < c->n_attachments; ++i) {
        if (fr->attachment_transforms) wc_xform_from_floats(&c->attachment_next[i], fr->attachment_transforms + 16 * i);
        else c->attachment_next[i] = c->attachment_xf[i];
    }
    for (int i = 0; i < c->n_colliders; ++i) {
        if (fr->collider_transforms) wc_xform_from_floats(&c->collider_next[i], fr->collider_transforms + 16 * i);
        else c->collider_next[i] = c->collider_xf[i];
    }

    double V1[3], Rc[9];
    int rotated = 0;
    for (int k = 0; k < 3; ++k) V1[k] = (T1.t[k] - c->object.t[k]) / dt;
    if (reset) {
        reset_state(c, &T1);
        st = b->upload(c, d);   /* the mirror holds the whole reset state: sent as is */
    } else if (jump) {
        teleport(c, &T1);
    } else {
        if (c->no_history) v3_copy(c->object_velocity, V1);
        rotated = inertia(c, &T1, V1, Rc);
    }
    if (st == WC_OK) st = set_inputs(c, fr, jump, rotated, Rc, d);
    if (st == WC_OK) st = b->step_frame(c, dt, ss, d);
    if (st == WC_OK) st = check_range(c, &T1, d);
    if (st != WC_OK) {
        wc_cloth_rollback(c);
        size_t used = strlen(d->message);
        snprintf(d->message + used, sizeof d->message - used, "%s", RESTORED);
        return st;
    }

    c->object = T1;
    if (jump) v3_zero(c->object_velocity);
    else v3_copy(c->object_velocity, V1);
    c->no_history = jump;
    for (int i = 0; i < c->n_attachments; ++i) c->attachment_xf[i] = c->attachment_next[i];
    for (int i = 0; i < c->n_colliders; ++i) c->collider_xf[i] = c->collider_next[i];
    wc_cloth_mesh_frame_done(c);
    return WC_OK;
}

wc_status wc_cloth_step(wc_cloth* c, const wc_cloth_frame* fr, wc_step_stats* ss, wc_diag* d) {
    memset(ss, 0, sizeof *ss);
    if (!(fr->dt > 0.0) || fr->dt > c->settings.max_frame_time)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "dt = %g s must be in (0, max_frame_time = %g s]", fr->dt,
                       c->settings.max_frame_time);
    wc_status st = c->backend->begin(c->device, d);
    if (st != WC_OK) return st;
    st = wc_cloth_step_grouped(c, fr, ss, d);
    c->backend->end(c->device);
    return st;
}
