/* The GPU's multigrid preconditioner (gpu/solver/wg_amg.h) on a real EGL context (llvmpipe
 * without a GPU): PCG with it reaches CHOLMOD's answer on real systems (hanging sheets, a stiff
 * one, a sheet draped over a sphere with contacts and friction, one-level sheets whose only level
 * is the dense factor, separate patches whose coarsest level is smoothed, two panels sewn vertex
 * to edge), every smoothed level's Chebyshev bound at or above its lambda_max, in as many
 * iterations as the same method on the CPU (core's multigrid with wg_amg_opts(): a second
 * backend) and in far fewer than with block Jacobi; a stiff sheet at rest stops at float's floor
 * (wg_solve.c) instead of its cap; a whole run matches the CPU's; a context with fragment passes
 * refuses it with a message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "solve_kernels.h"
#include "step.h"
#include "sew_tube.h"
#include "test_support.h"
#include "wg_amg.h"
#include "wg_sim_impl.h"

static wg_gl_context* gl;
static wg_device* dev;

/* A model of quads from arrays (freed here: they are the callers' scratch), sewn at sew (0: no
 * sewing); 0 on failure. */
static int quad_model(wc_model* m, double* pos, int nv, int* sizes, int nq, int* idx, double sew) {
    wc_source_mesh src;
    wc_diag d = {0};
    wc_status st = wc_source_mesh_from_arrays(&src, NULL, pos, nv, sizes, nq, idx, 1.0, &d);
    free(pos), free(sizes), free(idx);
    if (st != WC_OK) return 0;
    wc_model_def mdef = wc_default_model_def();
    mdef.sew_distance = sew;
    st = wc_model_build(m, &src, &mdef, NULL, &d);
    wc_source_mesh_free(&src);
    return st == WC_OK;
}

/* Two vertical q x q-quad panels side by side, GAP apart, B's rows offset by half a row (as
 * sew_tube.h's: every seam pairs a vertex with the middle of the other panel's boundary edge),
 * sewn at SEW, both top rows held, stepped `warm` frames on the CPU, the state rounded to float:
 * vertex-to-edge seams along one edge of a large mesh, whose modes local to the seams the power
 * iterations from a spread start reach last. */
static wc_state* sewn_panels(wc_model* m, int q, int warm) {
    const double dx = 1.0 / q;
    int per = (q + 1) * (q + 1), nv = per + (q + 1) * q, nf = q * q + q * (q - 1);
    double* pos = calloc((size_t)nv * 3, sizeof(double));
    int* sizes = calloc((size_t)nf, sizeof(int));
    int* idx = calloc((size_t)nf * 4, sizeof(int));
    int f = 0;
    for (int p = 0; p < 2; ++p) {
        int rows = p ? q : q + 1, base = p ? per : 0;
        for (int j = 0; j < rows; ++j)
            for (int i = 0; i <= q; ++i) {
                double* x = pos + 3 * (base + j * (q + 1) + i);
                x[0] = p ? 1.0 + GAP + i * dx : i * dx;
                x[1] = 1.0 - (j + 0.5 * p) * dx;
            }
        for (int j = 0; j + 1 < rows; ++j)
            for (int i = 0; i < q; ++i, ++f) {
                int* c = idx + 4 * f;
                sizes[f] = 4;
                c[0] = base + j * (q + 1) + i;
                c[1] = base + (j + 1) * (q + 1) + i;
                c[2] = base + (j + 1) * (q + 1) + i + 1;
                c[3] = base + j * (q + 1) + i + 1;
            }
    }
    if (!quad_model(m, pos, nv, sizes, nf, idx, SEW)) return NULL;
    if (m->n_seams == 0) return NULL;
    wc_diag d = {0};
    wc_sim_def def = ts_amg_def();
    wc_state* s = NULL;
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) return NULL;
    wc_pin* pins = calloc(2 * (size_t)(q + 1), sizeof *pins);
    for (int k = 0; k < 2 * (q + 1); ++k) {
        pins[k].particle = m->host_to_particle[k <= q ? k : per + k - (q + 1)];
        memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
    }
    wc_state_set_pins(s, pins, 2 * (q + 1), &d);
    free(pins);
    for (int k = 0; k < warm; ++k) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    for (int k = 0; k < 3 * m->n_particles; ++k) {
        s->x[k] = (float)s->x[k];
        s->v[k] = (float)s->v[k];
    }
    return s;
}

