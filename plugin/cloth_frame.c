/* weft_cloth_step: one host frame.
 *
 * Validation first (nothing changes on a refused call). Then the whole mutable state is saved into
 * the cloth's preallocated backup (snapshot.c, no checksum), so that a step failing every
 * recovery leaves the cloth exactly as before the call (STEP_FAILED). Nothing is allocated.
 *
 * The object transform (fr->object_transform, T1; T0 the previous one, p its origin, R its
 * rotation) moves the simulation only through inertia, teleport and reset; the cloth itself is
 * simulated in world space.
 *  - Normal frame: V1 = (p1 - p0) / dt. When there is no history (after create, teleport or
 *    reset) V0 := V1: no linear impulse from a velocity the cloth never saw change.
 *    Angular: c = 1 - angular_inertia; dR = R1 R0^-1; Rc = rotation by c x (dR's angle) about
 *    dR's axis (Rodrigues; c = 1: dR itself, so the carry matches the host's matrices); around
 *    the old origin p0: x <- p0 + Rc (x - p0), v <- V0 + Rc (v - V0); the solver's warm start dv and the pins' start-of-frame targets are
 *    carried the same way (so a cloth carried by the object is in the same state, relative to
 *    it, as one on a resting object); so is BDF2's history (core/bdf2.h: x_prev as x, v_prev as v).
 *    Linear: v += (1 - linear_inertia) (V1 - V0): the cloth is given that part of the object's
 *    velocity change (a constant velocity adds nothing); BDF2's history gets it as if the cloth
 *    had always moved that much faster: v_prev += c dV, x_prev -= hist_h c dV.
 *    Defaults (1, 1): c = 0 and 1 - linear = 0, both skipped: the object transform does not touch
 *    the simulation (bit-exact).
 *  - TELEPORT: dT = T1 T0^-1 carries everything fully: x <- dT x (points), v and dv rotated by
 *    dT's rotation (velocities relative to the object kept); the pins' start targets are set to
 *    their new targets (no interpolation across the jump) and colliders get zero velocity this
 *    frame. The history is reset (V0 after the frame is 0 and unknown), and so is BDF2's: its next
 *    substep is backward Euler.
 *  - RESET: x = T1 rest (the model's rest positions are object space, metres), v = dv = 0,
 *    contacts cleared, pins start at their targets, colliders at rest, time / frame / substep
 *    accumulator, the Chebyshev rho estimate and BDF2's history reset, then the frame is stepped. RESET with
 *    TELEPORT is a RESET.
 * Attachments: fr->attachment_transforms (or the previous ones) give the end-of-frame pin
 * targets A_i local (attach.c); pins move linearly from their start targets across the frame.
 * Colliders: world geometry from fr->collider_transforms (or the previous ones), velocity
 * (origin1 - origin0) / dt (colliders.c). Mesh colliders (mesh_colliders.c): end-of-frame
 * positions from weft_cloth_set_mesh_collider_vertices, else fr->mesh_collider_transforms x
 * rest, else unchanged; TELEPORT / RESET put them there at once. Wind: fr->wind replaces the air's wind.
 * Sleeping (core/state.h): the core wakes the cloth itself when the pins' targets, the colliders
 * or the wind differ from the last frame's; RESET, TELEPORT and an inertia carry (rotated, or a
 * linear velocity change given to the cloth) wake it here. With the default inertia (1, 1) the
 * object transform does not touch the simulation, so it does not wake it either.
 * GPU cloths (gpu_glue.c): the same validation and book-keeping; the backup is the textures'
 * (wg_sim_backup) plus the book-keeping only (no read-back); inertia and teleport run as one rigid
 * pass on the GPU (wg_sim_transform; the solver's warm start turns with the velocities), RESET sets the
 * CPU mirror and uploads it; the range check takes the GPU's max |coordinate| as a bound and reads
 * the positions back only when that bound could pass WA_MAX_OUTPUT_COORD. All of it inside one
 * wa_gl_begin/end. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "api_internal.h"
#include "clock.h"
#include "vec3.h"

#define WA_FRAME_FLAGS ((uint32_t)(WEFT_FRAME_TELEPORT | WEFT_FRAME_RESET))

static weft_status validate(weft_context* ctx, const wa_cloth* c, const weft_frame* fr, const char* fn) {
    char why[160];
    weft_status st;
    if (!fr) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: fr is NULL", fn);
    if (!isfinite(fr->dt)) return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: fr->dt is %s", fn, isnan(fr->dt) ? "NaN" : "Inf");
    if (!(fr->dt > 0.0) || fr->dt > c->max_frame_time)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: fr->dt = %g s must be in (0, max_frame_time = %g s]", fn,
                       fr->dt, c->max_frame_time);
    if (fr->flags & ~WA_FRAME_FLAGS)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: fr->flags 0x%x has unknown bits 0x%x", fn,
                       (unsigned)fr->flags, (unsigned)(fr->flags & ~WA_FRAME_FLAGS));
    if (fr->object_transform && (st = wa_check_transform(fr->object_transform, why, sizeof why)) != WEFT_OK)
        return wa_fail(ctx, st, "%s: fr->object_transform%s", fn, why);
    if (fr->attachment_transforms)
        for (int i = 0; i < c->n_attachments; ++i)
            if ((st = wa_check_transform(fr->attachment_transforms + 16 * i, why, sizeof why)) != WEFT_OK)
                return wa_fail(ctx, st, "%s: fr->attachment_transforms (attachment %d, elements %d..%d)%s", fn, i,
                               16 * i, 16 * i + 15, why);
    if (fr->collider_transforms)
        for (int i = 0; i < c->n_colliders; ++i)
            if ((st = wa_check_transform(fr->collider_transforms + 16 * i, why, sizeof why)) != WEFT_OK)
                return wa_fail(ctx, st, "%s: fr->collider_transforms (collider %d, elements %d..%d)%s", fn, i, 16 * i,
                               16 * i + 15, why);
    if ((st = wa_check_mesh_frame(ctx, c, fr, fn)) != WEFT_OK) return st;
    if (fr->wind)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(fr->wind[k]))
                return wa_fail(ctx, WEFT_ERROR_NONFINITE, "%s: fr->wind[%d] is %s", fn, k, isnan(fr->wind[k]) ? "NaN" : "Inf");
    return WEFT_OK;
}

/* x <- p0 + R (x - p0) for n points (R row-major) */
static void rotate_points(double* x, int n, const double* R, const double* p0) {
    for (int i = 0; i < n; ++i) {
        double d[3], o[3];
        v3_sub(d, x + 3 * i, p0);
        m3_mulv(o, R, d);
        v3_add(x + 3 * i, p0, o);
    }
}

