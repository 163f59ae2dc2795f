/* The step's energy check (wc_sim_def.fail_energy_gain). Backward Euler only dissipates, but the
 * step linearises it: a flat sheet hanging from two corners has no spring resisting vertical
 * motion at rest, so its first linearised step is a free fall of g h^2 that stretches each
 * pinned corner's edge spring (rest r) to sqrt(r^2 + (g h^2)^2): spring energy out of nothing.
 * Checked against that closed form with the check off; with it on, the same step is rolled back
 * and retried in pieces, and the total energy does not rise beyond the allowance. With an energy
 * source (moving pins) the check stays out of the way. */
#include <math.h>
#include <string.h>
#include "check.h"
#include "energy_log.h"
#include "forces.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

#define N 12
#define STIFF 1e4

static wc_model g_sheet; /* N x N, 1 m, horizontal at y = 0, STIFF x the default springs */

static double total_energy(const wc_state* s) { return energy_at(s, s->x); }

/* The sheet pinned at the two corners of its j = N - 1 edge, targets moving by move per frame. */
static wc_state* make(const wc_model* m, double gain, const double* move) {
    wc_sim_def d = wc_default_sim_def();
    d.solver.type = WC_SOLVER_DIRECT;
    d.air.normal_drag = d.air.tangent_drag = 0.0;
    d.fail_energy_gain = gain;
    d.threads = 1;
    wc_state* s = NULL;
    wc_diag diag = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &d, NULL, &diag), WC_OK);
    CHECK_EQ_INT(ts_pin_far_corners(s, N, move), WC_OK);
    return s;
}

/* Largest strain of a stretch spring with a pinned end. */
static double corner_strain(const wc_state* s) {
    const wc_model* m = s->model;
    double worst = 0.0;
    for (int k = m->spring_type_start[WC_SPRING_STRETCH]; k < m->spring_type_start[WC_SPRING_STRETCH + 1]; ++k) {
        const wc_spring* sp = &m->springs[k];
        int pinned = 0;
        for (int p = 0; p < s->n_pins; ++p) pinned |= sp->a == s->pins[p].particle || sp->b == s->pins[p].particle;
        if (!pinned) continue;
        double L[3];
        v3_sub(L, s->x + 3 * sp->a, s->x + 3 * sp->b);
        double strain = (v3_norm(L) - sp->rest) / sp->rest;
        if (strain > worst) worst = strain;
    }
    return worst;
}

static void test_linearised_free_fall(void) {
    wc_model* m = &g_sheet;
    const double h = 1.0 / 12, drop = 9.81 * h * h, rest = 1.0 / (N - 1);
    wc_state* s = make(m, 0.0, NULL);
    double e0 = total_energy(s);
    wc_step_stats st;
    wc_diag diag = {0};
    CHECK_EQ_INT(wc_step_frame(s, h, &st, &diag), WC_OK);
    CHECK_EQ_INT(st.rollbacks, 0);
    /* a free particle far from the pins fell g h^2 (backward Euler: v1 = g h, x1 = h v1) */
    int far = ts_sheet_particle(m, N, N / 2, 0);
    CHECK_NEAR(s->x[3 * far + 1], -drop, 1e-9 * drop);
    /* the horizontal edge spring at a pinned corner: rest r along x, its free end dropped */
    CHECK_NEAR(corner_strain(s), sqrt(1.0 + drop * drop / (rest * rest)) - 1.0, 1e-3);
    /* and the total energy rose: stretched stiff springs that nothing paid for */
    double e1 = total_energy(s);
    CHECK(e1 - e0 > 10.0 * s->total_mass * 9.81 * sqrt(2.0));
    wc_state_destroy(s);
}

static void test_check_rolls_back(void) {
    wc_model* m = &g_sheet;
    const double h = 1.0 / 12, drop = 9.81 * h * h, rest = 1.0 / (N - 1);
    wc_state* s = make(m, 0.01, NULL);
    log_rec rec = {0};
    wc_diag diag = {WC_OK, "", on_log, &rec};
    const double scale = s->total_mass * 9.81 * sqrt(2.0); /* M |g| D, nothing elastic at rest */
    const double e_start = total_energy(s);
    for (int f = 0; f < 6; ++f) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, h, &st, &diag), WC_OK);
        if (f == 0) {
            CHECK(st.rollbacks >= 1 && st.halvings >= 1);
            CHECK(rec.energy_rollbacks >= 1);
            CHECK(corner_strain(s) < 0.1 * (sqrt(1.0 + drop * drop / (rest * rest)) - 1.0));
        }
        CHECK_EQ_INT(st.failures, 0);
        /* what the stability benchmark calls failed: energy above the start by 0.1 M |g| D */
        CHECK(total_energy(s) - e_start <= 0.1 * scale);
    }
    wc_state_destroy(s);
}

static void test_sources_are_not_judged(void) {
    wc_model* m = &g_sheet;
    /* pins lifted 5 cm a frame: they pour energy in, the check must not call that a failure */
    const double up[3] = {0.0, 0.05, 0.0};
    wc_state* s = make(m, 0.01, up);
    log_rec rec = {0};
    wc_diag diag = {WC_OK, "", on_log, &rec};
    wc_step_stats st;
    for (int f = 0; f < 4; ++f) {
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 60, &st, &diag), WC_OK);
        wc_pin pins[2];
        memcpy(pins, s->pins, sizeof pins);
        for (int k = 0; k < 2; ++k) pins[k].target[1] += up[1];
        wc_diag d2 = {0};
        CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &d2), WC_OK);
    }
    CHECK_EQ_INT(rec.energy_rollbacks, 0);
    wc_state_destroy(s);
}

static void test_bad_gain(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 4, 1.0, 0.0, 0, 1.0));
    wc_sim_def d = wc_default_sim_def();
    const double bad[] = {-1.0, NAN, INFINITY};
    for (int k = 0; k < 3; ++k) {
        d.fail_energy_gain = bad[k];
        wc_state* s = NULL;
        wc_diag diag = {0};
        CHECK_EQ_INT(wc_state_create(&s, &m, &d, NULL, &diag), WC_ERROR_INVALID_ARGUMENT);
        CHECK(s == NULL);
        CHECK(strstr(diag.message, "fail_energy_gain") != NULL);
    }
    wc_model_free(&m);
}

int main(void) {
    CHECK(ts_sheet(&g_sheet, N, 1.0, 0.0, 0, STIFF));
    RUN_TEST(test_linearised_free_fall);
    RUN_TEST(test_check_rolls_back);
    RUN_TEST(test_sources_are_not_judged);
    wc_model_free(&g_sheet);
    RUN_TEST(test_bad_gain);
    return TEST_SUMMARY();
}
