/* TR-BDF2 (core/bdf2.h: a trapezoidal stage to t + gamma h, then a BDF2 stage) against closed
 * forms and with the rest of the step.
 *  - Convergence order on one spring (an undamped harmonic oscillator along the spring, exact
 *    u(t) = u0 cos wt + v0/w sin wt): the error at t = 1 s falls ~4x per halving of h.
 *  - Energy on the same undamped oscillator at 8 steps per period: never gains from one step to
 *    the next (L-stable: it damps), and keeps most of it (second order: far less than backward
 *    Euler loses at the same step, measured here).
 *  - Pins moving along a line stay exactly on their targets; no BDF2 history is used or kept.
 *  - A sheet dropped on a sphere and a floor with friction: finite, outside the colliders, asleep
 *    in the end (Newton 2 + line search); bit-identical on 1 and 2 threads.
 *  - Contacts in the xb form (bdf2.h "Contacts"): the formulas on a particle above a rising floor
 *    (both stages), and a 48^2 sheet dropped on a sphere that no longer stretches over it.
 *  - Air drag (implicit for TR-BDF2): a flat sheet moving along its normal slows as
 *    v0 exp(-r t); the error at 1 s falls ~4x per halving of h (backward Euler's explicit drag: 2x).
 *  - Stage 2's base: the position corrections after stage 1's solve are not extrapolated
 *    (formula check).
 *  - A 32^2 sheet's flat start (no air) rolls a TR-BDF2 substep back (both stages) and retries it; the same
 *    on 1 and 2 threads, pins on target. (Snapshots, teleports, no allocation per step, the GPU's
 *    refusal and the bad enum value: tests/test_api_snapshot.c, test_api_frame.c, test_api_gpu.c,
 *    test_api_misuse.c.) */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "bdf2.h"
#include "collide.h"
#include "colliders.h"
#include "drop_on_sphere.h"
#include "one_spring.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

static const double R = 0.5, U0 = 0.05, V0 = 0.2;

static wc_state* oscillator(const wc_model* m, wc_integrator integ) {
    wc_state* s = spring_state(m, integ);
    s->x[3] = R + U0;
    s->v[3] = V0;
    return s;
}

/* Position error at t = 1 s with n steps. */
static double oscillator_error(const wc_model* m, int n, double w) {
    wc_state* s = oscillator(m, WC_INTEGRATOR_TRBDF2);
    wc_diag dg = {0};
    for (int k = 0; k < n; ++k) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / n, &st, &dg), WC_OK);
        CHECK_EQ_INT(st.rollbacks, 0);
        CHECK_EQ_INT(st.bdf2_substeps, 0);
    }
    CHECK(!s->hist_valid);   /* one-step: no history */
    double exact = R + U0 * cos(w) + V0 / w * sin(w);
    double err = fabs(s->x[3] - exact);
    wc_state_destroy(s);
    return err;
}

static void test_convergence_order(void) {
    const double mass = 0.02, w = 2.0 * 3.14159265358979323846, k = mass * w * w;   /* period 1 s */
    wc_model m;
    spring_model(&m, k, mass);
    double e[4];
    int steps[4] = {25, 50, 100, 200};
    for (int q = 0; q < 4; ++q) e[q] = oscillator_error(&m, steps[q], w);
    double r1 = e[0] / e[1], r2 = e[1] / e[2], r3 = e[2] / e[3];
    printf("  trbdf2: error at 1 s with 25/50/100/200 steps %.3g %.3g %.3g %.3g m; ratios %.3f %.3f %.3f\n", e[0],
           e[1], e[2], e[3], r1, r2, r3);
    CHECK(r2 > 3.5 && r2 < 4.5 && r3 > 3.5 && r3 < 4.5);
    CHECK(e[3] < 1e-4);
    wc_model_free(&m);
}

/* Oscillator energy 1/2 m v^2 + 1/2 k u^2 (J). */
static double osc_energy(const wc_state* s, double mass, double k) {
    double u = s->x[3] - R;
    return 0.5 * mass * v3_dot(s->v + 3, s->v + 3) + 0.5 * k * u * u;
}