/* The Chebyshev smoother's bound on each smoothed level of the GPU's last setup (lvl_bound's
 * 1.1 x the Rayleigh quotient, x the finest level's seam factor) against lambda_max(D^-1 A) of
 * the same level of core's hierarchy built with the GPU's method on the same system (cpu, set up
 * by its solve), converged there in double (the larger of 400 power iterations and 60 Lanczos
 * steps). A bound short of lambda_max makes the V-cycle indefinite (docs/design/multigrid.md);
 * returns the smallest bound / lambda_max. */
static double bound_margin(wg_sim* g, wc_amg* cpu, wc_par* par, const char* name) {
    const wg_amg* a = g->amg;
    double worst = 1e300;
    for (int l = 0; l < a->n_levels && l < cpu->n_levels; ++l) {
        if ((l == a->n_levels - 1 && a->dense) || l == cpu->n_levels - 1) break; /* factored here or there */
        float sums[4];
        wg_read1(&g->layout, a->lev[l].bound, sums);
        double q = (double)sums[0] / (double)sums[1];
        double bound = 1.1 * q * wg_amg_bound_scale(a, l);
        wc_amg_level* L = &cpu->lev[l];
        double lmax = fmax(wc_amg_eigen_estimate(L, 400, 0, cpu->opts.pair_blocks, par),
                           wc_amg_eigen_estimate(L, 60, 1, cpu->opts.pair_blocks, par));
        printf("    %s, level %d (%d nodes): bound %.3f (1.1 x %.3f x %.2f), lambda_max %.3f: %.3f x\n", name, l,
               a->lev[l].n, bound, q, wg_amg_bound_scale(a, l), lmax, bound / lmax);
        worst = fmin(worst, bound / lmax);
    }
    return worst;
}

/* One system three ways on the GPU side (multigrid, block Jacobi) and two on the CPU (the same
 * multigrid, CHOLMOD). same_coarse 0: the CPU factors a coarsest level the GPU smooths (more
 * than WG_AMG_DENSE_NODES nodes): the iterations are not compared. at_rest: a stiff sheet's
 * first step, whose residual float cannot compute below ~5e-4 of |b| (the rows' sums cancel
 * terms ~1e4 x larger: wg_solve.c's float floor): both GPU solves stop there, converged as far
 * as float allows, instead of restarting until their cap (3000 iterations before the floor). */
