/* BDF2 (core/bdf2.h) against backward Euler, and with the rest of the step.
 *  - Convergence order on one spring (a free particle on a spring to a pinned one, moving along
 *    it: an undamped harmonic oscillator u(t) = u0 cos wt + v0/w sin wt): the error at t = 1 s
 *    falls ~4x per halving of h with BDF2, ~2x with backward Euler (measured here).
 *  - Pins moving along a line stay exactly on their targets; the history is used (BDF2 substeps
 *    counted) and restarts after a halved retry, set_positions and falling asleep.
 *  - A sheet dropped on a sphere and a floor with friction: finite, outside the colliders, at
 *    rest in the end (asleep), BDF2 substeps used; Newton + line search on top of it.
 *  - Bit-identical on 1 and 2 threads (BDF2 with Newton and line search, with contacts). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "collide.h"
#include "drop_on_sphere.h"
#include "one_spring.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

/* Position error at t = 1 s with n steps. */
static double oscillator_error(const wc_model* m, wc_integrator integ, int n, double w) {
    wc_state* s = spring_state(m, integ);
    wc_diag dg = {0};
    const double r = 0.5, u0 = 0.05, v0 = 0.2;
    s->x[3] = r + u0;
    s->v[3] = v0;
    int bdf2_steps = 0;
    for (int k = 0; k < n; ++k) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / n, &st, &dg), WC_OK);
        bdf2_steps += st.bdf2_substeps;
    }
    if (integ == WC_INTEGRATOR_BDF2) CHECK_EQ_INT(bdf2_steps, n - 1);   /* the first step is BE */
    double exact = r + u0 * cos(w) + v0 / w * sin(w);
    double err = fabs(s->x[3] - exact);
    wc_state_destroy(s);
    return err;
}

static void test_convergence_order(void) {
    const double mass = 0.02, w = 2.0 * 3.14159265358979323846, k = mass * w * w;   /* period 1 s */
    wc_model m;
    spring_model(&m, k, mass);
    for (int integ = 0; integ < 2; ++integ) {
        double e[4];
        int steps[4] = {100, 200, 400, 800};
        for (int q = 0; q < 4; ++q) e[q] = oscillator_error(&m, (wc_integrator)integ, steps[q], w);
        double r1 = e[0] / e[1], r2 = e[1] / e[2], r3 = e[2] / e[3];
        printf("  %s: error at 1 s with 100/200/400/800 steps %.3g %.3g %.3g %.3g m; ratios %.3f %.3f %.3f\n",
               wc_integrator_name((wc_integrator)integ), e[0], e[1], e[2], e[3], r1, r2, r3);
        if (integ == WC_INTEGRATOR_BE) {
            CHECK(r2 > 1.8 && r2 < 2.2 && r3 > 1.8 && r3 < 2.2);
        } else {
            CHECK(r2 > 3.5 && r2 < 4.5 && r3 > 3.5 && r3 < 4.5);
        }
    }
    wc_model_free(&m);
}

#define N 10

static wc_state* sheet(const wc_model* m, int newton, int ls, int threads) {
    wc_sim_def d = wc_default_sim_def();
    d.integrator = getenv("BDF2_BE") ? WC_INTEGRATOR_BE : WC_INTEGRATOR_BDF2;
    d.newton_iterations = newton;
    d.line_search = ls;
    d.threads = threads;
    wc_state* s = NULL;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &d, NULL, &dg), WC_OK);
    return s;
}

/* Two corners of a hanging sheet pinned, moving along x at 0.3 m/s. */
static void test_pins_and_history(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 1.0, 1, 1.0));
    wc_state* s = sheet(&m, 1, 0, 1);
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(&m, N, 0, N - 1);
    pins[1].particle = ts_sheet_particle(&m, N, N - 1, N - 1);
    wc_diag dg = {0};
    for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, s->x + 3 * pins[k].particle);
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
    int bdf2 = 0, substeps = 0;
    for (int f = 0; f < 30; ++f) {
        for (int k = 0; k < 2; ++k) pins[k].target[0] += 0.01;
        CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
        bdf2 += st.bdf2_substeps;
        substeps += st.substeps;
        for (int k = 0; k < 2; ++k) CHECK(v3_equal(s->x + 3 * pins[k].particle, pins[k].target));
        CHECK_NEAR(s->v[3 * pins[0].particle], 0.3, 1e-9);
    }
    printf("  moving pins: %d of %d substeps BDF2\n", bdf2, substeps);
    CHECK(bdf2 >= substeps - 8);   /* the first substep, and those after a halving, are BE */
    CHECK(s->hist_valid);
    /* set_positions restarts the history */
    CHECK_EQ_INT(wc_state_set_positions(s, s->x, s->v, &dg), WC_OK);
    CHECK(!s->hist_valid);
    wc_step_stats st;
    CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
    CHECK_EQ_INT(st.bdf2_substeps, 0);
    CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
    CHECK_EQ_INT(st.bdf2_substeps, st.substeps);
    /* another frame length: BE once, then BDF2 again */
    CHECK_EQ_INT(wc_step_frame(s, 1.0 / 60, &st, &dg), WC_OK);
    CHECK_EQ_INT(st.bdf2_substeps, 0);
    CHECK_EQ_INT(wc_step_frame(s, 1.0 / 60, &st, &dg), WC_OK);
    CHECK_EQ_INT(st.bdf2_substeps, st.substeps);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* A sheet dropped onto a sphere lying on a floor, friction 0.4, BDF2 (and Newton 2 + line
 * search): stays outside the colliders, comes to rest and sleeps; threads 1 and 2 agree. */
static void run_drop(const wc_model* m, int newton, int ls, int threads, double* x_out, int* slept, int* bdf2,
                     double* worst_depth) {
    wc_state* s = sheet(m, newton, ls, threads);
    drop_on_sphere(s, slept, bdf2, worst_depth);
    if (getenv("BDF2_DEBUG")) printf("  end: frame %lld max speed %.3g\n", s->frame, wc_state_max_speed(s));
    if (*slept) CHECK(!s->hist_valid);   /* asleep: the history no longer leads here */
    memcpy(x_out, s->x, 3 * (size_t)m->n_particles * sizeof(double));
    wc_state_destroy(s);
}

static void test_colliders_friction_sleep_threads(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.6, 0, 1.0));
    int n3 = 3 * m.n_particles;
    double xa[3 * N * N], xb[3 * N * N];
    for (int mode = 0; mode < 2; ++mode) {
        int slept, bdf2, slept2, bdf22;
        double depth, depth2;
        run_drop(&m, mode ? 2 : 1, mode, 1, xa, &slept, &bdf2, &depth);
        run_drop(&m, mode ? 2 : 1, mode, 2, xb, &slept2, &bdf22, &depth2);
        printf("  drop (%s): %d BDF2 substeps, asleep %d, deepest inside a collider %.3g m\n",
               mode ? "Newton 2 + line search" : "one step", bdf2, slept, depth);
        CHECK(bdf2 > 20);
        if (mode) CHECK(slept);   /* the plain step: still sliding slowly off the ball after 8 s (so is BE) */
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
        if (getenv("BDF2_DEBUG")) printf("  over the centre: y %.4f (%.3f m off axis)\n", xa[3 * best + 1], sqrt(bd));
        CHECK(sqrt(bd) < 0.1 && xa[3 * best + 1] > 0.49 && xa[3 * best + 1] < 0.54);
    }
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_convergence_order);
    RUN_TEST(test_pins_and_history);
    RUN_TEST(test_colliders_friction_sleep_threads);
    return TEST_SUMMARY();
}