static void test_energy_never_gained(void) {
    const double mass = 0.02, w = 2.0 * 3.14159265358979323846, k = mass * w * w;
    wc_model m;
    spring_model(&m, k, mass);
    double kept[2];
    for (int q = 0; q < 2; ++q) {
        wc_integrator integ = q ? WC_INTEGRATOR_TRBDF2 : WC_INTEGRATOR_BE;
        wc_state* s = oscillator(&m, integ);
        wc_diag dg = {0};
        double e0 = osc_energy(s, mass, k), prev = e0;
        for (int step = 0; step < 80; ++step) {   /* 10 periods, 8 steps each */
            wc_step_stats st;
            CHECK_EQ_INT(wc_step_frame(s, 1.0 / 8, &st, &dg), WC_OK);
            double e = osc_energy(s, mass, k);
            CHECK(e <= prev * (1.0 + 1e-12));
            prev = e;
        }
        kept[q] = prev / e0;
        wc_state_destroy(s);
    }
    printf("  energy kept after 10 periods at 8 steps per period: be %.3g, trbdf2 %.3g\n", kept[0], kept[1]);
    CHECK(kept[1] < 1.0);            /* damps */
    CHECK(kept[1] > 0.2);            /* but second order: */
    CHECK(kept[1] > 100.0 * kept[0]);   /* backward Euler keeps almost nothing */
    wc_model_free(&m);
}

/* A flat free sheet (normal +y, no gravity) moving at v0 along its normal: the springs stay at
 * rest and the air drag decelerates every particle alike, v(t) = v0 exp(-r t) with r = normal
 * drag / density (the mass and the drag are both lumped by area). Velocity error at 1 s. */
static double drag_error(const wc_model* m, wc_integrator integ, int n, double* r_out) {
    wc_sim_def sd = wc_default_sim_def();
    v3_zero(sd.gravity);
    sd.solver.type = WC_SOLVER_DIRECT;
    sd.integrator = integ;
    sd.threads = 1;
    sd.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &sd, NULL, &dg), WC_OK);
    for (int i = 0; i < m->n_particles; ++i) s->v[3 * i + 1] = 1.0;
    for (int k = 0; k < n; ++k) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / n, &st, &dg), WC_OK);
    }
    const double r = sd.air.normal_drag / wc_default_model_def().material.density;
    *r_out = r;
    double worst = 0.0;
    for (int i = 0; i < m->n_particles; ++i) {
        double e = fabs(s->v[3 * i + 1] - exp(-r));
        if (e > worst) worst = e;
    }
    wc_state_destroy(s);
    return worst;
}

static void test_air_drag_order(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 6, 1.0, 0.0, 0, 1.0));
    for (int q = 0; q < 2; ++q) {
        wc_integrator integ = q ? WC_INTEGRATOR_TRBDF2 : WC_INTEGRATOR_BE;
        double e[3], r = 0.0;
        int steps[3] = {20, 40, 80};
        for (int k = 0; k < 3; ++k) e[k] = drag_error(&m, integ, steps[k], &r);
        printf("  drag (r = %.3g 1/s), %s: velocity error at 1 s with 20/40/80 steps %.3g %.3g %.3g; ratios %.3f %.3f\n",
               r, wc_integrator_name(integ), e[0], e[1], e[2], e[0] / e[1], e[1] / e[2]);
        if (q) CHECK(e[0] / e[1] > 3.5 && e[1] / e[2] > 3.5 && e[1] / e[2] < 4.5);   /* second order */
        else CHECK(e[1] / e[2] > 1.8 && e[1] / e[2] < 2.2);                          /* explicit drag: first */
    }
    wc_model_free(&m);
}

#define N 10

static wc_state* sheet(const wc_model* m, int newton, int ls, int threads) {
    wc_sim_def d = wc_default_sim_def();
    d.integrator = WC_INTEGRATOR_TRBDF2;
    d.newton_iterations = newton;
    d.line_search = ls;
    d.threads = threads;
    wc_state* s = NULL;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &d, NULL, &dg), WC_OK);
    return s;
}

/* Two corners of a hanging sheet pinned, moving along x at 0.3 m/s. */
static void test_pins(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 1.0, 1, 1.0));
    for (int newton = 1; newton <= 2; ++newton) {
        wc_state* s = sheet(&m, newton, newton > 1, 1);
        wc_pin pins[2];
        memset(pins, 0, sizeof pins);
        pins[0].particle = ts_sheet_particle(&m, N, 0, N - 1);
        pins[1].particle = ts_sheet_particle(&m, N, N - 1, N - 1);
        wc_diag dg = {0};
        for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, s->x + 3 * pins[k].particle);
        CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
        for (int f = 0; f < 30; ++f) {
            for (int k = 0; k < 2; ++k) pins[k].target[0] += 0.01;
            CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
            wc_step_stats st;
            CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
            CHECK_EQ_INT(st.bdf2_substeps, 0);
            for (int k = 0; k < 2; ++k) CHECK(v3_equal(s->x + 3 * pins[k].particle, pins[k].target));
            CHECK_NEAR(s->v[3 * pins[0].particle], 0.3, 1e-9);
        }
        CHECK(!s->hist_valid);
        wc_state_destroy(s);
    }
    wc_model_free(&m);
}

