/* The GPU FBO solver (gpu/solver) against the CPU code on the same input, on a real EGL context
 * (llvmpipe without a GPU): the assembled system (A and b, relative 1e-5 in float), the filter,
 * SpMV, reductions on sizes that are not powers of two, every GPU solver against CHOLMOD's
 * direct solve of the same system, and whole runs GPU vs CPU; uploads of a span of an array. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"
#include "wg_compute.h"
#include "wg_passes.h"
#include "wg_sim_impl.h"

static wg_gl_context* gl;
static wg_device* dev;

/* A hanging n x n sheet pinned at its two top corners (the thesis's scene), stepped `warm`
 * frames on the CPU so that the system is not the trivial rest one. */
static wc_state* sheet_state(wc_model* m, int n, wc_solver_type solver, int warm, int vertical) {
    if (!ts_sheet(m, n, 1.0, 1.0, vertical, 1.0)) return NULL;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = solver;
    def.sleep_speed = 0.0;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        return NULL;
    }
    wc_pin pins[2] = {{ts_sheet_particle(m, n, 0, n - 1), {0, 0, 0}, {0, 0, 0}},  /* top corners */
                      {ts_sheet_particle(m, n, n - 1, n - 1), {0, 0, 0}, {0, 0, 0}}};
    for (int k = 0; k < 2; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
    wc_state_set_pins(s, pins, 2, &d);
    for (int f = 0; f < warm; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    /* the same input on both backends: the state rounded to what the GPU's float textures hold */
    for (int k = 0; k < 3 * m->n_particles; ++k) {
        s->x[k] = (float)s->x[k];
        s->v[k] = (float)s->v[k];
        s->dv[k] = (float)s->dv[k];
    }
    for (int k = 0; k < s->n_pins; ++k)
        for (int c = 0; c < 3; ++c) s->pins[k].target[c] = s->pin_from[3 * k + c] = (float)s->pins[k].target[c];
    return s;
}

static wc_state* hanging(wc_model* m, int n, wc_solver_type solver, int warm) {
    return sheet_state(m, n, solver, warm, 1);
}

/* The GPU's q = A x for a fresh random x against core's product with the CPU's A (relative). */
static double spmv_error(wg_sim* g, const wc_model* m, wc_state* s, double* x, double* y, double* yc) {
    int n = m->n_particles;
    wc_diag d = {0};
    for (int k = 0; k < 3 * n; ++k) x[k] = (double)rand() / RAND_MAX - 0.5;
    CHECK(wg_sim_debug_spmv(g, x, y, &d) == WC_OK);
    wc_bsr_mul(&m->pattern, s->A, x, yc, &s->par);
    return ts_max_diff(y, yc, 3 * n) / ts_max_abs(yc, 3 * n);
}

static void test_assembly_and_spmv(void) {
    wc_model m;
    wc_state* s = hanging(&m, 13, WC_SOLVER_PCG, 5);
    CHECK(s != NULL);
    if (!s) return;
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        fprintf(stderr, "%s\n", d.message);
        return;
    }
    int n = m.n_particles, nb = m.pattern.n_blocks;
    double h = 1.0 / 30.0;
    double* A = calloc((size_t)nb * 9, sizeof(double));
    double* b = calloc((size_t)n * 3, sizeof(double));
    double* S = calloc((size_t)n * 9, sizeof(double));
    double* z = calloc((size_t)n * 3, sizeof(double));
    unsigned char* ndof = calloc((size_t)n, 1);
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, A, b, S, z, ndof, NULL, &d) == WC_OK);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    /* b is a small sum of large terms: spring forces k (l - rest) near equilibrium against gravity.
       In float, l carries a rounding of ~6e-8 l, so each term k (l - rest) one of ~6e-8 k l: b's
       error is relative to h k l, the size of the terms float rounds (A's to its largest entry). */
    double sa = ts_max_abs(s->A, 9 * nb), kl = 0.0;
    for (int k = 0; k < m.n_springs; ++k) kl = fmax(kl, m.material.k[m.springs[k].type] * m.springs[k].rest);
    double ea = ts_max_diff(A, s->A, 9 * nb) / sa, eb = ts_max_diff(b, s->b, 3 * n) / (h * kl);
    printf("  13x13 sheet: A relative error %.2e, b %.2e (of h k l)\n", ea, eb);
    CHECK(ea < 1e-5);
    CHECK(eb < 1e-5);
    CHECK(ts_max_diff(S, s->filter.S, 9 * n) < 1e-6);
    CHECK(ts_max_diff(z, s->filter.z, 3 * n) < 1e-5 * (1.0 + ts_max_abs(s->filter.z, 3 * n)));
    int same_ndof = 1;
    for (int i = 0; i < n; ++i) same_ndof &= ndof[i] == s->filter.ndof[i];
    CHECK(same_ndof);

    /* SpMV with the GPU's A against core's with the CPU's A */
    double* x = calloc((size_t)n * 3, sizeof(double));
    double* y = calloc((size_t)n * 3, sizeof(double));
    double* yc = calloc((size_t)n * 3, sizeof(double));
    srand(3);
    double es = spmv_error(g, &m, s, x, y, yc);
    printf("  SpMV relative error %.2e\n", es);
    CHECK(es < 1e-5);
    if (dev->compute) {
        /* the compute SpMV's 3 work groups in rows of one (the 2D dispatch of a cloth past
           65535 groups, ~4M particles), on a new x (rows the dispatch missed would keep the
           last product) */
        int keep = dev->max_groups_x;
        dev->max_groups_x = 1;
        double e2 = spmv_error(g, &m, s, x, y, yc);
        printf("  SpMV in a 2D dispatch (groups in rows of 1): relative error %.2e\n", e2);
        CHECK(e2 < 1e-5);
        dev->max_groups_x = keep;
    }
    free(A), free(b), free(S), free(z), free(ndof), free(x), free(y), free(yc);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

