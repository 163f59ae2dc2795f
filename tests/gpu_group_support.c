/* Helpers of the one-group PCG tests (gpu_group_support.h). */
#include "gpu_group_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "step.h"
#include "test_support.h"
#include "wg_amg.h"

wg_sim* tg_gpu_system(wg_device* dev, wc_state* s, int planes) {
    wg_sim* g = NULL;
    wc_diag d = {0};
    if (wg_sim_create(dev, s, NULL, &g, &d) != WC_OK) {
        fprintf(stderr, "wg_sim_create: %s\n", d.message);
        return NULL;
    }
    const double h = 1.0 / 30.0;
    wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    const double nrm[3] = {0.26726124, 0.53452248, 0.80178373};   /* (1, 2, 3) / |(1, 2, 3)| */
    for (int i = 0; planes && i < s->model->n_particles; i += 7) {
        if (s->filter.ndof[i] != 0) continue;
        double* S = s->filter.S + 9 * i;
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) S[3 * a + b] = (a == b) - nrm[a] * nrm[b];
            s->filter.z[3 * i + a] = 0.05 * nrm[a];
        }
        s->filter.ndof[i] = 1;
    }
    CHECK(wg_sim_debug_set_system(g, s->A, s->b, &s->filter, &d) == WC_OK);
    return g;
}

wc_state* tg_sheet_system(wg_device* dev, wc_model* m, int n, int warm, double k_scale, wc_precond_type pc,
                          wg_sim** g) {
    *g = NULL;
    if (!ts_sheet(m, n, 1.0, 1.0, 1, k_scale)) return NULL;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = pc;
    def.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) return NULL;
    ts_pin_far_corners(s, n, NULL);
    for (int f = 0; f < warm; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    *g = tg_gpu_system(dev, s, 1);
    return s;
}

tg_solved tg_solve_as(wg_device* dev, wg_sim* g, const wc_solver_opts* o, const double* guess, wg_solve_mode mode) {
    tg_solved r;
    memset(&r, 0, sizeof r);
    r.dv = calloc((size_t)g->n * 3, sizeof(double));
    if (guess) memcpy(r.dv, guess, sizeof(double) * 3 * (size_t)g->n);
    dev->solve = mode;
    wg_sim_debug_set_opts(g, o);
    wc_diag d = {0};
    const long long p0 = wg_sim_debug_passes(g);
    r.st = wg_sim_debug_solve(g, WC_SOLVER_PCG, r.dv, &r.res, &d);
    r.passes = wg_sim_debug_passes(g) - p0;
    if (mode == WG_SOLVE_GROUP) wg_read1(&g->layout, &g->grp, r.grp);
    dev->solve = WG_SOLVE_AUTO;
    return r;
}

void tg_limit_refused(wg_device* dev, wc_precond_type pc) {
    wc_model m;
    const int side = 51;   /* 2,601 particles */
    CHECK(side * side > WG_GROUP_MAX_PARTICLES);
    if (!ts_sheet(&m, side, 1.0, 1.0, 1, 1.0)) return;
    wc_sim_def def = wc_default_sim_def();
    def.solver.preconditioner = pc;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&s, &m, &def, NULL, &d) == WC_OK);
    if (!s) return;
    const double x0 = s->x[0];
    wg_sim* g = NULL;
    dev->solve = WG_SOLVE_GROUP;
    CHECK_EQ_INT(wg_sim_create(dev, s, NULL, &g, &d), WC_ERROR_UNSUPPORTED);
    printf("  %s\n", d.message);
    CHECK(g == NULL);
    CHECK(strstr(d.message, "WEFT_GPU_SOLVE=group") != NULL && strstr(d.message, "2560") != NULL);
    CHECK(s->x[0] == x0);
    dev->solve = WG_SOLVE_PASSES;
    CHECK_EQ_INT(wg_sim_create(dev, s, NULL, &g, &d), WC_OK);
    wg_sim_destroy(g);
    dev->solve = WG_SOLVE_AUTO;
    wc_state_destroy(s);
    wc_model_free(&m);
}

void tg_zero_and_bad_b(wg_device* dev, wc_state* s, wg_sim* g, wc_solver_opts o, tg_compare_fn compare) {
    const int n = g->n;
    wc_diag d = {0};
    double* zero_b = calloc((size_t)n * 3, sizeof(double));
    double* guess = calloc((size_t)n * 3, sizeof(double));
    double* bad = calloc((size_t)n * 3, sizeof(double));
    if (!zero_b || !guess || !bad) {
        CHECK(0);
        free(zero_b), free(guess), free(bad);
        return;
    }
    wc_filter f = s->filter;
    f.z = zero_b;
    CHECK(wg_sim_debug_set_system(g, s->A, zero_b, &f, &d) == WC_OK);
    for (int i = 0; i < 3 * n; ++i) guess[i] = 0.01 * sin((double)i);
    o.tolerance = 1e-4;
    tg_solved zr = compare("zero right-hand side", g, &o, guess, 0.0, 0.0);
    CHECK(zr.res.converged && zr.res.iterations == 0 && zr.res.residual == 0.0);
    CHECK(ts_max_abs(zr.dv, 3 * n) == 0.0);   /* dv = z = 0, the guess dropped */
    free(zr.dv);

    f.z = s->filter.z;
    memcpy(bad, s->b, sizeof(double) * 3 * (size_t)n);
    bad[3 * (n / 2)] = NAN;
    CHECK(wg_sim_debug_set_system(g, s->A, bad, &f, &d) == WC_OK);
    tg_solved a = tg_solve_as(dev, g, &o, NULL, WG_SOLVE_GROUP), b = tg_solve_as(dev, g, &o, NULL, WG_SOLVE_PASSES);
    printf("  non-finite b: status group %d passes %d, residual %g / %g\n", a.st, b.st, a.res.residual, b.res.residual);
    CHECK_EQ_INT(a.st, WC_ERROR_SOLVER_DIVERGED);
    CHECK_EQ_INT(b.st, WC_ERROR_SOLVER_DIVERGED);
    CHECK(!a.res.converged && a.res.residual == b.res.residual);
    CHECK(ts_max_diff(a.dv, b.dv, 3 * n) == 0.0);   /* both dv = z */
    free(a.dv), free(b.dv), free(bad), free(guess), free(zero_b);
}

void tg_vcycle(wg_sim* g, const double* r, double* z) {
    const int n = g->n;
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) g->rb[4 * i + c] = c < 3 ? (float)r[3 * i + c] : 0.0f;
    wg_array_upload(&g->layout, &g->r[0], n, g->rb);
    wg_amg_apply(g->amg, &g->r[0], &g->part);
    wg_array_read(&g->layout, g->amg->z, n, g->rb);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) z[3 * i + c] = g->rb[4 * i + c];
}
