/* Inexact Newton (core/newton.h "Inexact", wc_sim_def.newton_forcing).
 *  - The forcing term saves PCG iterations and moves the answer by little against the step's own
 *    error: a 16 x 16 sheet swinging from two pins for 10 frames, TR-BDF2 and backward Euler at
 *    one step per frame, Newton 3 with PCG and the multigrid, forcing 1e-2 against 0 (every solve
 *    to 1e-4). Both are compared with a converged reference (TR-BDF2 at 8 steps per frame, direct
 *    solves, 8 Newton iterations to 1e-10): the two runs differ by a small part of that error, and
 *    the forcing does not make it larger.
 *  - Inert where it has nothing to do: one Newton iteration, and the direct solver (bit for bit).
 *  - The solver's tolerance is the def's again after the frame.
 *  (A bad forcing term is refused: test_newton.c's test_bad_def.) */
#include <math.h>
#include <string.h>
#include "check.h"
#include "step.h"
#include "test_support.h"
#include "vec3.h"

#define N 16

static wc_state* swing_state(const wc_model* m, wc_integrator ig, int newton, wc_solver_type solver, double forcing,
                             int substeps) {
    wc_sim_def d = wc_default_sim_def();
    d.substeps = substeps;
    d.solver.type = solver;
    d.solver.preconditioner = WC_PRECOND_AMG;
    d.integrator = ig;
    d.newton_iterations = newton;
    d.line_search = newton > 1;
    d.newton_forcing = forcing;
    d.threads = 1;
    d.sleep_speed = 0.0;
    if (solver == WC_SOLVER_DIRECT && newton > 3) d.solver.tolerance = 1e-10;
    wc_state* s = NULL;
    wc_diag diag = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &d, NULL, &diag), WC_OK);
    CHECK_EQ_INT(ts_pin_far_corners(s, N, NULL), WC_OK);
    return s;
}

typedef struct run_totals {
    long long iterations, solves;
    int rollbacks, not_converged;
} run_totals;

static run_totals run(wc_state* s, int frames) {
    run_totals t = {0, 0, 0, 0};
    wc_step_stats st;
    wc_diag diag = {0};
    for (int f = 0; f < frames; ++f) {
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &diag), WC_OK);
        t.iterations += st.iterations;
        t.solves += st.solves;
        t.rollbacks += st.rollbacks;
        t.not_converged += st.not_converged;
    }
    return t;
}

static double rms_distance(const wc_state* a, const wc_state* b) {
    int n = a->model->n_particles;
    double e = 0.0;
    for (int i = 0; i < n; ++i) {
        double d[3];
        v3_sub(d, a->x + 3 * i, b->x + 3 * i);
        e += v3_dot(d, d);
    }
    return sqrt(e / n);
}

/* Forcing 1e-2 against 0 at Newton 3, each against the converged stages. */
static void test_forcing_saves_iterations(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 0, 1.0));
    const int frames = 10;
    const wc_integrator igs[2] = {WC_INTEGRATOR_TRBDF2, WC_INTEGRATOR_BE};
    for (int g = 0; g < 2; ++g) {
        wc_state* exact = swing_state(&m, WC_INTEGRATOR_TRBDF2, 8, WC_SOLVER_DIRECT, 0.0, 8);
        wc_state* tight = swing_state(&m, igs[g], 3, WC_SOLVER_PCG, 0.0, 1);
        wc_state* loose = swing_state(&m, igs[g], 3, WC_SOLVER_PCG, 1e-2, 1);
        run(exact, frames);
        run_totals tt = run(tight, frames), tl = run(loose, frames);
        double e_tight = rms_distance(tight, exact), e_loose = rms_distance(loose, exact);
        double between = rms_distance(tight, loose);
        printf("  %s Newton 3: forcing 0: %lld iterations in %lld solves (%.2f per solve), %d rollbacks; "
               "forcing 1e-2: %lld in %lld (%.2f), %d rollbacks\n",
               wc_integrator_name(igs[g]), tt.iterations, tt.solves, (double)tt.iterations / (double)tt.solves,
               tt.rollbacks, tl.iterations, tl.solves, (double)tl.iterations / (double)tl.solves, tl.rollbacks);
        printf("  RMS distance after %d frames to the converged reference: forcing 0 %.3e m, forcing 1e-2 %.3e m; "
               "between the two %.3e m\n",
               frames, e_tight, e_loose, between);
        CHECK(tl.iterations < 0.9 * (double)tt.iterations);
        CHECK(tl.rollbacks == 0 && tt.rollbacks == 0);
        CHECK(tl.not_converged == 0 && tt.not_converged == 0);
        /* the inexact solves move the run by a small part of the step's own error, and not
           further from the converged reference */
        CHECK(e_tight > 0.0);
        CHECK(between < 0.05 * e_tight);
        CHECK(e_loose < 1.02 * e_tight);
        /* the step's tolerance and floor are back */
        CHECK(wc_solver_tolerance(loose->solver) == loose->def.solver.tolerance);
        wc_state_destroy(exact);
        wc_state_destroy(tight);
        wc_state_destroy(loose);
    }
    wc_model_free(&m);
}

/* One Newton iteration, or the direct solver: the forcing term changes nothing, bit for bit. */
static void test_forcing_inert(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 0, 100.0));
    int n3 = 3 * m.n_particles;
    struct {
        int newton;
        wc_solver_type solver;
    } cases[2] = {{1, WC_SOLVER_PCG}, {3, WC_SOLVER_DIRECT}};
    for (int c = 0; c < 2; ++c) {
        wc_state* a = swing_state(&m, WC_INTEGRATOR_TRBDF2, cases[c].newton, cases[c].solver, 0.0, 1);
        wc_state* b = swing_state(&m, WC_INTEGRATOR_TRBDF2, cases[c].newton, cases[c].solver, 0.5, 1);
        run(a, 10);
        run(b, 10);
        CHECK(memcmp(a->x, b->x, (size_t)n3 * sizeof(double)) == 0);
        CHECK(memcmp(a->v, b->v, (size_t)n3 * sizeof(double)) == 0);
        wc_state_destroy(a);
        wc_state_destroy(b);
    }
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_forcing_saves_iterations);
    RUN_TEST(test_forcing_inert);
    return TEST_SUMMARY();
}