static void test_reductions_and_large_sheet(void) {
    wc_model m;
    wc_state* s = hanging(&m, 300, WC_SOLVER_PCG, 0);   /* 90,000 particles */
    CHECK(s != NULL);
    if (!s) return;
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) return;
    const int sizes[] = {1, 7, 1000, 4097, 90000};
    double* v = calloc(90000, sizeof(double));
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; ++k) {
        int n = sizes[k];
        double sum = 0.0, mx = -1.0;
        for (int i = 0; i < n; ++i) {
            v[i] = 0.25 + (double)((i * 7919) % 1000) / 1000.0;
            sum += (float)v[i];
            mx = fmax(mx, (float)v[i]);
        }
        v[n / 2] = 3.5;   /* the maximum somewhere inside */
        sum += 3.5 - (float)(0.25 + (double)(((n / 2) * 7919) % 1000) / 1000.0);
        double gs = wg_sim_debug_reduce(g, v, n, 0), gm = wg_sim_debug_reduce(g, v, n, 1);
        printf("  reduce %6d: sum %.7g (exact %.7g), max %.7g\n", n, gs, sum, gm);
        CHECK(fabs(gs - sum) <= 1e-6 * sum + 1e-6);
        CHECK(gm == 3.5);
    }
    /* +inf (the checks' mark of a non-finite state) in a max reduction stays +inf: the levels
       once blended sum and max with float weights, and 0 inf is NaN */
    for (int i = 0; i < 4097; ++i) v[i] = 1.0;
    v[2000] = INFINITY;
    double gi = wg_sim_debug_reduce(g, v, 4097, 1);
    printf("  reduce   4097 with +inf: max %g\n", gi);
    CHECK(isinf(gi) && gi > 0.0);
    free(v);
    /* and the 300 x 300 sheet steps on the GPU (30 PCG iterations: llvmpipe is slow) */
    s->def.solver.max_iterations = 30;
    wc_step_stats st;
    wc_status r = wg_sim_step_frame(g, s, 1.0 / 30.0, &st, &d);
    CHECK(wg_sim_download(g, s, &d) == WC_OK);
    int finite = 1;
    for (int k = 0; k < 3 * m.n_particles; ++k) finite &= isfinite(s->x[k]) != 0;
    printf("  300 x 300 sheet: one frame on the GPU, status %d, %d iterations, max strain %.3g\n", (int)r,
           st.iterations, st.max_strain);
    CHECK(r == WC_OK);
    CHECK(finite);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Each GPU solver on systems from real steps (a sheet hanging from pins; a sheet draped over a
 * sphere: contacts with friction) against CHOLMOD on the same (CPU-assembled) system: converged
 * to its tolerance, and as close to the direct solution as the CPU's own solver at that
 * tolerance. */
/* A 10 x 10 sheet dropped on a sphere and draped over it for 20 frames on the CPU: contacts and
 * friction in the system. */
