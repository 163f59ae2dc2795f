/* The step against independent references: the closed-form discrete trajectory of one spring,
 * static balance of a hanging sheet, energy that never grows without external forces, pins that
 * sit exactly on their (moving) targets, and bit-identical repeat runs. */
#include <complex.h>
#include <stdlib.h>
#include <string.h>
#include "assemble.h"
#include "check.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

static wc_state* make_state(const wc_model* m, wc_sim_def def) {
    wc_state* s = NULL;
    wc_diag d = {0};
    wc_status st = wc_state_create(&s, m, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "state: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return s;
}

/* One spring of stiffness k, damping d, rest r between a pinned particle and a free one of mass
 * m, moving along the spring: backward Euler is the linear recurrence z' = T z on (u, v), u the
 * extension, with T = [[1 + h a, h (1 + b)], [a, 1 + b]], a = -h k / D, b = -h (d + h k) / D,
 * D = m + h d + h^2 k. Its closed form T^n = (l1^n (T - l2) - l2^n (T - l1)) / (l1 - l2) with the
 * (possibly complex) eigenvalues l1, l2. The model is a triangle whose springs are cut down to
 * the one between particles 0 and 1. */
static void test_spring_mass_closed_form(void) {
    double pos[9] = {0, 0, 0, 0.5, 0, 0, 0, 0.7, 0.3};
    int sizes[1] = {3}, idx[3] = {0, 1, 2};
    wc_source_mesh src;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, 3, sizes, 1, idx, 1.0, &dg), WC_OK);
    wc_model_def def = wc_default_model_def();
    def.reorder = 0;
    def.material.uniform_mass = 0.02;
    def.material.k[WC_SPRING_STRETCH] = 300.0;
    def.material.d[WC_SPRING_STRETCH] = 0.4;
    wc_model m;
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &dg), WC_OK);
    /* keep only spring 0-1 */
    int keep = -1;
    for (int s = 0; s < m.n_springs; ++s)
        if (m.springs[s].a == 0 && m.springs[s].b == 1) keep = s;
    CHECK(keep >= 0);
    m.springs[0] = m.springs[keep];
    m.n_springs = 1;
    for (int t = 1; t <= WC_SPRING_TYPE_COUNT; ++t) m.spring_type_start[t] = 1;
    wc_bsr_pattern_free(&m.pattern, &m.alloc);
    CHECK_EQ_INT(wc_bsr_pattern_build(&m.pattern, &m, &m.alloc), 0);

    double k = 300.0, d = 0.4, mass = 0.02, r = 0.5, h = 1.0 / 30.0;
    for (int solver = 0; solver < 2; ++solver) {
        wc_sim_def sd = wc_default_sim_def();
        v3_zero(sd.gravity);
        sd.air.normal_drag = sd.air.tangent_drag = 0.0;
        sd.solver.type = solver ? WC_SOLVER_PCG : WC_SOLVER_DIRECT;
        sd.solver.tolerance = 1e-14;
        wc_state* s = make_state(&m, sd);
        wc_pin pins[2] = {{0, {0, 0, 0}, {0, 0, 0}}, {2, {0, 0.7, 0.3}, {0, 0, 0}}};
        CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &dg), WC_OK);
        double u0 = 0.1, v0 = -0.3;
        s->x[3] = r + u0;
        s->v[3] = v0;
        double D = m.mass[1] + h * d + h * h * k;
        CHECK_NEAR(m.mass[1], mass, 0);
        double a = -h * k / D, b = -h * (d + h * k) / D;
        double T[4] = {1 + h * a, h * (1 + b), a, 1 + b};
        double tr = T[0] + T[3], det = T[0] * T[3] - T[1] * T[2];
        double complex disc = csqrt(tr * tr - 4 * det + 0 * I);
        double complex l1 = (tr + disc) / 2, l2 = (tr - disc) / 2;
        double worst = 0;
        for (int n = 1; n <= 90; ++n) {
            CHECK_EQ_INT(wc_step_frame(s, h, NULL, &dg), WC_OK);
            double complex p1 = cpow(l1, n), p2 = cpow(l2, n);
            double complex c = (p1 - p2) / (l1 - l2), e = (l1 * p2 - l2 * p1) / (l1 - l2);
            /* T^n = c T + e I */
            double u = creal(c * (T[0] * u0 + T[1] * v0) + e * u0);
            double v = creal(c * (T[2] * u0 + T[3] * v0) + e * v0);
            double eu = fabs(s->x[3] - r - u), ev = fabs(s->v[3] - v);
            if (eu > worst) worst = eu;
            if (ev * h > worst) worst = ev * h;
            CHECK(s->x[4] == 0.0 && s->x[5] == 0.0); /* stays on the spring's line */
        }
        printf("  %s: largest deviation from the closed form over 90 steps: %.3g m\n", solver ? "pcg" : "direct", worst);
        CHECK(worst < 1e-12);
        wc_state_destroy(s);
    }
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