/* A sheet dropped onto a sphere lying on a floor, friction 0.4. */
static void run_drop(const wc_model* m, int threads, double* x_out, int* slept, double* worst_depth) {
    wc_state* s = sheet(m, 2, 1, threads);
    drop_on_sphere(s, slept, NULL, worst_depth);
    memcpy(x_out, s->x, 3 * (size_t)m->n_particles * sizeof(double));
    wc_state_destroy(s);
}

static void test_colliders_friction_sleep_threads(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.6, 0, 1.0));
    int n3 = 3 * m.n_particles;
    double xa[3 * N * N], xb[3 * N * N];
    int slept, slept2;
    double depth, depth2;
    run_drop(&m, 1, xa, &slept, &depth);
    run_drop(&m, 2, xb, &slept2, &depth2);
    printf("  drop (Newton 2 + line search): asleep %d, deepest inside a collider %.3g m\n", slept, depth);
    CHECK(slept);
    CHECK(depth < 1e-9);
    CHECK(memcmp(xa, xb, (size_t)n3 * sizeof(double)) == 0);   /* thread-count independent */
    /* the sheet lies on the ball: the particle nearest above its centre sits on its shell */
    int best = 0;
    double bd = 1e9;
    for (int i = 0; i < m.n_particles; ++i) {
        double dx = xa[3 * i] - 0.1, dz = xa[3 * i + 2] - 0.05, d2 = dx * dx + dz * dz;
        if (d2 < bd) {
            bd = d2;
            best = i;
        }
    }
    /* it rests on the ball: the particle nearest the ball is on its shell (r + thickness, within
       1 mm), and the one nearest above its centre is above the ball, not slid off. (Its height
       is not asserted: the sheet settles with a fold near the top, whose height moved with every
       change of the settling (0.530 at 2e50674, 0.541 without the push-out's rollbacks, 0.56
       with TR-BDF2's refreshed damping)). */
    double dmin = 1e9;
    const double c[3] = {0.1, 0.25, 0.05};
    for (int i = 0; i < m.n_particles; ++i) {
        double d[3];
        v3_sub(d, xa + 3 * i, c);
        dmin = fmin(dmin, v3_norm(d) - 0.25);
    }
    printf("  on the ball: nearest particle %.4f m from its surface (shell 0.005), the one above its centre at y = %.4f\n",
           dmin, xa[3 * best + 1]);
    CHECK(dmin > 0.005 - 1e-6 && dmin < 0.006);
    CHECK(sqrt(bd) < 0.1 && xa[3 * best + 1] > 0.49);
    wc_model_free(&m);
}

/* The same drop with the sphere's radius moved by rounding-sized amounts (-1e-9 to +1e-9 m): the
 * outcome is chaotic, and each must come to rest within the 360 frames. It guards the release of
 * TR-BDF2's contacts on the substep's impulse (bdf2.h wc_integ_contact_impulses): released on one
 * stage's impulse, a corner lying on the floor under a ringing fold let go on one stage's pull,
 * fell 2-3 mm into the floor in the next (a released particle on the shell is not caught again,
 * collide.c), and the projection's push back out fed the fold 5-17 mJ; 4 of these 8 perturbed
 * drops never came to rest. */
static void test_drop_sleeps_perturbed(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.6, 0, 1.0));
    const double dr[9] = {0.0, -1e-9, -7.5e-10, -5e-10, -2.5e-10, 2.5e-10, 5e-10, 7.5e-10, 1e-9};
    printf("  frames to rest:");
    for (int k = 0; k < 9; ++k) {
        wc_state* s = sheet(&m, 2, 1, 1);
        int slept, frames;
        double depth;
        drop_on_sphere_radius(s, 0.25 + dr[k], &slept, &frames, NULL, &depth);
        printf(" %+.2g: %d%s", dr[k], frames, slept ? "" : " (moving)");
        CHECK(slept);
        CHECK(depth < 1e-9);
        wc_state_destroy(s);
    }
    printf("\n");
    wc_model_free(&m);
}

/* The 32^2 sheet flat at first, hanging from two corners in still air (no drag), one linearised
 * step per stage: its flat start gains energy in a stage and is rolled back (the whole substep, both stages) and
 * retried in halves; the result is the same on 1 and 2 threads and the pins stay on target. */