static wc_state* draped(wc_model* m, wc_solver_type solver) {
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = solver;
    def.sleep_speed = 0.0;
    return ts_draped(m, 10, &def, 20);
}

static void test_solvers_vs_direct(void) {
    const wc_solver_type types[3] = {WC_SOLVER_PCG, WC_SOLVER_JACOBI, WC_SOLVER_CHEBYSHEV};
    for (int k = 0; k < 6; ++k) {
        wc_model m;
        wc_state* s = k < 3 ? hanging(&m, 10, types[k], 3) : draped(&m, types[k % 3]);
        CHECK(s != NULL);
        if (!s) return;
        if (k >= 3) printf("  draped over a sphere: %d particles in contact\n", s->contacts.active);
        if (k >= 3) CHECK(s->contacts.active >= 4);
        const wc_solver_type type = types[k % 3];
        s->def.solver.tolerance = 1e-4;
        s->def.solver.max_iterations = type == WC_SOLVER_JACOBI ? 30000 : 3000;
        wc_diag d = {0};
        wg_sim* g = NULL;
        CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
        if (!g) return;
        int n = m.n_particles;
        double h = 1.0 / 30.0;
        CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
        wc_step_stats st;
        memset(&st, 0, sizeof st);
        wc_substep_prepare(s, h, 1.0, &st);
        wc_solver* direct = NULL;
        wc_solver_opts o = s->def.solver;
        o.type = WC_SOLVER_DIRECT;
        CHECK(wc_solver_create(&direct, &m, &o, 1, NULL, &d) == WC_OK);
        double* ref = calloc((size_t)n * 3, sizeof(double));
        double* dv = calloc((size_t)n * 3, sizeof(double));
        wc_solve_result rd, rg;
        CHECK(wc_solve(direct, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, ref, &s->par, &rd) == WC_OK);
        /* the same system on both (the CPU's A and b rounded to float): solvers, not assemblies, compared */
        CHECK(wg_sim_debug_set_system(g, s->A, s->b, &s->filter, &d) == WC_OK);
        wc_status gs = wg_sim_debug_solve(g, type, dv, &rg, &d);
        double err = ts_max_diff(dv, ref, 3 * n) / ts_max_abs(ref, 3 * n);
        /* the CPU's own solver at the same tolerance: the error any solver stopping there has */
        wc_solver* cpu = NULL;
        o.type = type;
        CHECK(wc_solver_create(&cpu, &m, &o, 0, NULL, &d) == WC_OK);
        wc_solver_set_residual_floor(cpu, wc_state_residual_floor(s, h)); /* as the GPU's prepare set its own */
        double* dc = calloc((size_t)n * 3, sizeof(double));
        wc_solve_result rc;
        wc_solve(cpu, type, s->A, s->b, &s->filter, dc, &s->par, &rc);
        double err_cpu = ts_max_diff(dc, ref, 3 * n) / ts_max_abs(ref, 3 * n);
        if (type == WC_SOLVER_CHEBYSHEV) {
            /* the same start vector (lanczos_start.glsl ports core's splitmix64): the same
               estimate to float rounding (with a 32-bit hash instead the drape's differed by
               1.4e-3: 0.9995 against 0.998119) */
            double rho_g = wg_sim_debug_rho(g), rho_c = wc_solver_estimate_rho(cpu, s->A, &s->filter, &s->par);
            printf("  chebyshev rho: GPU %.6f, CPU %.6f\n", rho_g, rho_c);
            CHECK(fabs(rho_g - rho_c) < 1e-4);
        }
        printf("  %-9s GPU: %5d iterations, residual %.2e (%s), error vs CHOLMOD %.2e; CPU: %5d, %.2e, %.2e\n",
               wc_solver_name(type), rg.iterations, rg.residual, rg.converged ? "converged" : "not converged", err,
               rc.iterations, rc.residual, err_cpu);
        CHECK(gs == WC_OK);
        CHECK(rg.converged);
        CHECK(rg.residual <= 1e-4);
        /* the error left at a given residual is the system's conditioning: per unit of residual,
           the GPU's within 5x of the CPU's own solver's (each stops at a residual of its own
           direction) */
        CHECK(err <= 5.0 * (err_cpu / rc.residual) * rg.residual + 1e-4);
        if (type == WC_SOLVER_CHEBYSHEV) {
            /* capped at 20 iterations from a non-zero initial guess, in a solve that estimates
               rho first (on the GPU its Lanczos steps once overwrote the initial guess): the GPU
               and the CPU stop at about the same residual */
            wc_solver_opts co = o;
            co.max_iterations = 20;
            wc_solver* capped = NULL;
            CHECK(wc_solver_create(&capped, &m, &co, 0, NULL, &d) == WC_OK);
            for (int q = 0; q < 3 * n; ++q) dc[q] = dv[q] = 0.5 * ref[q];
            wc_solve(capped, WC_SOLVER_CHEBYSHEV, s->A, s->b, &s->filter, dc, &s->par, &rc);
            wg_sim_debug_invalidate_rho(g);
            s->def.solver.max_iterations = 20;
            wg_sim_debug_set_opts(g, &co);
            wg_sim_debug_solve(g, WC_SOLVER_CHEBYSHEV, dv, &rg, &d);
            printf("  chebyshev capped at 20 from dv = ref / 2: residual GPU %.3g, CPU %.3g\n", rg.residual, rc.residual);
            CHECK(rg.residual <= 2.0 * rc.residual + 1e-4);
            wc_solver_destroy(capped);
        }
        free(dc);
        wc_solver_destroy(cpu);
        free(ref), free(dv);
        wc_solver_destroy(direct);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* PCG's dot products as the solve takes them (compute passes: per-work-group partial sums folded
 * into the SpMV and the update, finished by the scalars pass) against double sums of the same
 * float vectors read back, over row counts around the work groups' 64 and 256 rows; then PCG's
 * iterates capped at 1, 5 and 20 iterations against core's PCG on the same float system. */
static void test_pcg_dots_and_iterates(void) {
    wc_model m;
    wc_state* s = hanging(&m, 32, WC_SOLVER_PCG, 1);
    CHECK(s != NULL);
    if (!s) return;
    s->def.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) return;
    const int n = m.n_particles;
    const double h = 1.0 / 30.0;
    CHECK(wg_sim_debug_prepare(g, s, h, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, h, 1.0, &st);
    CHECK(wg_sim_debug_set_system(g, s->A, s->b, &s->filter, &d) == WC_OK);
    double *c = calloc((size_t)n * 3, sizeof(double)), *r = calloc((size_t)n * 3, sizeof(double));
    double *q = calloc((size_t)n * 3, sizeof(double)), *t = calloc((size_t)n * 3, sizeof(double));
    const int rows[5] = {1, 63, 64, 65, 1000};
    for (int k = 0; k < 5; ++k) {
        /* c filtered and zero past the rows: c.q = c.A c > 0 (the scalars pass takes its root) */
        for (int i = 0; i < n; ++i) {
            double u[3], f[3];
            for (int j = 0; j < 3; ++j) {
                u[j] = (double)rand() / RAND_MAX - 0.5;
                r[3 * i + j] = (float)((double)rand() / RAND_MAX - 0.5);
            }
            wc_filter_apply(&s->filter, i, u, f);
            for (int j = 0; j < 3; ++j) c[3 * i + j] = i < rows[k] ? (float)f[j] : 0.0;
        }
        double dots[3];
        CHECK(wg_sim_debug_pcg_dots(g, rows[k], c, r, q, t, dots, &d) == WC_OK);
        double ref[3] = {0, 0, 0}, mag[3] = {0, 0, 0};
        for (int i = 0; i < 3 * rows[k]; ++i) {
            const double term[3] = {c[i] * q[i], r[i] * t[i], r[i] * r[i]};
            for (int j = 0; j < 3; ++j) ref[j] += term[j], mag[j] += fabs(term[j]);
        }
        double worst = 0.0;
        for (int j = 0; j < 3; ++j) worst = fmax(worst, fabs(dots[j] - ref[j]) / fmax(mag[j], 1e-300));
        printf("  %4d rows: c.q %.9g (double %.9g), r.t %.9g (%.9g), r.r %.9g (%.9g): %.2g of the terms' sum\n",
               rows[k], dots[0], ref[0], dots[1], ref[1], dots[2], ref[2], worst);
        /* a float sum of m terms in a tree: within ~log2(m) 2^-24 of the sum of their magnitudes */
        CHECK(worst <= 1e-6);
        CHECK(ref[0] >= 0.0);
    }
    wc_solver_opts o = s->def.solver;
    o.tolerance = 0.0;
    o.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    const int caps[3] = {1, 5, 20};
    for (int k = 0; k < 3; ++k) {
        o.max_iterations = caps[k];
        wg_sim_debug_set_opts(g, &o);
        memset(q, 0, sizeof(double) * 3 * (size_t)n);
        memset(t, 0, sizeof(double) * 3 * (size_t)n);
        wc_solve_result rg, rc;
        wg_sim_debug_solve(g, WC_SOLVER_PCG, q, &rg, &d);
        wc_solver* cpu = NULL;
        CHECK(wc_solver_create(&cpu, &m, &o, 0, NULL, &d) == WC_OK);
        if (!cpu) break;
        wc_solver_set_residual_floor(cpu, wc_state_residual_floor(s, h));
        wc_solve(cpu, WC_SOLVER_PCG, s->A, s->b, &s->filter, t, &s->par, &rc);
        double e = ts_max_diff(q, t, 3 * n) / ts_max_abs(t, 3 * n);
        printf("  PCG capped at %2d: iterations GPU %d CPU %d, residual GPU %.4g CPU %.4g, iterates %.2g apart\n", caps[k],
               rg.iterations, rc.iterations, rg.residual, rc.residual, e);
        CHECK(rg.iterations == rc.iterations);
        /* float's rounding grows with the iterations (5.1e-8, 2.9e-6, 9.7e-5 here) */
        CHECK(e <= 2e-5 * caps[k]);
        CHECK(fabs(rg.residual - rc.residual) <= 1e-3 * rc.residual);
        wc_solver_destroy(cpu);
    }
    /* a row count out of range: refused, nothing run */
    CHECK(wg_sim_debug_pcg_dots(g, 0, c, r, q, t, (double[3]){0}, &d) == WC_ERROR_INVALID_ARGUMENT);
    CHECK(wg_sim_debug_pcg_dots(g, n + 1, c, r, q, t, (double[3]){0}, &d) == WC_ERROR_INVALID_ARGUMENT);
    free(c), free(r), free(q), free(t);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* A system that cannot be solved (a NaN velocity makes b non-finite): every GPU solver reports
 * SOLVER_DIVERGED as the CPU does, and leaves a finite dv (= z). */
static void test_divergence(void) {
    const wc_solver_type types[3] = {WC_SOLVER_PCG, WC_SOLVER_JACOBI, WC_SOLVER_CHEBYSHEV};
    for (int k = 0; k < 3; ++k) {
        wc_model m;
        wc_state* s = hanging(&m, 8, types[k], 0);
        if (!s) return;
        wc_diag d = {0};
        s->v[3 * 5 + 1] = NAN;
        wg_sim* g = NULL;
        CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
        if (!g) return;
        int n = m.n_particles;
        CHECK(wg_sim_debug_prepare(g, s, 1.0 / 30.0, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d) == WC_OK);
        wc_solve_result r;
        double* dv = calloc((size_t)n * 3, sizeof(double));
        wc_status st = wg_sim_debug_solve(g, types[k], dv, &r, &d);
        int finite = 1;
        for (int q = 0; q < 3 * n; ++q) finite &= isfinite(dv[q]) != 0;
        /* the CPU on the same input */
        wc_step_stats sst;
        memset(&sst, 0, sizeof sst);
        wc_substep_prepare(s, 1.0 / 30.0, 1.0, &sst);
        wc_solver* cpu = NULL;
        CHECK(wc_solver_create(&cpu, &m, &s->def.solver, 0, NULL, &d) == WC_OK);
        double* dc = calloc((size_t)n * 3, sizeof(double));
        wc_solve_result rc;
        wc_status sc = wc_solve(cpu, types[k], s->A, s->b, &s->filter, dc, &s->par, &rc);
        printf("  %-9s NaN in b: GPU status %d, CPU status %d\n", wc_solver_name(types[k]), (int)st, (int)sc);
        CHECK(finite);
        CHECK(st == WC_ERROR_SOLVER_DIVERGED);
        CHECK(sc == WC_ERROR_SOLVER_DIVERGED);
        /* the cloth made finite again: the next solve must not inherit the NaN the diverged one
           left in the solver's textures. PCG's start once formed S (t + 0 c) from the old c:
           0 NaN is NaN on NVIDIA's driver (seen there with a new texture's stale contents), while
           llvmpipe folds 0 x to 0, so on llvmpipe this passed before the fix too */
        s->v[3 * 5 + 1] = 0.0;
        wc_substep_prepare(s, 1.0 / 30.0, 1.0, &sst);
        CHECK(wg_sim_debug_set_system(g, s->A, s->b, &s->filter, &d) == WC_OK);
        memset(dv, 0, (size_t)n * 3 * sizeof(double));
        wc_solve_result r2;
        wc_status st2 = wg_sim_debug_solve(g, types[k], dv, &r2, &d);
        finite = 1;
        for (int q = 0; q < 3 * n; ++q) finite &= isfinite(dv[q]) != 0;
        printf("  %-9s then a finite system: GPU status %d, %d iterations, residual %.2e\n", wc_solver_name(types[k]),
               (int)st2, r2.iterations, r2.residual);
        CHECK_EQ_INT(st2, WC_OK);
        CHECK(finite);
        if (types[k] == WC_SOLVER_PCG) CHECK(r2.converged);
        free(dv), free(dc);
        wc_solver_destroy(cpu);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* 60 frames of a sheet that starts horizontal and swings down from two corners, on both
 * backends: the same trajectory within 0.2 % of the cloth's size with PCG, 2 % with Chebyshev. The remainder: float (GPU) vs
 * double (CPU) arithmetic, amplified by solves that stop at a relative residual of 1e-4 (each
 * backend's iterates differ at that level) over 60 chaotic-ish frames of a swinging sheet. */
static void test_whole_run(void) {
    const wc_solver_type types[2] = {WC_SOLVER_PCG, WC_SOLVER_CHEBYSHEV};
    for (int k = 0; k < 2; ++k) {
        wc_model m;
        wc_state* c = sheet_state(&m, 16, types[k], 0, 0);
        if (!c) return;
        wc_state* s = NULL;
        wc_diag d = {0};
        wc_state_create(&s, &m, &c->def, NULL, &d);
        wc_state_set_pins(s, c->pins, c->n_pins, &d);
        wg_sim* g = NULL;
        CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
        if (!g) return;
        int ok = 1, n = m.n_particles;
        wc_step_stats sg, sc;
        int iters_g = 0, iters_c = 0;
        for (int f = 0; f < 60 && ok; ++f) {
            ok &= wg_sim_step_frame(g, s, 1.0 / 30.0, &sg, &d) == WC_OK;
            if (!ok) fprintf(stderr, "GPU frame %d: %s\n", f, d.message);
            ok &= wc_step_frame(c, 1.0 / 30.0, &sc, &d) == WC_OK;
            iters_g += sg.iterations;
            iters_c += sc.iterations;
        }
        CHECK(ok);
        CHECK(wg_sim_download(g, s, &d) == WC_OK);
        double e = ts_max_diff(s->x, c->x, 3 * n);
        double drop = c->x[3 * ts_sheet_particle(&m, 16, 0, 0) + 1] - 1.0;
        printf("  60 frames, %-9s: max |x_gpu - x_cpu| = %.3g m on a 1 m sheet (its far corner moved %.3g m); "
               "iterations GPU %d CPU %d\n", wc_solver_name(types[k]), e, drop, iters_g, iters_c);
        CHECK(fabs(drop) > 0.3);
        /* PCG converges every solve (|x| differences are float rounding carried by 60 frames);
           Chebyshev stops at its 300-iteration cap in most frames on both backends, so each
           follows its own unconverged iterates */
        CHECK(e < (types[k] == WC_SOLVER_PCG ? 0.002 : 0.02));
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_state_destroy(c);
        wc_model_free(&m);
    }
}

/* A mesh larger than the device's textures is refused with a message naming the sizes (the
 * device's limit lowered to 4 texels for the test), and the state is untouched. */
static void test_texture_limit(void) {
    wc_model m;
    wc_state* s = hanging(&m, 13, WC_SOLVER_PCG, 0);
    if (!s) return;
    int saved = dev->max_texture_size;
    dev->max_texture_size = 4;
    wc_diag d = {0};
    wg_sim* g = NULL;
    double x0 = s->x[0];
    wc_status st = wg_sim_create(dev, s, NULL, &g, &d);
    dev->max_texture_size = saved;
    printf("  texture limit 4: status %d, \"%s\"\n", (int)st, d.message);
    CHECK(st == WC_ERROR_GPU);
    CHECK(g == NULL);
    CHECK(strstr(d.message, "169 particles") != NULL && strstr(d.message, "4 x 4") != NULL);
    CHECK(s->x[0] == x0);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* wg_array_upload_range replaces exactly its items: a span inside a row, spans across rows (a
 * partial first row, whole rows, a partial last one), a whole row, the whole array; checked
 * against a host copy of what the array must hold after each upload. */
static void test_upload_range(void) {
    wg_layout L;
    char err[256] = "";
    CHECK(wg_layout_init(&L, 10, dev->max_texture_size, (wc_allocator){0}, err, sizeof err));
    const int n = 3500;   /* rows of 1,024 items: three whole, the fourth partial */
    float* want = calloc(4 * (size_t)n, sizeof(float));
    float* got = malloc(4 * (size_t)n * sizeof(float));
    float* src = malloc(4 * (size_t)n * sizeof(float));
    wg_tex t;
    memset(&t, 0, sizeof t);
    CHECK(wg_array_create(&L, &t, GL_RGBA32F, n, NULL, err, sizeof err));
    static const int span[][2] = {{5, 4}, {1000, 1100}, {1024, 1024}, {2047, 1453}, {3071, 1}, {0, 3500}};
    int same = 1;
    for (size_t k = 0; k < sizeof span / sizeof span[0]; ++k) {
        int first = span[k][0], count = span[k][1];
        for (int i = 0; i < 4 * count; ++i) src[i] = (float)(1000 * (k + 1) + i);
        memcpy(want + 4 * (size_t)first, src, 4 * (size_t)count * sizeof(float));
        wg_array_upload_range(&L, &t, first, count, src);
        wg_array_read(&L, &t, n, got);
        int ok = memcmp(got, want, 4 * (size_t)n * sizeof(float)) == 0;
        if (!ok) printf("  span [%d, %d): the array differs\n", first, first + count);
        same = same && ok;
    }
    CHECK(same);
    CHECK(glGetError() == GL_NO_ERROR);
    wg_tex_destroy(&t);
    wg_layout_destroy(&L);
    free(want);
    free(got);
    free(src);
}

/* The direct solver does not exist on the GPU: refused, with the reason. */
static void test_direct_refused(void) {
    wc_model m;
    wc_state* s = hanging(&m, 6, WC_SOLVER_DIRECT, 0);
    if (!s) return;
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_ERROR_UNSUPPORTED);
    CHECK(g == NULL && strstr(d.message, "no direct solver") != NULL);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* wg_compute.c's transformation of a pass source, on an awkward one: a comment that names
 * #version before the directive, a line longer than any fixed buffer, a vec2 output. */
static void test_compute_source(void) {
    char src[2048];
    int at = snprintf(src, sizeof src,
                      "// the #version line comes next\n#version 330 core\nuniform int u_n;\nout vec4 o0;\nout vec2 o1;\n"
                      "void main() { float s = 0.0");
    for (int k = 0; k < 60; ++k) at += snprintf(src + at, sizeof src - (size_t)at, " + gl_FragCoord.x");
    snprintf(src + at, sizeof src - (size_t)at, "; o0 = vec4(s); o1 = vec2(gl_FragCoord.y); }\n");
    char* cs = wg_compute_source(gl, src);
    CHECK(cs != NULL);
    if (!cs) return;
    CHECK(strncmp(cs, "#version 430 core\n", 18) == 0);
    CHECK(strstr(cs, "gl_FragCoord") == NULL);
    CHECK(strstr(cs, "\nvec4 o0;") != NULL && strstr(cs, "\nvec2 o1;") != NULL);
    CHECK(strstr(cs, "void wg_main() { float s = 0.0 + wg_frag_coord.x") != NULL);
    CHECK(strstr(cs, "o1 = vec2(wg_frag_coord.y); }") != NULL);   /* the end of the 1000-character line */
    CHECK(strstr(cs, "if (u_wg_nout > 1) imageStore(wg_img1, p, vec4(o1, 0.0, 0.0));") != NULL);
    if (GLEW_VERSION_4_3) {   /* and it compiles */
        wg_program prog;
        char err[512] = "";
        int ok = wg_program_build_compute(&prog, "test", cs, err, sizeof err);
        if (!ok) printf("  %s\n", err);
        CHECK(ok);
        if (ok) wg_program_destroy(&prog);
    }
    wg_gl_free(gl, cs);
    CHECK(wg_compute_source(gl, "void main() {}\n") == NULL);   /* no #version line */
}

/* A pass's input table against its program (wg_passes.h): the samplers the shader reads are
 * exactly the table's names, bound to units in the table's order (a declared but unread sampler
 * is no input); a name missing from either side is refused, naming the pass and the uniform. */
static void test_pass_inputs(void) {
    static const char fs[] = "#version 330 core\n"
                             "uniform sampler2D x;\n"
                             "uniform isampler2D rows;\n"
                             "uniform sampler2D unread;\n"
                             "out vec4 o0;\n"
                             "void main() { o0 = texelFetch(x, ivec2(0), 0) + vec4(texelFetch(rows, ivec2(0), 0)); }\n";
    typedef struct probe_in {
        const wg_tex *x, *rows, *y;
    } probe_in;
    const wg_pass_input exact[] = {{"rows", offsetof(probe_in, rows)}, {"x", offsetof(probe_in, x)}};
    const wg_pass_input missing[] = {{"rows", offsetof(probe_in, rows)}, {"x", offsetof(probe_in, x)},
                                     {"y", offsetof(probe_in, y)}};
    const wg_pass_input extra[] = {{"x", offsetof(probe_in, x)}};
    wg_program prog;
    char err[512] = "";
    CHECK(wg_program_build(&prog, "probe", wg_fullscreen_vs, fs, err, sizeof err));
    if (!prog.id) return;
    wg_pass_info pass = {"probe", exact, 2, sizeof(probe_in), 0, 0};
    CHECK(wg_pass_bind_inputs(prog.id, &pass, err, sizeof err));
    GLint unit_rows = -1, unit_x = -1;
    glGetUniformiv(prog.id, glGetUniformLocation(prog.id, "rows"), &unit_rows);
    glGetUniformiv(prog.id, glGetUniformLocation(prog.id, "x"), &unit_x);
    CHECK(unit_rows == 0 && unit_x == 1);
    pass.in = missing;
    pass.n_in = 3;
    CHECK(!wg_pass_bind_inputs(prog.id, &pass, err, sizeof err));
    printf("  missing: %s\n", err);
    CHECK(strstr(err, "'probe'") != NULL && strstr(err, "'y'") != NULL);
    pass.in = extra;
    pass.n_in = 1;
    CHECK(!wg_pass_bind_inputs(prog.id, &pass, err, sizeof err));
    printf("  extra: %s\n", err);
    CHECK(strstr(err, "'probe'") != NULL && strstr(err, "'rows'") != NULL);
    wg_program_destroy(&prog);
    CHECK(glGetError() == GL_NO_ERROR);
}

/* A call site that breaks a pass's contract (an input left NULL, another pass's input struct)
 * binds nothing there; the runner keeps the fault, and the next frame reports it as a GPU error
 * naming the pass and the input. */
static void test_pass_fault(void) {
    wc_model m;
    wc_state* s = hanging(&m, 6, WC_SOLVER_PCG, 0);
    if (!s) return;
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!g) {
        wc_state_destroy(s);
        wc_model_free(&m);
        return;
    }
    CHECK(g->run.fault[0] == '\0');
    WG_USE(&g->run, WGP_TRANSFORM, &(wg_transform_in){.x = wg_ring_cur(&g->x), .v = wg_ring_cur(&g->v)});
    printf("  %s\n", g->run.fault);
    CHECK(strstr(g->run.fault, "'transform'") != NULL && strstr(g->run.fault, "'dv'") != NULL);
    CHECK(wg_sim_step_frame(g, s, 1.0 / 30.0, NULL, &d) == WC_ERROR_GPU);
    CHECK(strstr(d.message, "'dv'") != NULL);
    g->run.fault[0] = '\0';
    WG_USE(&g->run, WGP_TRANSFORM, &(wg_src_in){.src = wg_ring_cur(&g->x)});
    printf("  %s\n", g->run.fault);
    CHECK(strstr(g->run.fault, "'transform'") != NULL && strstr(g->run.fault, "input struct") != NULL);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    RUN_TEST(test_assembly_and_spmv);
    RUN_TEST(test_reductions_and_large_sheet);
    RUN_TEST(test_solvers_vs_direct);
    RUN_TEST(test_pcg_dots_and_iterates);
    RUN_TEST(test_divergence);
    RUN_TEST(test_whole_run);
    RUN_TEST(test_texture_limit);
    RUN_TEST(test_upload_range);
    RUN_TEST(test_direct_refused);
    RUN_TEST(test_compute_source);
    RUN_TEST(test_pass_inputs);
    RUN_TEST(test_pass_fault);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
