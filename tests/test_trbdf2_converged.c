/* TR-BDF2 with its stages solved to convergence (Newton + line search, tolerance 1e-12) keeps
 * second order on forces whose direction turns during a stage (core/newton.h "Refreshed"):
 *  - A damped spring whirling round its pinned end (the spring's direction turns ~2 rad in 1 s):
 *    the position error at t = 1 s against an independent RK4 solution of the same ODE
 *    m x'' = -(k (|x| - r) + d (v . u)) u, u = x / |x|, at 20000 steps falls ~4x per halving of
 *    h. With the damping's directions frozen at the stage's start (as backward Euler and BDF2
 *    keep them) it falls ~2x: first order.
 *  - A small sheet tumbling in air (no gravity, spinning about an in-plane axis: the triangles'
 *    normals turn, so the drag's geometry changes within a stage): self-convergence, the
 *    difference between runs at n and 2n steps falls ~4x per halving (with the air's geometry
 *    frozen at the stage's start: ~2x). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "one_spring.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

static const double R = 0.5, U0 = 0.05, V0 = 0.2, VT = 1.0;   /* m, m, m/s radial, m/s tangential */

/* The spring's force on particle 1 at (x, v) (3, N). */
static void spring_force(double k, double d, const double* x, const double* v, double* f) {
    double l = v3_norm(x), u[3];
    v3_scale(u, x, 1.0 / l);
    v3_scale(f, u, -(k * (l - R) + d * v3_dot(v, u)));
}

/* RK4 of the whirling damped spring to t = 1 s in n steps: position at the end (3). */
static void rk4_reference(double k, double d, double mass, int n, double* x_end) {
    double y[6] = {R + U0, 0, 0, V0, VT, 0}, h = 1.0 / n;
    for (int s = 0; s < n; ++s) {
        double kk[4][6], t[6];
        for (int q = 0; q < 4; ++q) {
            const double c = q == 0 ? 0.0 : q == 3 ? 1.0 : 0.5;
            for (int j = 0; j < 6; ++j) t[j] = y[j] + (q ? c * h * kk[q - 1][j] : 0.0);
            double f[3];
            spring_force(k, d, t, t + 3, f);
            for (int j = 0; j < 3; ++j) {
                kk[q][j] = t[3 + j];
                kk[q][3 + j] = f[j] / mass;
            }
        }
        for (int j = 0; j < 6; ++j) y[j] += h / 6.0 * (kk[0][j] + 2 * kk[1][j] + 2 * kk[2][j] + kk[3][j]);
    }
    v3_copy(x_end, y);
}

/* TR-BDF2, Newton to convergence: position error at t = 1 s with n steps against `exact`. */
static double whirl_error(const wc_model* m, int n, const double* exact) {
    wc_state* s = spring_state(m, WC_INTEGRATOR_TRBDF2);
    s->def.newton_iterations = 20;
    s->def.line_search = 1;
    s->def.solver.tolerance = 1e-12;
    s->x[3] = R + U0;
    s->v[3] = V0;
    s->v[4] = VT;
    wc_diag dg = {0};
    for (int k = 0; k < n; ++k) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / n, &st, &dg), WC_OK);
        CHECK_EQ_INT(st.rollbacks, 0);
    }
    double e[3];
    v3_sub(e, s->x + 3, exact);
    wc_state_destroy(s);
    return v3_norm(e);
}

