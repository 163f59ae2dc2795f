/* The frame driver: schedule, retries, stats and sleeping over a backend's substep (step_driver.h). */
#include "step_driver.h"
#include <math.h>
#include <string.h>
#include "clock.h"
#include "mesh_collider.h"
#include "vec3.h"

/* A substep of length h from frame fraction alpha0 to alpha1, retried on failure with halved
 * steps and then with the last-resort solver. On final failure the state is as it was. */
static wc_status robust_substep(wc_state* s, double h, double alpha0, double alpha1, double pin_energy,
                                  wc_step_stats* st, wc_diag* diag, const wc_step_ops* ops) {
    wc_diag local = {WC_OK, "", NULL, NULL}; /* a recovered failure is a warning, not the caller's error */
    ops->save(ops->user, s);
    wc_solver_type user = s->def.solver.type;
    /* the last resorts: the finest pieces (judged on all but the energy gain), then the whole
       substep at once, accepted whenever finite (a cloth under pins that jump a kilometre in a
       frame blows up in small pieces, and is merely stretched by one) */
    int tries = s->def.max_halvings + 1 + (s->def.direct_fallback ? 2 : 0);
    for (int t = 0; t < tries; ++t) {
        int last_resort = t > s->def.max_halvings;
        int finest = t == s->def.max_halvings + 1;
        int halvings = !last_resort ? t : finest ? s->def.max_halvings : 0;
        int judge = !last_resort ? WC_JUDGE_ALL : finest ? WC_JUDGE_NO_GAIN : WC_JUDGE_FINITE;
        wc_solver_type solver = last_resort ? ops->last_resort_solver : user;
        int pieces = 1 << halvings;
        if (t > 0) {
            ++st->rollbacks;
            if (halvings > 0) ++st->halvings;
            if (last_resort) ++st->direct_fallbacks;
        }
        wc_status ok = WC_OK;
        double residual = st->residual; /* a discarded try's residual (inf when it blew up) is not reported */
        for (int p = 0; p < pieces && ok == WC_OK; ++p) {
            double a1 = alpha0 + (alpha1 - alpha0) * (p + 1) / pieces;
            s->sub_alpha0 = alpha0 + (alpha1 - alpha0) * p / pieces;
            ok = ops->substep(ops->user, s, h / pieces, a1, solver, judge, pin_energy, st, &local);
        }
        if (ok == WC_OK) {
            st->substeps += pieces;
            return WC_OK;
        }
        wc_log(diag, WC_LOG_WARN, "rolled back: %s", local.message);
        st->residual = residual;
        ops->restore(ops->user, s);
    }
    ++st->failures;
    return WC_ERROR_STEP_FAILED;
}

static int air_equal(const wc_air* a, const wc_air* b) {
    return v3_equal(a->wind, b->wind) && a->normal_drag == b->normal_drag && a->tangent_drag == b->tangent_drag;
}

/* A frame of a sleeping cloth: time advances exactly as the substeps would advance it. */
static wc_status sleep_frame(wc_state* s, double dt, wc_step_stats* st, double t_start) {
    if (s->def.substep_dt > 0) {
        const double h = s->def.substep_dt;
        s->accumulator += dt;
        while (s->accumulator >= h * (1.0 - 1e-9)) {
            s->accumulator -= h;
            s->time += h;
        }
        if (s->accumulator < 0) s->accumulator = 0;
    } else {
        const double h = dt / s->def.substeps;
        for (int k = 0; k < s->def.substeps; ++k) s->time += h;
    }
    for (int k = 0; k < s->n_mesh; ++k) wc_mesh_collider_end_frame(s->mesh[k]);
    ++s->frame;
    st->asleep = 1;
    st->solver = s->def.solver.type;
    st->contacts = s->contacts.active;
    st->max_strain = s->sleep_strain;
    st->kinetic_energy = 0.0;
    st->ms.total = wc_now_ms() - t_start;
    return WC_OK;
}