/* Net force on every free particle: springs + gravity (the balance a sheet at rest must meet). */
static double worst_imbalance(const wc_model* m, wc_state* s) {
    wc_eval_springs(m, s->x, s->v, WC_COMPRESSION_DROP, &s->par, s->se);
    wc_eval_external(m, s->x, s->v, s->def.gravity, &s->def.air, &s->par, s->tri_scratch, s->f_ext);
    wc_assemble(m, s->se, s->f_ext, s->v, 1e-3, &s->par, s->A, s->b, s->f);
    double worst = 0;
    for (int i = 0; i < m->n_particles; ++i) {
        int pinned = 0;
        for (int k = 0; k < s->n_pins; ++k) pinned |= s->pins[k].particle == i;
        if (pinned) continue;
        double rel = v3_norm(s->f + 3 * i) / (m->mass[i] * 9.81);
        if (rel > worst) worst = rel;
    }
    return worst;
}

static void pin_top_corners(wc_state* s, const wc_model* m, int n) {
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(m, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(m, n, n - 1, n - 1);
    for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, m->rest_pos + 3 * pins[k].particle);
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &d), WC_OK);
}

static void test_hanging_sheet_comes_to_rest(void) {
    int n = 10;
    wc_model m;
    CHECK(ts_sheet(&m, n, 1.0, 1.0, 1, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_DIRECT;
    wc_state* s = make_state(&m, sd);
    pin_top_corners(s, &m, n);
    double before = worst_imbalance(&m, s);
    wc_diag d = {0};
    wc_step_stats st;
    for (int f = 0; f < 600; ++f) CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &d), WC_OK);
    double after = worst_imbalance(&m, s);
    printf("  net force / weight: %.3g at rest shape, %.3g after 20 s; kinetic energy %.3g J; strain %.3g\n", before,
           after, st.kinetic_energy, st.max_strain);
    CHECK(before > 0.5);
    CHECK(after < 1e-6);
    CHECK(st.kinetic_energy < 1e-12);
    CHECK(st.max_strain > 0 && st.max_strain < 0.1);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* No gravity, no air, no pins: kinetic + elastic energy never grows (backward Euler and spring
 * damping only dissipate). */
static void test_energy_never_grows(void) {
    int n = 8;
    wc_model m;
    CHECK(ts_sheet(&m, n, 1.0, 0.0, 0, 1.0));
    for (int solver = 0; solver < 2; ++solver) {
        wc_sim_def sd = wc_default_sim_def();
        v3_zero(sd.gravity);
        sd.air.normal_drag = sd.air.tangent_drag = 0.0;
        sd.solver.type = solver ? WC_SOLVER_PCG : WC_SOLVER_DIRECT;
        sd.solver.tolerance = 1e-12;
        sd.solver.max_iterations = 2000;
        wc_state* s = make_state(&m, sd);
        srand(3);
        for (int i = 0; i < 3 * m.n_particles; ++i) {
            s->x[i] = m.rest_pos[i] * 1.15 + 0.02 * (rand() / (double)RAND_MAX - 0.5);
            s->v[i] = 0.5 * (rand() / (double)RAND_MAX - 0.5);
        }
        double e0 = wc_state_kinetic_energy(s) + wc_spring_energy(&m, s->x), prev = e0, worst = 0;
        wc_diag d = {0};
        for (int f = 0; f < 120; ++f) {
            CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, NULL, &d), WC_OK);
            double e = wc_state_kinetic_energy(s) + wc_spring_energy(&m, s->x);
            if ((e - prev) / e0 > worst) worst = (e - prev) / e0;
            prev = e;
        }
        printf("  %s: energy %.4g J -> %.4g J, largest growth in one frame %.3g of the start\n",
               solver ? "pcg" : "direct", e0, prev, worst);
        CHECK(worst <= 1e-9);
        CHECK(prev < 0.5 * e0);
        wc_state_destroy(s);
    }
    wc_model_free(&m);
}