static void run_flat_start(const wc_model* m, int threads, double* x_out, int* rollbacks) {
    const int n = 32;
    wc_state* s = sheet(m, 1, 0, threads);
    s->def.air.normal_drag = s->def.air.tangent_drag = 0.0;   /* still air: the drag no longer holds it */
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(m, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(m, n, n - 1, n - 1);
    for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, s->x + 3 * pins[k].particle);
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
    *rollbacks = 0;
    for (int f = 0; f < 45; ++f) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
        *rollbacks += st.rollbacks;
        for (int k = 0; k < 2; ++k) CHECK(v3_equal(s->x + 3 * pins[k].particle, pins[k].target));
    }
    for (int i = 0; i < 3 * m->n_particles; ++i) CHECK(isfinite(s->x[i]) && isfinite(s->v[i]));
    memcpy(x_out, s->x, 3 * (size_t)m->n_particles * sizeof(double));
    wc_state_destroy(s);
}

static void test_rollback_threads(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 32, 1.0, 0.0, 0, 1.0));
    size_t n3 = 3 * (size_t)m.n_particles;
    double* xa = malloc(n3 * sizeof(double));
    double* xb = malloc(n3 * sizeof(double));
    int ra = 0, rb = 0;
    run_flat_start(&m, 1, xa, &ra);
    run_flat_start(&m, 2, xb, &rb);
    printf("  flat start: %d rollback(s)\n", ra);
    CHECK(ra > 0);
    CHECK_EQ_INT(ra, rb);
    CHECK(memcmp(xa, xb, n3 * sizeof(double)) == 0);
    free(xa);
    free(xb);
    wc_model_free(&m);
}

/* Stage 2's base after stage 1 and a correction (bdf2.h): with x_g, v_g as stage 1 solved them
 * and the corrections that follow (a collider's projection, strain limiting, self-collision)
 * moving them by dx, dvc, stage 2 starts from the corrected x_g + dx, v_g + dvc but extrapolates
 * only the motion the solve made: xb = x_g + dx + c2 (x_g - x_n), vstar = v_g + dvc +
 * c2 (x_g - x_n) / he, and mom = c2 (v_g + dvc - v_n). Without the correction, the textbook
 * stage. */
static void test_corrections_not_extrapolated(void) {
    const double g = WC_TRBDF2_GAMMA, c2 = (1.0 - g) * (1.0 - g) / (g * (2.0 - g)), h = 0.01;
    wc_model m;
    spring_model(&m, 10.0, 0.02);
    for (int corrected = 0; corrected < 2; ++corrected) {
        wc_state* s = oscillator(&m, WC_INTEGRATOR_TRBDF2);
        const double xn[3] = {s->x[3], s->x[4], s->x[5]}, vn[3] = {s->v[3], s->v[4], s->v[5]};
        wc_integ ig;
        wc_integ_begin(s, h, &ig);
        wc_integ_prepare(s, &ig);
        const double xg[3] = {xn[0] + 0.003, xn[1] - 0.001, xn[2]}, vg[3] = {vn[0] - 0.3, vn[1] - 0.1, 0.05};
        const double dx[3] = {0.0, 0.002, -0.001}, dvc[3] = {0.0, 0.2, -0.1};
        v3_copy(s->x + 3, xg);
        v3_copy(s->v + 3, vg);
        wc_integ_solved(s, &ig);
        if (corrected) {
            v3_add(s->x + 3, s->x + 3, dx);
            v3_add(s->v + 3, s->v + 3, dvc);
        }
        wc_integ_begin_stage2(s, h, &ig);
        wc_integ_prepare(s, &ig);
        CHECK_EQ_INT(ig.stage, 2);
        CHECK_NEAR(ig.he, g * h / 2.0, 1e-15);
        for (int c = 0; c < 3; ++c) {
            double xs = s->x[3 + c], back = c2 * (xg[c] - xn[c]);
            CHECK_NEAR(s->xb[3 + c], xs + back, 1e-15);
            CHECK_NEAR(s->mom[3 + c], c2 * (s->v[3 + c] - vn[c]), 1e-15);
            if (corrected) CHECK_NEAR(s->v[3 + c], vg[c] + dvc[c], 1e-15);
            CHECK_NEAR(s->vstar[3 + c], s->v[3 + c] + back / ig.he, 1e-12);
            if (corrected) CHECK_NEAR(xs, xg[c] + dx[c], 1e-15);
        }
        wc_state_destroy(s);
    }
    wc_model_free(&m);
}

/* The xb form's contact (bdf2.h "Contacts"), formula check: a particle found by begin 3 mm above
 * the shell of a floor rising at 0.1 m/s, falling at 0.5 m/s with 0.2 m/s sideways. After
 * wc_integ_contacts its normal velocity is the floor's, z prescribes no normal change, and
 * x_new = xb + he v_new with v_new.n = vc.n lands on the shell where the floor is at the stage's
 * end (x.n - 3 mm + h vc.n); the tangential motion is the stage's own. Both stages. */