static void rotate_vectors(double* v, int n, const double* R) {
    for (int i = 0; i < n; ++i) {
        double o[3];
        m3_mulv(o, R, v + 3 * i);
        v3_copy(v + 3 * i, o);
    }
}

static void reset_state(wa_cloth* c, const wa_xform* T1) {
    wc_state* s = c->state;
    const wc_model* m = &c->model;
    int n = m->n_particles;
    for (int i = 0; i < n; ++i) wa_xform_point(T1, m->rest_pos + 3 * i, s->x + 3 * i);
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
    wc_state_wake(s);
}

static void teleport_state(wa_cloth* c, const wa_xform* T1) {
    wc_state* s = c->state;
    int n = c->model.n_particles;
    wa_xform inv0, dT;
    wa_xform_inverse(&c->object, &inv0);
    m3_mul(dT.R, T1->R, inv0.R);
    wa_xform_point(T1, inv0.t, dT.t);
    if (c->gpu) {   /* on the GPU: x' = dT x, v' = dT.R v */
        const double zero[3] = {0.0, 0.0, 0.0};
        wa_gpu_transform(c, dT.R, dT.t, dT.R, zero);
        wc_state_wake(s);
        return;
    }
    for (int i = 0; i < n; ++i) wa_xform_point(&dT, s->x + 3 * i, s->x + 3 * i);
    rotate_vectors(s->v, n, dT.R);
    rotate_vectors(s->dv, n, dT.R);
    s->hist_valid = 0;   /* BDF2 restarts with a backward-Euler substep */
    wc_state_wake(s);
}

/* Inertia of a normal frame (see the top of the file); V1 and the history are handled by the
 * caller. Returns 1 with Rc when the angular carry was applied (the pins' start targets follow). */