static void check_system(const char* name, wc_model* m, wc_state* s, int same_coarse, int at_rest) {
    const double h = 1.0 / 30.0;
    int n = m->n_particles;
    wc_diag d = {0};
    s->def.solver.tolerance = 1e-4;
    s->def.solver.max_iterations = 3000;
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s\n", d.message);
        return;
    }
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    wc_solver_opts o = s->def.solver;
    o.type = WC_SOLVER_DIRECT;
    wc_solver* direct = NULL;
    CHECK(wc_solver_create(&direct, m, &o, 1, NULL, &d) == WC_OK);
    double* ref = calloc((size_t)n * 3, sizeof(double));
    double* dv = calloc((size_t)n * 3, sizeof(double));
    double* dc = calloc((size_t)n * 3, sizeof(double));
    wc_solve_result rd, rg, rc, rb;
    CHECK(wc_solve(direct, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, ref, &s->par, &rd) == WC_OK);
    CHECK(wg_sim_debug_set_system(g, s->A, s->b, &s->filter, &d) == WC_OK);
    wc_status gs = wg_sim_debug_solve(g, WC_SOLVER_PCG, dv, &rg, &d);
    double err = ts_max_diff(dv, ref, 3 * n) / ts_max_abs(ref, 3 * n);
    /* the same solve by the V-cycle's unfused passes (wg_amg.fuse 0: a pass a smoothing step, the
       residual a pass of its own; the same arithmetic), cold as the first */
    double* du = calloc((size_t)n * 3, sizeof(double));
    wc_solve_result ru;
    g->amg->fuse = 0;
    wg_amg_cold(g->amg);
    CHECK(wg_sim_debug_solve(g, WC_SOLVER_PCG, du, &ru, &d) == gs);
    g->amg->fuse = 1;
    const double fuse_diff = ts_max_diff(du, dv, 3 * n) / ts_max_abs(dv, 3 * n);
    printf("  %-24s fused V-cycles against one pass a step: %d / %d iterations, solutions %.2e apart\n", name,
           rg.iterations, ru.iterations, fuse_diff);
    CHECK_EQ_INT(ru.iterations, rg.iterations);
    CHECK(fuse_diff <= 1e-5);
    free(du);
    /* the CPU's PCG with the same multigrid (core's, built with the GPU's options) */
    o.type = WC_SOLVER_PCG;
    wc_solver* cpu = NULL;
    CHECK(wc_solver_create(&cpu, m, &o, 0, NULL, &d) == WC_OK);
    wc_amg_destroy(cpu->amg);
    cpu->amg = NULL;
    wc_amg_opts ao = wg_amg_opts();
    ao.values = 1;
    CHECK(wc_amg_create(&cpu->amg, m, &ao, &cpu->alloc, &d) == WC_OK);
    wc_solver_set_residual_floor(cpu, wc_state_residual_floor(s, h));
    wc_solve(cpu, WC_SOLVER_PCG, s->A, s->b, &s->filter, dc, &s->par, &rc);
    double err_cpu = ts_max_diff(dc, ref, 3 * n) / ts_max_abs(ref, 3 * n);
    const double margin = bound_margin(g, cpu->amg, &s->par, name);
    /* block Jacobi on the GPU, for scale */
    wc_state* sb = NULL;
    wc_sim_def bdef = s->def;
    bdef.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    wg_sim* gb = NULL;
    CHECK(wc_state_create(&sb, m, &bdef, NULL, &d) == WC_OK);
    CHECK(wg_sim_create(dev, sb, NULL, &gb, &d) == WC_OK);
    memset(dc, 0, sizeof(double) * 3 * (size_t)n);
    CHECK(wg_sim_debug_prepare(gb, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    CHECK(wg_sim_debug_set_system(gb, s->A, s->b, &s->filter, &d) == WC_OK);
    wg_sim_debug_solve(gb, WC_SOLVER_PCG, dc, &rb, &d);
    printf("  %-24s %5d particles, %d levels (coarsest %d nodes, %s): GPU multigrid %3d iterations (residual %.2e, "
           "error vs CHOLMOD %.2e), CPU same method %3d (%.2e), GPU block Jacobi %4d\n",
           name, n, g->amg->n_levels, g->amg->lev[g->amg->n_levels - 1].n, g->amg->dense ? "factored" : "smoothed",
           rg.iterations, rg.residual, err, rc.iterations, err_cpu, rb.iterations);
    CHECK(g->amg->dense == same_coarse);
    CHECK(margin >= 1.0); /* the smoother's bound covers lambda_max on every smoothed level */
    CHECK(gs == WC_OK);
    CHECK(rg.converged);
    CHECK(rb.converged);
    CHECK(rg.residual <= (at_rest ? 1e-3 : 1e-4));
    if (at_rest) CHECK(err <= 1e-3);
    else CHECK(err <= 5.0 * (err_cpu / rc.residual) * rg.residual + 1e-4);
    /* float against double: the same method within a few iterations */
    if (same_coarse) CHECK(rg.iterations <= 1.5 * rc.iterations + 3);
    if (n > 500) CHECK(3 * rg.iterations < rb.iterations);
    if (at_rest) CHECK(rb.iterations < 1000);
    if (g->amg->n_levels == 1) CHECK(rg.iterations <= 3); /* one level: the dense factor is the inverse (in float) */
    wg_sim_destroy(gb);
    wc_state_destroy(sb);
    wc_solver_destroy(cpu);
    wc_solver_destroy(direct);
    free(ref), free(dv), free(dc);
    wg_sim_destroy(g);
}

static void test_solves(void) {
    static const struct {
        const char* name;
        int kind, n, warm, same_coarse, at_rest; /* kind 0: hanging n x n; 1: draped; 2: 40 patches;
                                                    3: two n x n panels sewn */
        double k_scale;
    } cases[] = {
        {"hanging 32 x 32", 0, 32, 3, 1, 0, 1.0},
        {"hanging 32 x 32, at rest", 0, 32, 0, 1, 1, 1.0},
        {"hanging 64 x 64, k x1000", 0, 64, 3, 1, 0, 1000.0},
        {"draped over a sphere", 1, 24, 20, 1, 0, 1.0},
        {"hanging 4 x 4 (one level)", 0, 4, 3, 1, 0, 1.0},
        {"hanging 5 x 5 (one level)", 0, 5, 3, 1, 0, 1.0},
        {"40 separate patches", 2, 40, 3, 0, 0, 1.0},
        {"two panels sewn, 24 x 24", 3, 24, 3, 1, 0, 1.0},
    };
    const wc_sim_def def = ts_amg_def();
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        wc_model m;
        wc_state* s = cases[k].kind == 0   ? ts_hanging_float(&m, cases[k].n, cases[k].warm, cases[k].k_scale)
                      : cases[k].kind == 1 ? ts_draped(&m, cases[k].n, &def, cases[k].warm)
                      : cases[k].kind == 2 ? ts_patches(&m, cases[k].n, &def)
                                           : sewn_panels(&m, cases[k].n, cases[k].warm);
        CHECK(s != NULL);
        if (!s) return;
        if (cases[k].kind == 1) {
            printf("  draped: %d particles in contact\n", s->contacts.active);
            CHECK(s->contacts.active >= 20);
        }
        check_system(cases[k].name, &m, s, cases[k].same_coarse, cases[k].at_rest);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* 60 frames of a 16 x 16 sheet falling from two pins, GPU (multigrid) against CPU (its default
 * multigrid): both converge every solve, so the end states agree to float rounding. */
static void test_whole_run(void) {
    wc_model m;
    if (!ts_sheet(&m, 16, 1.0, 1.0, 0, 1.0)) return;
    wc_sim_def def = ts_amg_def();
    wc_state *c = NULL, *s = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&c, &m, &def, NULL, &d) == WC_OK);
    CHECK(wc_state_create(&s, &m, &def, NULL, &d) == WC_OK);
    ts_pin_far_corners(c, 16, NULL);
    ts_pin_far_corners(s, 16, NULL);
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) return;
    int ok = 1, it_g = 0, it_c = 0, n = m.n_particles;
    wc_step_stats sg, sc;
    for (int f = 0; f < 60 && ok; ++f) {
        ok &= wg_sim_step_frame(g, s, 1.0 / 30.0, &sg, &d) == WC_OK;
        ok &= wc_step_frame(c, 1.0 / 30.0, &sc, &d) == WC_OK;
        it_g += sg.iterations;
        it_c += sc.iterations;
    }
    CHECK(ok);
    CHECK(wg_sim_download(g, s, &d) == WC_OK);
    double e = ts_max_diff(s->x, c->x, 3 * n);
    printf("  60 frames: max |x_gpu - x_cpu| = %.3g m; PCG iterations GPU %d, CPU %d\n", e, it_g, it_c);
    CHECK(e < 0.002);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_state_destroy(c);
    wc_model_free(&m);
}

/* Fragment passes have no multigrid: the cloth is refused, naming what would work. */
static void test_fragment_refused(void) {
    wc_model m;
    if (!ts_sheet(&m, 8, 1.0, 1.0, 0, 1.0)) return;
    wc_sim_def def = ts_amg_def();
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK(wc_state_create(&s, &m, &def, NULL, &d) == WC_OK);
    int compute = dev->compute;
    dev->compute = 0;
    wg_sim* g = NULL;
    wc_status st = wg_sim_create(dev, s, NULL, &g, &d);
    dev->compute = compute;
    printf("  fragment passes: %s\n", d.message);
    CHECK(st == WC_ERROR_UNSUPPORTED);
    CHECK(g == NULL);
    CHECK(strstr(d.message, "compute-shader") != NULL && strstr(d.message, "block_jacobi") != NULL);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    if (dev->compute) {
        RUN_TEST(test_solves);
        RUN_TEST(test_whole_run);
    }
    RUN_TEST(test_fragment_refused);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