static void test_whirling_damped_spring(void) {
    const double mass = 0.02, w = 2.0 * 3.14159265358979323846, k = mass * w * w;   /* period 1 s */
    wc_model m;
    spring_model(&m, k, mass);
    const double d = 0.2 * sqrt(k * mass);   /* damping ratio 0.1 */
    m.material.d[WC_SPRING_STRETCH] = d;
    CHECK_NEAR(m.mass[1], mass, 1e-15);
    CHECK_NEAR(m.material.k[WC_SPRING_STRETCH], k, 1e-12);
    double exact[3];
    rk4_reference(k, d, mass, 20000, exact);
    double turn = atan2(exact[1], exact[0]);
    double e[4];
    int steps[4] = {25, 50, 100, 200};
    for (int q = 0; q < 4; ++q) e[q] = whirl_error(&m, steps[q], exact);
    double r1 = e[0] / e[1], r2 = e[1] / e[2], r3 = e[2] / e[3];
    printf("  whirling damped spring (turned %.2f rad): error at 1 s with 25/50/100/200 steps %.3g %.3g %.3g "
           "%.3g m; ratios %.3f %.3f %.3f\n",
           turn, e[0], e[1], e[2], e[3], r1, r2, r3);
    CHECK(fabs(turn) > 1.0);
    CHECK(r2 > 3.5 && r2 < 4.5 && r3 > 3.5 && r3 < 4.5);
    wc_model_free(&m);
}

#define N 6

/* A free N x N sheet (no gravity) spinning about its x axis at 3 rad/s, moving along +y at
 * 1 m/s, in air: TR-BDF2 with Newton to convergence, n steps to t = 1 s; positions into x_out. */
static void tumble(const wc_model* m, int n, double* x_out) {
    wc_sim_def sd = wc_default_sim_def();
    v3_zero(sd.gravity);
    sd.solver.type = WC_SOLVER_DIRECT;
    sd.solver.tolerance = 1e-12;
    sd.integrator = WC_INTEGRATOR_TRBDF2;
    sd.newton_iterations = 20;
    sd.line_search = 1;
    sd.threads = 1;
    sd.sleep_speed = 0.0;
    sd.fail_energy_gain = 0.0;
    wc_state* s = NULL;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &sd, NULL, &dg), WC_OK);
    double c[3] = {0, 0, 0};
    for (int i = 0; i < m->n_particles; ++i) v3_add(c, c, s->x + 3 * i);
    v3_scale(c, c, 1.0 / m->n_particles);
    const double omega[3] = {3.0, 0, 0};
    for (int i = 0; i < m->n_particles; ++i) {
        double r[3];
        v3_sub(r, s->x + 3 * i, c);
        v3_cross(s->v + 3 * i, omega, r);
        s->v[3 * i + 1] += 1.0;
    }
    for (int k = 0; k < n; ++k) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / n, &st, &dg), WC_OK);
        CHECK_EQ_INT(st.rollbacks, 0);
    }
    memcpy(x_out, s->x, 3 * (size_t)m->n_particles * sizeof(double));
    wc_state_destroy(s);
}

static double rms_diff(const double* a, const double* b, int n) {
    double e = 0.0;
    for (int k = 0; k < 3 * n; ++k) e += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrt(e / n);
}

static void test_tumbling_sheet_in_air(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 0, 1.0));
    const int n3 = 3 * m.n_particles;
    int steps[4] = {20, 40, 80, 160};
    double* x[4];
    for (int q = 0; q < 4; ++q) {
        x[q] = malloc((size_t)n3 * sizeof(double));
        CHECK(x[q] != NULL);
        tumble(&m, steps[q], x[q]);
    }
    double d0 = rms_diff(x[0], x[1], m.n_particles), d1 = rms_diff(x[1], x[2], m.n_particles),
           d2 = rms_diff(x[2], x[3], m.n_particles);
    printf("  tumbling sheet in air: RMS difference 20-40 %.3g, 40-80 %.3g, 80-160 %.3g m; ratios %.3f %.3f\n", d0,
           d1, d2, d0 / d1, d1 / d2);
    CHECK(d0 / d1 > 3.3 && d1 / d2 > 3.5 && d1 / d2 < 4.5);
    for (int q = 0; q < 4; ++q) free(x[q]);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_whirling_damped_spring);
    RUN_TEST(test_tumbling_sheet_in_air);
    return TEST_SUMMARY();
}
