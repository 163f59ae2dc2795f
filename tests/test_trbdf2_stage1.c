/* TR-BDF2's trapezoidal stage iterated to its own tolerance (core/newton.c "Stage 1"): a sheet
 * falling from horizontal off two pinned corners and swinging, at one substep a frame with
 * Newton 3 (the documented accurate setting), 32 x 32, 30 frames at 1/24 s:
 *  - with the rule every stage 1 ends on a gradient test at or below wc_sim_def.stage1_tolerance
 *    (the stats' stage1_unconverged stays 0) and takes iterations past the Newton count;
 *  - reproducible: two runs whose linear solves differ only by a 1 % change of the tolerance stay
 *    within a stated bound of each other, where without the rule (stage1_tolerance 0, stage 1 cut
 *    off at the Newton count, unconverged) they part by more (docs/bench/trbdf2_converged.md). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "step.h"
#include "test_support.h"

#define N 32
#define FRAMES 30

typedef struct {
    int stage1_iterations, stage1_unconverged, rollbacks;
} run_stats;

/* The swing at solver tolerance tol with stage-1 tolerance s1: positions of every frame into xs. */
static void swing(const wc_model* m, double tol, double s1, double* xs, run_stats* rs) {
    wc_sim_def sd = wc_default_sim_def();
    sd.integrator = WC_INTEGRATOR_TRBDF2;
    sd.newton_iterations = 3;
    sd.line_search = 1;
    sd.solver.tolerance = tol;
    sd.stage1_tolerance = s1;
    sd.threads = 1;
    sd.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_create(&s, m, &sd, NULL, &dg), WC_OK);
    CHECK_EQ_INT(ts_pin_far_corners(s, N, NULL), WC_OK);
    memset(rs, 0, sizeof *rs);
    const size_t n3 = 3 * (size_t)m->n_particles;
    for (int f = 0; f < FRAMES; ++f) {
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 24.0, &st, &dg), WC_OK);
        rs->stage1_iterations += st.stage1_iterations;
        rs->stage1_unconverged += st.stage1_unconverged;
        rs->rollbacks += st.rollbacks;
        memcpy(xs + n3 * (size_t)f, s->x, n3 * sizeof(double));
    }
    wc_state_destroy(s);
}

/* RMS distance over all frames and particles (m). */
static double rms_all(const double* a, const double* b, int n) {
    double e = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n * FRAMES; ++k) e += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrt(e / ((double)n * FRAMES));
}

static void test_stage1_converged_and_reproducible(void) {
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 0, 1.0));
    const size_t len = 3 * (size_t)m.n_particles * FRAMES;
    double *a = malloc(len * sizeof(double)), *b = malloc(len * sizeof(double));
    double *c = malloc(len * sizeof(double)), *d = malloc(len * sizeof(double));
    CHECK(a && b && c && d);
    run_stats ra, rb, rc, rd;
    swing(&m, 1e-4, 2e-2, a, &ra);
    swing(&m, 1.01e-4, 2e-2, b, &rb);
    swing(&m, 1e-4, 0.0, c, &rc);
    swing(&m, 1.01e-4, 0.0, d, &rd);
    const double on = rms_all(a, b, m.n_particles), off = rms_all(c, d, m.n_particles);
    printf("  stage 1 to 2e-2: %d extra iterations, %d unconverged, %d rollbacks (x1.01: %d, %d, %d); "
           "off: %d rollbacks\n",
           ra.stage1_iterations, ra.stage1_unconverged, ra.rollbacks, rb.stage1_iterations, rb.stage1_unconverged,
           rb.rollbacks, rc.rollbacks + rd.rollbacks);
    printf("  tolerance 1e-4 against 1.01e-4, RMS over %d frames: with the rule %.3g m, without %.3g m\n", FRAMES, on,
           off);
    CHECK_EQ_INT(ra.stage1_unconverged, 0);
    CHECK_EQ_INT(rb.stage1_unconverged, 0);
    CHECK(ra.stage1_iterations > 0);
    CHECK_EQ_INT(rc.stage1_iterations, 0);
    /* measured (32 x 32, 30 frames at 1/24 s): 0.0285 m with the rule, 0.0459 m without; the
       flapping sheet amplifies any difference while it falls, converged or not, so the bound is
       relative: the converged stage parts the two runs by clearly less */
    CHECK(on < 0.75 * off);
    free(a);
    free(b);
    free(c);
    free(d);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_stage1_converged_and_reproducible);
    return TEST_SUMMARY();
}
