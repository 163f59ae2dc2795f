/* The one-group PCG solve (pcg_group.glsl: a whole block-Jacobi PCG solve in one work group)
 * against the multi-pass chain on the same float systems (real EGL: llvmpipe without a GPU),
 * the chain checked against core's PCG by test_gpu_solver: sheets of several sizes up to
 * WG_GROUP_MAX_PARTICLES with pins and plane constraints carrying z, a solve that hits the
 * iteration cap, one that converges at once, a zero right-hand side, one that restarts from the
 * true residual, a non-finite system; the group is one dispatch, and a cloth past the group's
 * limit is refused when WEFT_GPU_SOLVE=group forces it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "gpu_group_support.h"
#include "step.h"
#include "test_support.h"
#include "wg_sim_impl.h"

static wg_gl_context* gl;
static wg_device* dev;

static wc_state* sheet_system(wc_model* m, int n, int warm, wg_sim** g) {
    return tg_sheet_system(dev, m, n, warm, 1.0, WC_PRECOND_BLOCK_JACOBI, g);
}

typedef tg_solved solved;

static solved solve_as(wg_sim* g, const wc_solver_opts* o, const double* guess, wg_solve_mode mode) {
    return tg_solve_as(dev, g, o, guess, mode);
}

/* The group against the chain from the same guess: the same status, iteration count and
 * convergence, the final residual within rel_res (relative), the iterates within rel_dv of the
 * largest component; returns the group's run (the caller frees its dv). */
static solved compare(const char* what, wg_sim* g, const wc_solver_opts* o, const double* guess, double rel_dv,
                      double rel_res) {
    solved a = solve_as(g, o, guess, WG_SOLVE_GROUP), b = solve_as(g, o, guess, WG_SOLVE_PASSES);
    const int n3 = 3 * g->n;
    const double scale = fmax(ts_max_abs(b.dv, n3), 1e-30), e = ts_max_diff(a.dv, b.dv, n3) / scale;
    const double dres = fabs(a.res.residual - b.res.residual) / fmax(b.res.residual, 1e-30);
    printf("  %-34s %5d particles: iterations group %3d passes %3d, residual %.4g / %.4g (%.1g apart), "
           "iterates %.2g apart, %d restart(s), passes %lld / %lld\n", what, g->n, a.res.iterations,
           b.res.iterations, a.res.residual, b.res.residual, dres, e, (int)a.grp[3], a.passes, b.passes);
    CHECK_EQ_INT(a.st, b.st);
    CHECK_EQ_INT(a.res.iterations, b.res.iterations);
    CHECK_EQ_INT(a.res.converged, b.res.converged);
    CHECK(a.res.residual0 == b.res.residual0 || fabs(a.res.residual0 - b.res.residual0) <= 1e-5 * b.res.residual0);
    CHECK(dres <= rel_res || fabs(a.res.residual - b.res.residual) <= 0.01 * o->tolerance);
    CHECK(e <= rel_dv);
    CHECK(a.passes == 1);   /* one dispatch: its read-backs are no passes */
    free(b.dv);
    return a;
}

static void test_sizes(void) {
    /* 9 .. 2,500 particles (the limit: 2,560); llvmpipe runs one work group on one thread, so the
       largest take a few capped iterations only */
    const int sides[4] = {3, 13, 32, 50};
    for (int k = 0; k < 4; ++k) {
        wc_model m;
        wg_sim* g = NULL;
        wc_state* s = sheet_system(&m, sides[k], 2, &g);
        CHECK(s != NULL && g != NULL);
        if (!s || !g) return;
        wc_solver_opts o = s->def.solver;
        if (k < 2) {
            /* converged solves: each stops where its own float recurrence says, the iterates
               within the tolerance times the system's conditioning of each other */
            o.tolerance = 1e-4;
            o.max_iterations = 400;
            solved a = compare("converged to 1e-4", g, &o, NULL, 2e-4, 0.05);
            CHECK(a.res.converged);
            CHECK(a.st == WC_OK);
            /* from the converged answer: done at once (the start's rules, confirmed) */
            o.tolerance = 1e-3;
            solved b = compare("from its answer, to 1e-3", g, &o, a.dv, 1e-6, 0.05);
            CHECK_EQ_INT(b.res.iterations, 0);
            CHECK(b.res.converged);
            free(a.dv), free(b.dv);
        }
        /* capped: the same float steps (rounding grows with them); 1, 7 and 25 iterations on 169
           particles, 1 and 7 on 9 (27 unknowns: by 25 the float steps only stir rounding), 7 on
           the largest */
        o.tolerance = 0.0;
        const int caps[3] = {1, 7, 25};
        const int from = k < 2 ? 0 : 1, to = k == 1 ? 3 : 2;
        for (int c = from; c < to; ++c) {
            o.max_iterations = caps[c];
            solved p = compare("capped (tolerance 0)", g, &o, NULL, 2e-5 * caps[c], 1e-3);
            CHECK_EQ_INT(p.res.iterations, caps[c]);
            CHECK(!p.res.converged);
            free(p.dv);
        }
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* A tolerance near float's reach: the recurrence says converged where the true residual does not,
 * and the solve restarts from it. A zero right-hand side (b = 0, z = 0): dv = z, converged, no
 * iteration, in both. A non-finite b: diverged in both, dv = z. */
static void test_edges(void) {
    wc_model m;
    wg_sim* g = NULL;
    wc_state* s = sheet_system(&m, 10, 0, &g);
    CHECK(s != NULL && g != NULL);
    if (!s || !g) return;
    wc_solver_opts o = s->def.solver;
    o.max_iterations = 400;
    o.tolerance = 1e-6;
    solved r = compare("tolerance 1e-6 (restarts)", g, &o, NULL, 2e-3, 0.5);
    CHECK(r.grp[3] >= 1.0f);
    free(r.dv);

    tg_zero_and_bad_b(dev, s, g, o, compare);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* WEFT_GPU_SOLVE=group (the device's choice) on a cloth past the group's limit: refused at
 * creation with a message naming the limit, the state untouched; =passes takes it. */
static void test_limit_refused(void) { tg_limit_refused(dev, WC_PRECOND_BLOCK_JACOBI); }

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    if (!dev->compute) {   /* the one-group solve is a compute shader: nothing to compare */
        printf("fragment passes: no one-group solve\n");
    } else {
        RUN_TEST(test_sizes);
        RUN_TEST(test_edges);
        RUN_TEST(test_limit_refused);
    }
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
