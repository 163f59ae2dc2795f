/* The linear solves' residual floor (core/solve.h, wc_solver_set_residual_floor; the step sets
 * wc_state_residual_floor): its closed form (h |g| sqrt(sum m^2) over the particles no pin holds
 * fully: a line pin's particle still counts); a system whose right-hand side is a millionth of
 * a real one (a cloth at rest: its forces balance) is solved to the floor in fewer iterations
 * than to its own tiny residual, with a true residual within tolerance x floor and an answer
 * within tolerance x g h of CHOLMOD's; a right-hand side above the floor gives the very same
 * iterates with and without it; invalid floors are ignored. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "solve.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

#define N 16

/* ||S (b - A x)|| (filter z of the pins is zero: still pins) */
static double filtered_residual(const wc_model* m, const wc_state* s, const double* b, const double* x) {
    int n = m->n_particles;
    double* r = malloc(3 * (size_t)n * sizeof(double));
    wc_par par = s->par;
    wc_bsr_mul(&m->pattern, s->A, x, r, &par);
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        double d[3], o[3];
        for (int c = 0; c < 3; ++c) d[c] = b[3 * i + c] - r[3 * i + c];
        wc_filter_apply(&s->filter, i, d, o);
        sum += v3_dot(o, o);
    }
    free(r);
    return sqrt(sum);
}

static void test_floor(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 1.0, 0, 1.0)); /* horizontal: it falls and swings */
    wc_sim_def sd = wc_default_sim_def();
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    /* two corners pinned fully, a third on a line (it still counts in the floor) */
    wc_pin pins[3];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(&m, N, 0, N - 1);
    pins[1].particle = ts_sheet_particle(&m, N, N - 1, N - 1);
    pins[2].particle = ts_sheet_particle(&m, N, N / 2, N - 1);
    v3_set(pins[2].free_axis, 1.0, 0.0, 0.0);
    for (int k = 0; k < 3; ++k) v3_copy(pins[k].target, m.rest_pos + 3 * pins[k].particle);
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 3, &d), WC_OK);
    for (int f = 0; f < 5; ++f) CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, NULL, &d), WC_OK);

    const double h = 1.0 / 30;
    double m2 = 0.0;
    for (int i = 0; i < m.n_particles; ++i)
        if (i != pins[0].particle && i != pins[1].particle) m2 += m.mass[i] * m.mass[i];
    const double floor_ref = h * 9.81 * sqrt(m2), floor = wc_state_residual_floor(s, h);
    printf("  floor %.6g kg m/s (closed form %.6g)\n", floor, floor_ref);
    CHECK_NEAR(floor, floor_ref, 1e-12 * floor_ref);

    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    int n3 = 3 * m.n_particles;
    double* small = malloc((size_t)n3 * sizeof(double));
    for (int k = 0; k < n3; ++k) small[k] = 1e-6 * s->b[k];

    wc_solver_opts o = s->def.solver;
    o.type = WC_SOLVER_PCG;
    o.tolerance = 1e-4;
    o.max_iterations = 1000;
    wc_solver *plain = NULL, *floored = NULL, *direct = NULL;
    CHECK_EQ_INT(wc_solver_create(&plain, &m, &o, 0, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_solver_create(&floored, &m, &o, 0, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_solver_create(&direct, &m, &o, 1, NULL, &d), WC_OK);
    wc_solver_set_residual_floor(floored, floor);
    wc_solver_set_residual_floor(floored, NAN);  /* ignored */
    wc_solver_set_residual_floor(floored, -1.0); /* ignored */

    double *d0 = calloc((size_t)n3, sizeof(double)), *d1 = calloc((size_t)n3, sizeof(double));
    double* ref = calloc((size_t)n3, sizeof(double));
    wc_solve_result r0, r1, rd;
    CHECK_EQ_INT(wc_solve(plain, WC_SOLVER_PCG, s->A, small, &s->filter, d0, &s->par, &r0), WC_OK);
    CHECK_EQ_INT(wc_solve(floored, WC_SOLVER_PCG, s->A, small, &s->filter, d1, &s->par, &r1), WC_OK);
    CHECK_EQ_INT(wc_solve(direct, WC_SOLVER_DIRECT, s->A, small, &s->filter, ref, &s->par, &rd), WC_OK);
    double true1 = filtered_residual(&m, s, small, d1), err1 = ts_max_diff(d1, ref, n3);
    printf("  right-hand side x 1e-6 (|S b| = %.3g): %d iterations to its own residual, %d to the floor "
           "(true residual %.3g = %.3g x floor); |dv - CHOLMOD| %.3g m/s (tolerance x g h = %.3g)\n",
           r0.residual0, r0.iterations, r1.iterations, true1, true1 / floor, err1, 1e-4 * 9.81 * h);
    CHECK(r0.residual0 < floor);
    CHECK_NEAR(r1.scale, floor, 0.0);
    CHECK_NEAR(r0.scale, r0.residual0, 0.0);
    CHECK(r1.converged);
    CHECK(r1.iterations < r0.iterations);
    CHECK(true1 <= 1e-4 * floor * (1.0 + 1e-9));
    CHECK(err1 <= 1e-4 * 9.81 * h);

    /* the real right-hand side, above the floor: the same iterates with and without it */
    memset(d0, 0, (size_t)n3 * sizeof(double));
    memset(d1, 0, (size_t)n3 * sizeof(double));
    CHECK_EQ_INT(wc_solve(plain, WC_SOLVER_PCG, s->A, s->b, &s->filter, d0, &s->par, &r0), WC_OK);
    CHECK_EQ_INT(wc_solve(floored, WC_SOLVER_PCG, s->A, s->b, &s->filter, d1, &s->par, &r1), WC_OK);
    printf("  real right-hand side |S b| = %.3g (%.1f x the floor): %d and %d iterations\n", r0.residual0,
           r0.residual0 / floor, r0.iterations, r1.iterations);
    CHECK(r0.residual0 > floor);
    CHECK_EQ_INT(r0.iterations, r1.iterations);
    CHECK(memcmp(d0, d1, (size_t)n3 * sizeof(double)) == 0);

    free(small);
    free(d0);
    free(d1);
    free(ref);
    wc_solver_destroy(plain);
    wc_solver_destroy(floored);
    wc_solver_destroy(direct);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_floor);
    return TEST_SUMMARY();
}