/* Pins moving along a line (and one line-constrained pin): every frame the pinned particles sit
 * bit-exactly on their targets, and the line pin stays on its line. */
static void test_pins_exact(void) {
    int n = 9;
    wc_model m;
    CHECK(ts_sheet(&m, n, 1.0, 1.0, 1, 1.0));
    wc_state* s = make_state(&m, wc_default_sim_def());
    wc_pin pins[3];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(&m, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(&m, n, n - 1, n - 1);
    pins[2].particle = ts_sheet_particle(&m, n, n / 2, n - 1);
    v3_set(pins[2].free_axis, 0, 0, 1);
    double base[3][3];
    for (int k = 0; k < 3; ++k) v3_copy(base[k], m.rest_pos + 3 * pins[k].particle);
    wc_diag d = {0};
    int bad = 0;
    for (int f = 1; f <= 60; ++f) {
        double t = f / 30.0;
        for (int k = 0; k < 3; ++k) {
            v3_copy(pins[k].target, base[k]);
            pins[k].target[0] += 0.3 * sin(2 * t);
            pins[k].target[1] += 0.1 * t;
        }
        CHECK_EQ_INT(wc_state_set_pins(s, pins, 3, &d), WC_OK);
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, NULL, &d), WC_OK);
        for (int k = 0; k < 2; ++k)
            if (memcmp(s->x + 3 * pins[k].particle, pins[k].target, 3 * sizeof(double)) != 0) ++bad;
        const double* x = s->x + 3 * pins[2].particle;
        if (fabs(x[0] - pins[2].target[0]) > 1e-9 || fabs(x[1] - pins[2].target[1]) > 1e-9) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Same inputs, same thread count: bit-identical positions (with wind, colliders and pins). */
static void test_bit_identical(void) {
    int n = 16;
    wc_model m;
    CHECK(ts_sheet(&m, n, 1.0, 0.5, 0, 1.0));
    double* first = malloc(sizeof(double) * 3 * m.n_particles);
    for (int run = 0; run < 2; ++run) {
        wc_sim_def sd = wc_default_sim_def();
        sd.threads = 2;
        v3_set(sd.air.wind, 2.0, 0.0, 1.0);
        wc_state* s = make_state(&m, sd);
        wc_collider c;
        memset(&c, 0, sizeof c);
        c.type = WC_COLLIDER_SPHERE;
        v3_set(c.center, 0.1, 0.1, 0.0);
        c.radius = 0.3;
        c.thickness = 0.01;
        c.friction = 0.3;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_state_set_colliders(s, &c, 1, &d), WC_OK);
        for (int f = 0; f < 30; ++f) CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, NULL, &d), WC_OK);
        if (run == 0) memcpy(first, s->x, sizeof(double) * 3 * m.n_particles);
        else CHECK(memcmp(first, s->x, sizeof(double) * 3 * m.n_particles) == 0);
        wc_state_destroy(s);
    }
    free(first);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_spring_mass_closed_form);
    RUN_TEST(test_hanging_sheet_comes_to_rest);
    RUN_TEST(test_energy_never_grows);
    RUN_TEST(test_pins_exact);
    RUN_TEST(test_bit_identical);
    return TEST_SUMMARY();
}