static int inertia(wa_cloth* c, const wa_xform* T1, const double* V1, double* Rc) {
    wc_state* s = c->state;
    int n = c->model.n_particles, rotated = 0;
    const double* p0 = c->object.t;
    const double* V0 = c->object_velocity;
    double cang = 1.0 - c->angular_inertia;
    if (cang != 0.0) {
        wa_xform inv;
        double dR[9];
        wa_xform_inverse(&c->object, &inv);
        m3_mul(dR, T1->R, inv.R);
        rotated = wa_rotation_fraction(dR, cang, Rc);
        if (rotated && !c->gpu) {
            int hist = s->hist_valid;
            rotate_points(s->x, n, Rc, p0);
            if (hist) rotate_points(s->x_prev, n, Rc, p0);
            for (int i = 0; i < n; ++i) {
                double d[3], o[3];
                v3_sub(d, s->v + 3 * i, V0);
                m3_mulv(o, Rc, d);
                v3_add(s->v + 3 * i, V0, o);
                if (!hist) continue;
                v3_sub(d, s->v_prev + 3 * i, V0);
                m3_mulv(o, Rc, d);
                v3_add(s->v_prev + 3 * i, V0, o);
            }
            rotate_vectors(s->dv, n, Rc);
        }
    }
    double clin = 1.0 - c->linear_inertia, dV[3] = {0.0, 0.0, 0.0};
    int linear = 0;
    if (clin != 0.0) {
        v3_sub(dV, V1, V0);
        linear = dV[0] != 0.0 || dV[1] != 0.0 || dV[2] != 0.0;
        if (linear && !c->gpu) {
            for (int i = 0; i < n; ++i) v3_axpy(s->v + 3 * i, clin, dV);
            if (s->hist_valid)
                for (int i = 0; i < n; ++i) {
                    v3_axpy(s->v_prev + 3 * i, clin, dV);
                    v3_axpy(s->x_prev + 3 * i, -clin * s->hist_h, dV);
                }
        }
    }
    if (c->gpu && (rotated || linear)) {
        /* one pass: x' = Rc x + (p0 - Rc p0), v' = Rc v + (V0 - Rc V0) + clin dV */
        double Rx[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tx[3] = {0.0, 0.0, 0.0}, dv[3] = {0.0, 0.0, 0.0};
        if (rotated) {
            double q[3];
            memcpy(Rx, Rc, sizeof Rx);
            m3_mulv(q, Rc, p0);
            v3_sub(tx, p0, q);
            m3_mulv(q, Rc, V0);
            v3_sub(dv, V0, q);
        }
        if (linear) v3_axpy(dv, clin, dV);
        wa_gpu_transform(c, Rx, tx, Rx, dv);
    }
    if (linear) wc_state_wake(s);
    if (rotated) wc_state_wake(s);
    return rotated;
}

static void fill_stats(weft_frame_stats* o, const wc_step_stats* st, const wc_state* s, double ms_total) {
    memset(o, 0, sizeof *o);
    o->ms_total = ms_total;
    o->ms_forces = st->ms.forces;
    o->ms_assemble = st->ms.assemble;
    o->ms_solve = st->ms.solve;
    o->ms_collide = st->ms.collide;
    o->ms_integrate = st->ms.integrate;
    o->substeps = st->substeps;
    o->iterations = st->iterations;
    o->solves = st->solves;
    o->ms_precond = st->precond_ms;
    o->max_iterations = st->max_iterations;
    o->residual = st->residual;
    o->not_converged = st->not_converged;
    o->solver = (weft_solver)st->solver;
    o->rollbacks = st->rollbacks;
    o->halvings = st->halvings;
    o->direct_fallbacks = st->direct_fallbacks;
    o->failures = st->failures;
    o->contacts = st->contacts;
    o->max_strain = st->max_strain;
    o->kinetic_energy = st->kinetic_energy;
    o->time = s->time;
    o->frame = s->frame;
    o->asleep = st->asleep;
    o->fell_asleep = st->fell_asleep;
    o->woke = st->woke;
    o->self_impacts = st->self_impacts;
    o->self_zones = st->self_zones;
    o->self_unresolved = st->self_unresolved;
    o->ms_self_collide = st->ms.self_collide;
}

weft_status weft_cloth_step(weft_context* ctx, weft_cloth cloth, const weft_frame* fr, weft_frame_stats* stats) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_step";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    double t_start = wc_now_ms();
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    weft_status st = validate(ctx, c, fr, fn);
    if (st != WEFT_OK) return st;

    wc_state* s = c->state;
    if (c->gpu) {
        /* GPU cloth: the textures are backed up on the GPU, the book-keeping here; every GL call
         * of the frame happens inside this one wa_gl_begin/end */
        st = wa_gl_begin(ctx, fn);
        if (st != WEFT_OK) return st;
        wa_snapshot_write_small(c, c->backup);
        wa_gpu_backup(c);
    } else {
        wa_snapshot_write(c, c->backup, 0);
    }
    const double dt = fr->dt;
    const int reset = (fr->flags & WEFT_FRAME_RESET) != 0;
    const int teleport = !reset && (fr->flags & WEFT_FRAME_TELEPORT) != 0;

    wa_xform T1 = c->object;
    if (fr->object_transform) wa_xform_from_floats(&T1, fr->object_transform);
    for (int i = 0; i < c->n_attachments; ++i) {
        if (fr->attachment_transforms) wa_xform_from_floats(&c->attachment_next[i], fr->attachment_transforms + 16 * i);
        else c->attachment_next[i] = c->attachment_xf[i];
    }
    for (int i = 0; i < c->n_colliders; ++i) {
        if (fr->collider_transforms) wa_xform_from_floats(&c->collider_next[i], fr->collider_transforms + 16 * i);
        else c->collider_next[i] = c->collider_xf[i];
    }

    double V1[3], Rc[9];
    int rotated = 0;
    for (int k = 0; k < 3; ++k) V1[k] = (T1.t[k] - c->object.t[k]) / dt;
    wc_diag d = wa_core_diag(ctx);
    st = WEFT_OK;
    if (reset) {
        reset_state(c, &T1);
        if (c->gpu) {   /* the mirror holds the whole reset state: sent as is */
            st = wa_gpu_transfer(c, 1, &d);
        }
    } else if (teleport) {
        teleport_state(c, &T1);
    } else {
        if (c->no_history) v3_copy(c->object_velocity, V1);
        rotated = inertia(c, &T1, V1, Rc);
    }

    wa_pin_targets(c, c->attachment_next);
    if (st == WEFT_OK) st = wa_status(wc_state_set_pins(s, c->pins, c->n_pins, &d));
    if (st == WEFT_OK) {
        if (reset || teleport) {
            for (int k = 0; k < c->n_pins; ++k) v3_copy(s->pin_from + 3 * k, s->pins[k].target);
        } else if (rotated) {
            rotate_points(s->pin_from, c->n_pins, Rc, c->object.t);
        }
        wa_world_colliders(c, c->collider_next, c->collider_xf, (reset || teleport) ? 0.0 : dt);
        st = wa_status(wc_state_set_colliders(s, c->wc_colliders, c->n_colliders, &d));
        if (st == WEFT_OK) wa_mesh_frame(c, fr, reset || teleport);
    }
    if (st == WEFT_OK && fr->wind) v3_copy(s->def.air.wind, fr->wind);
    wc_step_stats ss;
    memset(&ss, 0, sizeof ss);
    if (st == WEFT_OK) st = c->gpu ? wa_gpu_step_frame(c, dt, &ss, &d) : wc_step_frame(s, dt, &ss, &d);
    int bad_vertex = -1;
    double bad_value = 0.0;
    if (st == WEFT_OK) {
        weft_status rst = WEFT_OK;
        int in_range = c->gpu ? wa_gpu_outputs_in_range(c, &T1, &bad_vertex, &bad_value, &rst, &d)
                              : wa_outputs_in_range(c, &T1, &bad_vertex, &bad_value);
        if (rst != WEFT_OK)
            st = rst;
        else if (!in_range)
            st = wa_status(wc_fail(&d, WC_ERROR_STEP_FAILED,
                         "the step took host vertex %d to a coordinate of %g, beyond the %g the float outputs hold",
                         bad_vertex, bad_value, WA_MAX_OUTPUT_COORD));
    }
    if (st != WEFT_OK) {
        if (c->gpu) {
            /* the textures back; the mirror refreshed from them (the sleep state's strain is
             * measured on it), then the book-keeping */
            wa_gpu_restore_backup(c);
            wc_diag dd = wa_core_diag(ctx);
            (void)wa_gpu_transfer(c, 0, &dd);
            wa_snapshot_apply_small(c, c->backup);
            wa_gl_end(ctx);
        } else {
            wa_snapshot_apply(c, c->backup);
        }
        return wa_fail(ctx, st, "%s: %s (the cloth was restored to its state before the call)", fn, d.message);
    }
    if (c->gpu) wa_gl_end(ctx);

    c->object = T1;
    if (reset || teleport) v3_zero(c->object_velocity);
    else v3_copy(c->object_velocity, V1);
    c->no_history = reset || teleport;
    for (int i = 0; i < c->n_attachments; ++i) c->attachment_xf[i] = c->attachment_next[i];
    for (int i = 0; i < c->n_colliders; ++i) c->collider_xf[i] = c->collider_next[i];
    wa_mesh_frame_done(c);
    if (stats) fill_stats(stats, &ss, s, wc_now_ms() - t_start);
    return wa_ok(ctx);
}