static void test_contact_formula(void) {
    wc_model m;
    spring_model(&m, 10.0, 0.02);
    const double h = 0.02, gap = 0.003, vc = 0.1;
    for (int stage = 1; stage <= 2; ++stage) {
        wc_state* s = oscillator(&m, WC_INTEGRATOR_TRBDF2);
        wc_collider c = plane(0, 1, 0, s->x[4] - gap);   /* the particle 3 mm above it (thickness 0) */
        v3_set(c.velocity, 0, vc, 0);
        wc_diag dg = {0};
        CHECK_EQ_INT(wc_state_set_colliders(s, &c, 1, &dg), WC_OK);
        v3_set(s->v + 3, 0.2, -0.5, 0.0);
        wc_integ ig;
        wc_integ_begin(s, h, &ig);
        if (stage == 2) {
            wc_integ_prepare(s, &ig);
            v3_copy(s->xs + 3, s->x + 3);
            s->xs[4] -= 0.004;   /* stage 1 moved it down 4 mm */
            wc_integ_begin_stage2(s, h, &ig);
        }
        for (int i = 0; i < m.n_particles; ++i) wc_filter_free_particle(&s->filter, i);
        const double x0[3] = {s->x[3], s->x[4], s->x[5]};
        CHECK_EQ_INT(wc_contacts_begin(&s->contacts, s->colliders, 1, s->x, s->v, ig.h, &s->filter, &s->par), 1);
        CHECK_EQ_INT(s->contacts.collider[2], 0);
        wc_integ_prepare(s, &ig);
        const double back_t = s->xb[3] - s->x[3];
        wc_integ_contacts(s, &ig);
        CHECK_NEAR(s->v[4], vc, 1e-15);
        CHECK_NEAR(s->v[3], 0.2, 1e-15);
        CHECK_NEAR(s->filter.z[4], 0.0, 0.0);
        double land = s->xb[4] + ig.he * s->v[4];
        CHECK_NEAR(land, x0[1] - gap + ig.h * vc, 1e-14);
        CHECK_NEAR(s->xb[3] - s->x[3], back_t, 0.0);   /* tangential: untouched */
        for (int k = 3; k < 6; ++k) CHECK_NEAR(s->vstar[k], s->v[k] + (s->xb[k] - s->x[k]) / ig.he, 1e-12);
        if (stage == 1) CHECK(v3_equal(s->v_prev + 3, s->v + 3));
        else CHECK_NEAR(s->mom[4], (sqrt(2.0) - 1.0) / 2.0 * (s->v[4] - s->v_prev[4]), 1e-15);
        wc_state_destroy(s);
    }
    wc_model_free(&m);
}

/* A 48^2 sheet dropped flat onto a sphere (the bench's drape48: radius 0.25 m, 5 cm below, shell
 * 5 mm, friction 0.3), TR-BDF2 with Newton 2, 1 s. With backward Euler's landing rule in the
 * stages (the approach speed carried into the sphere, projected back out, and extrapolated into
 * it again by stage 2) the sheet over-stretches; with the xb form's contacts (bdf2.h) it stays
 * under the bound below (docs/design/solver.md, "Integrators"). */
static void test_drape_strain(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 48, 1.0, 0.3, 0, 1.0));
    wc_state* s = sheet(&m, 2, 1, 0);
    wc_collider c = sphere(0, 0, 0, 0.25);
    c.thickness = 0.005;
    c.friction = 0.3;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_set_colliders(s, &c, 1, &dg), WC_OK);
    double worst = 0.0;
    int rollbacks = 0;
    for (int f = 0; f < 30; ++f) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
        rollbacks += st.rollbacks;
        worst = fmax(worst, wc_max_stretch_strain(&m, s->x));
    }
    printf("  drape48, 1 s: largest strain %.4f, %d rollback(s)\n", worst, rollbacks);
    CHECK(worst < 0.08);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_convergence_order);
    RUN_TEST(test_corrections_not_extrapolated);
    RUN_TEST(test_energy_never_gained);
    RUN_TEST(test_air_drag_order);
    RUN_TEST(test_pins);
    RUN_TEST(test_colliders_friction_sleep_threads);
    RUN_TEST(test_drop_sleeps_perturbed);
    RUN_TEST(test_contact_formula);
    RUN_TEST(test_drape_strain);
    RUN_TEST(test_rollback_threads);
    return TEST_SUMMARY();
}