/* After a successful active frame: the rest timer, and falling asleep. */
static void rest_timer(wc_state* s, double dt, double max_speed, wc_step_stats* st, const wc_step_ops* ops) {
    if (!(s->def.sleep_speed > 0)) return;
    if (!(max_speed < s->def.sleep_speed)) {
        s->rest_time = 0.0;
        return;
    }
    s->rest_time += dt;
    if (s->rest_time >= s->def.sleep_time) {
        memset(s->v, 0, 3 * (size_t)s->model->n_particles * sizeof(double));
        s->hist_valid = 0;   /* BDF2 restarts with backward Euler when it wakes */
        if (ops->sleep) ops->sleep(ops->user, s);
        s->asleep = 1;
        s->sleep_strain = st->max_strain;
        st->fell_asleep = 1;
    }
}

wc_status wc_step_frame_ops(wc_state* s, double dt, wc_step_stats* stats, wc_diag* diag, const wc_step_ops* ops) {
    wc_step_stats local;
    wc_step_stats* st = stats ? stats : &local;
    memset(st, 0, sizeof *st);
    if (!s) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "step: NULL state");
    if (!(dt > 0) || !isfinite(dt) || dt > 1e3)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "step: frame time %g s must be finite, > 0 and <= 1000", dt);
    double t_start = wc_now_ms();
    /* gravity and air are plain fields of def: a change since the last frame wakes the cloth */
    if (!v3_equal(s->def.gravity, s->input_gravity) || !air_equal(&s->def.air, &s->input_air)) {
        wc_state_wake(s);
        v3_copy(s->input_gravity, s->def.gravity);
        s->input_air = s->def.air;
    }
    if (s->asleep) return sleep_frame(s, dt, st, t_start);
    s->seam_scale = wc_seam_scale(s->model, s->time + dt); /* constant over the frame (sew.h) */
    s->seam_ramping = wc_seam_scale(s->model, s->time) > 0.0;
    st->woke = s->woke;
    s->woke = 0;
    double pin_speed2 = 0.0;
    for (int k = 0; k < s->n_pins; ++k) {
        double d[3];
        v3_sub(d, s->pins[k].target, s->pin_from + 3 * k);
        double v2 = v3_dot(d, d) / (dt * dt);
        if (v2 > pin_speed2) pin_speed2 = v2;
    }
    double pin_energy = 0.5 * s->total_mass * pin_speed2; /* what moving pins may add to the kinetic energy */

    wc_status result = WC_OK;
    if (s->def.substep_dt > 0) {
        s->accumulator += dt;
        double h = s->def.substep_dt, consumed = 0.0, budget = s->accumulator;
        while (s->accumulator >= h * (1.0 - 1e-9)) {
            double a0 = consumed / budget, a1 = (consumed + h) / budget;
            if (a1 > 1.0) a1 = 1.0;
            if (robust_substep(s, h, a0, a1, pin_energy, st, diag, ops) != WC_OK) result = WC_ERROR_STEP_FAILED;
            s->accumulator -= h;
            consumed += h;
            s->time += h;
        }
        if (s->accumulator < 0) s->accumulator = 0;
    } else {
        int n = s->def.substeps;
        double h = dt / n;
        for (int k = 0; k < n; ++k) {
            if (robust_substep(s, h, (double)k / n, (double)(k + 1) / n, pin_energy, st, diag, ops) != WC_OK)
                result = WC_ERROR_STEP_FAILED;
            s->time += h;
        }
    }
    for (int k = 0; k < s->n_pins; ++k) v3_copy(s->pin_from + 3 * k, s->pins[k].target);
    for (int k = 0; k < s->n_mesh; ++k) wc_mesh_collider_end_frame(s->mesh[k]);
    ++s->frame;
    st->contacts = s->contacts.active;
    double max_speed = 0.0;
    ops->measure(ops->user, s, &max_speed, &st->kinetic_energy, &st->max_strain);
    if (result == WC_OK) rest_timer(s, dt, max_speed, st, ops);
    else s->rest_time = 0.0;
    if (st->fell_asleep) st->kinetic_energy = 0.0;
    st->ms.total = wc_now_ms() - t_start;
    if (result != WC_OK)
        return wc_fail(diag, result, "step: %d substep(s) failed after every retry; the state was kept finite",
                       st->failures);
    return WC_OK;
}
