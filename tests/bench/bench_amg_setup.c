/* Where the multigrid's setup time goes (a benchmark: prints a table, asserts nothing).
 *
 * An n x n sheet (1 m, default material), flat at first and hanging from its two far corners
 * (`weft bench peers`' sheetN), stepped --frames frames at 1/30 s, one substep per frame, with
 * PCG + the multigrid, backward Euler, Newton 2 iterations with line search (the library's
 * defaults, weft_default_cloth_def), on --threads threads. Printed: ms per frame (median), solves
 * and PCG iterations per solve, and the setup's phases (wc_amg.phase_ms, amg.h) in ms per solve.
 *
 * Then, on the last system's levels, the eigenvalue estimate (amg_eigen.c) beside a converged one
 * (60 Lanczos steps, 400 power iterations).
 *
 * The memory limit: the bytes the last system's PCG iterations must move (the model below) over
 * their CPU time (the fastest of 10 solves from zero), beside a copy (memcpy) of the same working
 * set on the same core (source and destination together that size; the fastest of 20); and the share of the frames' wall time spent outside
 * the linear solves (run it on a quiet machine for that one).
 *
 * --repeat R: the last system's setup R more times, each phase's minimum over them (a shared
 * machine's load inflates the sums; the minimum is what the code costs).
 *
 *   bench_amg_setup [--n 100] [--frames 10] [--threads 1] [--repeat 0]
 *                   [--power N] [--coarse N] [--lanczos 0|1]   (wc_amg_opts' estimate)
 *                   [--single 0|1]   (wc_amg_opts.single: the V-cycle's float copies; default 1)
 *                   [--single-x 0|1] (wc_amg_opts.single_x: its float iterates; default 1)
 *                   [--ab R]   (then the last system's V-cycles and PCG solves alternating single_x 1
 *                               and 0 in this run, R rounds: median and fastest CPU ms of each)
 *                   [--ab-smoother R]   (the same alternating the smoother's AVX2 node updates and
 *                               its scalar loops, wc_amg_opts.smooth_vector) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "bsr_rows.h"
#include "clock.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* Bytes a 3x3-block BSR product must move at least once: values (`value` bytes each: 8, or 4 for
 * the V-cycle's float copies), column indices, row starts. */
static double bsr_bytes(int n_rows, int n_blocks, double value) {
    return (9.0 * value + 4.0) * n_blocks + 4.0 * (n_rows + 1);
}

/* Bytes one V-cycle (amg_cycle.c, Chebyshev smoothing with `sweeps` steps) must move, each kernel
 * reading its matrix and its vectors once and writing its output once (no reuse between kernels):
 * per level 2 sweeps operator products, 2 sweeps block-diagonal applications, the restriction
 * and the prolongation (P's values and indices), about 8 sweeps + 6 passes over 3n-vectors; the
 * coarsest level's dense factor twice. *working_set: the distinct bytes (matrices, P, D^-1, 4
 * vectors a level). */
static double vcycle_bytes(const wc_amg* a, double* working_set) {
    const int s = a->opts.sweeps;
    const double value = a->opts.single ? 4.0 : 8.0;
    double bytes = 0.0, ws = 0.0;
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_level* L = &a->lev[l];
        const double vec = 24.0 * L->n, op = bsr_bytes(L->n, L->n_blocks, value),
                     dinv = 72.0 * L->group * L->n;
        if (l == a->n_levels - 1) {
            if (a->coarse_dense) {
                const double dense = 8.0 * (double)a->coarse_dofs * a->coarse_dofs;
                bytes += 2.0 * dense + 4.0 * vec;
                ws += dense + 3.0 * vec;
            } else {
                bytes += WC_AMG_COARSE_SWEEPS * (op + dinv + 4.0 * vec);
                ws += op + dinv + 3.0 * vec;
            }
            continue;
        }
        const double pb = bsr_bytes(L->n, L->p_start[L->n], value) + 4.0 * L->p_start[L->n]; /* P and P^T's index */
        bytes += 2.0 * s * (op + dinv) + 2.0 * pb + (8.0 * s + 6.0) * vec;
        ws += op + dinv + pb + 4.0 * vec;
    }
    *working_set = ws;
    return bytes;
}

/* Copy bandwidth (bytes read + written per ms) of a memcpy of `size` bytes, the fastest of 20. */
static double copy_rate(size_t size) {
    char *src = malloc(size), *dst = malloc(size);
    if (!src || !dst) {
        free(src);
        free(dst);
        return 0.0;
    }
    memset(src, 1, size);
    memset(dst, 0, size);
    double best = 1e300;
    for (int r = 0; r < 20; ++r) {
        double t0 = wc_cpu_ms();
        memcpy(dst, src, size);
        double t = wc_cpu_ms() - t0;
        if (t < best && t > 0) best = t;
        src[r % size] = dst[(r * 7) % size]; /* keeps the copies */
    }
    free(src);
    free(dst);
    return best < 1e300 ? 2.0 * (double)size / best : 0.0;
}

/* The last system's V-cycles (20 a sample) and PCG solves from zero, alternating single_x 1 and 0
 * within each of R rounds: the median and fastest CPU ms of each, the iterations. */
/* --ab-smoother R: the last system's V-cycles and PCG solves alternating the smoother's AVX2 node
 * updates and its scalar loops (wc_amg_opts.smooth_vector; amg_smooth.c) in this run. */
static void ab_smoother(wc_state* s, wc_amg* amg, int rounds) {
    const int n3 = 3 * amg->lev[0].n, keep = amg->opts.smooth_vector;
    double *r = malloc(sizeof(double) * (size_t)n3), *z = malloc(sizeof(double) * (size_t)n3);
    double* t[2][2];
    int it[2] = {0, 0};
    for (int v = 0; v < 2; ++v)
        for (int q = 0; q < 2; ++q) t[v][q] = malloc(sizeof(double) * (size_t)rounds);
    for (int k = 0; k < n3; ++k) r[k] = s->b[k];
    for (int round = 0; round < rounds; ++round)
        for (int v = 0; v < 2; ++v) { /* v = 0: the kernel */
            amg->opts.smooth_vector = 1 - v;
            double c0 = wc_cpu_ms();
            for (int k = 0; k < 20; ++k) wc_amg_apply(amg, r, z, &s->par);
            t[v][0][round] = (wc_cpu_ms() - c0) / 20.0;
            memset(z, 0, sizeof(double) * (size_t)n3);
            double setup0 = 0.0, setup1 = 0.0;
            for (int p = 0; p < WC_AMG_PHASES; ++p) setup0 += amg->phase_ms[p];
            wc_solve_result res;
            c0 = wc_cpu_ms();
            wc_solve(s->solver, WC_SOLVER_PCG, s->A, s->b, &s->filter, z, &s->par, &res);
            double c = wc_cpu_ms() - c0;
            for (int p = 0; p < WC_AMG_PHASES; ++p) setup1 += amg->phase_ms[p];
            t[v][1][round] = c - (setup1 - setup0);
            it[v] = res.iterations;
        }
    amg->opts.smooth_vector = keep;
    printf("the last system, the smoother's node updates in AVX2 and scalar alternating, %d rounds%s (CPU ms, "
           "median (fastest)):\n| node updates | V-cycle | PCG solve less setup | PCG it. |\n|---|---|---|---|\n",
           rounds, wc_amg_cheb_nodes_kernel() ? "" : " (no AVX2: both scalar)");
    for (int v = 0; v < 2; ++v) {
        for (int q = 0; q < 2; ++q) qsort(t[v][q], (size_t)rounds, sizeof(double), cmp_double);
        printf("| %s | %.3f (%.3f) | %.3f (%.3f) | %d |\n", v ? "scalar" : "AVX2", t[v][0][rounds / 2], t[v][0][0],
               t[v][1][rounds / 2], t[v][1][0], it[v]);
    }
    printf("\n");
    for (int v = 0; v < 2; ++v)
        for (int q = 0; q < 2; ++q) free(t[v][q]);
    free(r);
    free(z);
}

static void ab_single_x(wc_state* s, wc_amg* amg, int rounds) {
    const int n3 = 3 * amg->lev[0].n, keep = amg->opts.single_x;
    double *r = malloc(sizeof(double) * (size_t)n3), *z = malloc(sizeof(double) * (size_t)n3);
    double* t[2][3];
    const wc_amg_level* F = &amg->lev[0];
    const wc_bsr_rows_fx_fn fx = wc_bsr_rows_fx_vector();
    float* xf = calloc(4 * (size_t)F->n, sizeof(float));
    int it[2] = {0, 0};
    for (int v = 0; v < 2; ++v)
        for (int q = 0; q < 3; ++q) t[v][q] = malloc(sizeof(double) * (size_t)rounds);
    for (int k = 0; k < n3; ++k) r[k] = s->b[k];
    for (int i = 0; i < F->n; ++i)
        for (int c = 0; c < 3; ++c) xf[4 * i + c] = (float)r[3 * i + c];
    for (int round = 0; round < rounds; ++round)
        for (int v = 0; v < 2; ++v) { /* v = 0: single_x 1 */
            amg->opts.single_x = 1 - v;
            double c0 = wc_cpu_ms();
            for (int k = 0; k < 20; ++k) wc_amg_apply(amg, r, z, &s->par);
            t[v][0][round] = (wc_cpu_ms() - c0) / 20.0;
            memset(z, 0, sizeof(double) * (size_t)n3);
            double setup0 = 0.0, setup1 = 0.0;
            for (int p = 0; p < WC_AMG_PHASES; ++p) setup0 += amg->phase_ms[p];
            wc_solve_result res;
            c0 = wc_cpu_ms();
            wc_solve(s->solver, WC_SOLVER_PCG, s->A, s->b, &s->filter, z, &s->par, &res);
            double c = wc_cpu_ms() - c0;
            for (int p = 0; p < WC_AMG_PHASES; ++p) setup1 += amg->phase_ms[p];
            t[v][1][round] = c - (setup1 - setup0);
            it[v] = res.iterations;
            c0 = wc_cpu_ms(); /* the finest level's float operator times x, 50 times: the row kernel alone */
            for (int k = 0; k < 50 && F->val_f; ++k) {
                if (v == 0 && fx) fx(F->row_start, F->col, F->val_f, 0, F->n, r, -1.0, xf, z, NULL);
                else wc_bsr_rows_f(F->row_start, F->col, F->val_f, 0, F->n, r, -1.0, r, z);
            }
            t[v][2][round] = (wc_cpu_ms() - c0) / 50.0;
        }
    amg->opts.single_x = keep;
    printf("the last system, single_x 1 and 0 alternating, %d rounds (CPU ms, median (fastest)):\n"
           "| single_x | V-cycle | PCG solve less setup | PCG it. | finest level's product |\n|---|---|---|---|---|\n",
           rounds);
    for (int v = 0; v < 2; ++v) {
        for (int q = 0; q < 3; ++q) qsort(t[v][q], (size_t)rounds, sizeof(double), cmp_double);
        printf("| %d | %.3f (%.3f) | %.3f (%.3f) | %d | %.4f (%.4f) |\n", 1 - v, t[v][0][rounds / 2], t[v][0][0],
               t[v][1][rounds / 2], t[v][1][0], it[v], t[v][2][rounds / 2], t[v][2][0]);
    }
    printf("\n");
    for (int v = 0; v < 2; ++v)
        for (int q = 0; q < 3; ++q) free(t[v][q]);
    free(xf);
    free(r);
    free(z);
}

int main(int argc, char** argv) {
    int n = 100, frames = 10, threads = 1, power = 0, coarse = 0, lanczos = -1, repeat = 0, single = -1,
        single_x = -1, ab = 0, ab_smooth = 0;
    for (int a = 1; a < argc; ++a) {
        if (!strcmp(argv[a], "--n") && a + 1 < argc) n = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--frames") && a + 1 < argc) frames = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--threads") && a + 1 < argc) threads = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--power") && a + 1 < argc) power = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--coarse") && a + 1 < argc) coarse = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--repeat") && a + 1 < argc) repeat = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--lanczos") && a + 1 < argc) lanczos = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--single") && a + 1 < argc) single = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--single-x") && a + 1 < argc) single_x = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--ab") && a + 1 < argc) ab = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--ab-smoother") && a + 1 < argc) ab_smooth = atoi(argv[++a]);
        else {
            fprintf(stderr, "usage: bench_amg_setup [--n N] [--frames N] [--threads N] [--power N] [--coarse N] "
                            "[--lanczos 0|1] [--repeat R] [--single 0|1] [--single-x 0|1] [--ab R] [--ab-smoother R]\n");
            return 2;
        }
    }
    if (n < 2 || frames < 1 || threads < 1) return 2;
    wc_model m;
    if (!ts_sheet(&m, n, 1.0, 1.0, 0, 1.0)) return 1;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_AMG;
    def.integrator = WC_INTEGRATOR_BE;
    def.newton_iterations = 2;
    def.line_search = 1;
    def.threads = threads;
    def.sleep_speed = 0;
    wc_state* s;
    wc_diag d = {0};
    if (wc_state_create(&s, &m, &def, NULL, &d) != WC_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        return 1;
    }
    wc_pin pins[2] = {{0}};
    pins[0].particle = ts_sheet_particle(&m, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(&m, n, n - 1, n - 1);
    for (int k = 0; k < 2; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
    wc_state_set_pins(s, pins, 2, &d);
    wc_amg* amg = s->solver->amg;
    if (!amg) {
        fprintf(stderr, "no multigrid\n");
        return 1;
    }
    if (power > 0) amg->opts.power_iterations = power;
    if (coarse > 0) amg->opts.coarse_iterations = coarse;
    if (lanczos >= 0) amg->opts.lanczos = lanczos;
    if (single >= 0) amg->opts.single = single;
    if (single_x >= 0) amg->opts.single_x = single_x;
    double* ms = malloc(sizeof(double) * (size_t)frames);
    double* cpu = malloc(sizeof(double) * (size_t)frames);
    long solves = 0, iterations = 0;
    double precond = 0.0, solve = 0.0, wall_total = 0.0;
    for (int f = 0; f < frames; ++f) {
        wc_step_stats st = {0};
        double t0 = wc_now_ms(), c0 = wc_cpu_ms();
        if (wc_step_frame(s, 1.0 / 30.0, &st, &d) != WC_OK) fprintf(stderr, "frame %d: %s\n", f, d.message);
        ms[f] = wc_now_ms() - t0;
        cpu[f] = wc_cpu_ms() - c0;
        solves += st.solves;
        iterations += st.iterations;
        precond += st.precond_ms;
        solve += st.ms.solve;
        wall_total += ms[f];
    }
    qsort(ms, (size_t)frames, sizeof *ms, cmp_double);
    qsort(cpu, (size_t)frames, sizeof *cpu, cmp_double);
    double per = solves > 0 ? 1.0 / (double)solves : 0.0, setup_sum = 0.0;
    printf("sheet%d (%d particles), %d frames, %d thread(s), %d levels (op. complexity %.2f)\n", n, m.n_particles,
           frames, threads, amg->n_levels, wc_amg_operator_complexity(amg));
    printf("median %.1f ms/frame wall, %.1f CPU; %ld solves (%.2f per frame), %.2f PCG it./solve; solve %.2f ms/solve, of which "
           "setup %.2f, PCG %.2f\n\n",
           ms[frames / 2], cpu[frames / 2], solves, (double)solves / frames, iterations * per, solve * per, precond * per,
           (solve - precond) * per);
    { /* the last system's PCG iterations against the memory limit (vcycle_bytes): the system solved
         again from zero 10 times, CPU ms of its iterations (the solve less its setup), the fastest */
        const wc_amg_level* F = &amg->lev[0];
        const int n3 = 3 * F->n;
        double* dv = malloc(sizeof(double) * (size_t)n3);
        double pcg_ms = 1e300;
        int it = 0;
        for (int r = 0; r < 10 && dv; ++r) {
            memset(dv, 0, sizeof(double) * (size_t)n3);
            double setup0 = 0.0, setup1 = 0.0;
            for (int p = 0; p < WC_AMG_PHASES; ++p) setup0 += amg->phase_ms[p];
            wc_solve_result res;
            double c0 = wc_cpu_ms();
            wc_solve(s->solver, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res);
            double c = wc_cpu_ms() - c0;
            for (int p = 0; p < WC_AMG_PHASES; ++p) setup1 += amg->phase_ms[p];
            if (c - (setup1 - setup0) < pcg_ms) pcg_ms = c - (setup1 - setup0);
            it = res.iterations;
        }
        free(dv);
        const double vec = 24.0 * F->n;
        double ws = 0.0, vb = vcycle_bytes(amg, &ws);
        const double fine = bsr_bytes(F->n, F->n_blocks, 8.0) + 3.0 * vec; /* A's product: A, x, y */
        /* a solve: it + 2 fine products (the filtered residuals), it + 1 V-cycles, and per
           iteration about 15 passes over 3n-vectors (the filtered dot, the updates, the direction) */
        const double bytes = (it + 2.0) * fine + (it + 1.0) * vb + it * 15.0 * vec;
        ws += bsr_bytes(F->n, F->n_blocks, 8.0) + 6.0 * vec;
        const double rate = pcg_ms > 0 && pcg_ms < 1e300 ? bytes / pcg_ms : 0.0, copy = copy_rate((size_t)(ws / 2));
        printf("memory: the last system's PCG iterations (%d) move >= %.2f MB (working set %.2f MB) in %.2f CPU ms: "
               "%.1f GB/s; a copy of %.2f MB (source and destination: the same working set) on this core: %.1f GB/s "
               "(PCG at %.0f %% of it)\n",
               it, bytes / 1e6, ws / 1e6, pcg_ms, rate / 1e6, ws / 2e6, copy / 1e6, copy > 0 ? 100.0 * rate / copy : 0.0);
        printf("outside the linear solves: %.0f %% of the frames' wall time (forces, assembly, the line search's "
               "potentials, the step's checks)\n\n",
               wall_total > 0 ? 100.0 * (1.0 - solve / wall_total) : 0.0);
    }
    if (ab > 0) ab_single_x(s, amg, ab);
    if (ab_smooth > 0) ab_smoother(s, amg, ab_smooth);
    printf("| setup phase | CPU ms/solve | share |\n|---|---|---|\n");
    for (int p = 0; p < WC_AMG_PHASES; ++p) setup_sum += amg->phase_ms[p];
    for (int p = 0; p < WC_AMG_PHASES; ++p)
        printf("| %s | %.2f | %.0f %% |\n", wc_amg_phase_name((wc_amg_phase)p), amg->phase_ms[p] / amg->setups,
               setup_sum > 0 ? 100.0 * amg->phase_ms[p] / setup_sum : 0.0);
    printf("| total | %.2f | |\n", setup_sum / amg->setups);
    if (repeat > 0) { /* the last system again: each phase's minimum */
        double best[WC_AMG_PHASES], total = 0.0;
        for (int p = 0; p < WC_AMG_PHASES; ++p) best[p] = 1e300;
        for (int r = 0; r < repeat; ++r) {
            memset(amg->phase_ms, 0, sizeof amg->phase_ms);
            wc_amg_setup(amg, s->A, &s->filter, &s->par);
            for (int p = 0; p < WC_AMG_PHASES; ++p)
                if (amg->phase_ms[p] < best[p]) best[p] = amg->phase_ms[p];
        }
        printf("\nthe last system's setup %d more times, minimum per phase (CPU ms):\n| phase | min ms |\n|---|---|\n",
               repeat);
        for (int p = 0; p < WC_AMG_PHASES; ++p) {
            printf("| %s | %.2f |\n", wc_amg_phase_name((wc_amg_phase)p), best[p]);
            total += best[p];
        }
        printf("| total | %.2f |\n", total);
    }
    printf("\n%s, %d steps on the finest level, %d on the others (last system)\n",
           amg->opts.lanczos ? "Lanczos" : "power iterations", amg->opts.power_iterations, amg->opts.coarse_iterations);
    printf("| level | nodes | blocks | bound | bound / 1.1 | Lanczos 60 | power 400 | A P products | P^T T products |\n"
           "|---|---|---|---|---|---|---|---|---|\n");
    for (int l = 0; l < amg->n_levels; ++l) {
        wc_amg_level* L = &amg->lev[l];
        if (l == amg->n_levels - 1 && amg->coarse_dense) {
            printf("| %d | %d | %d | (dense) | | | |\n", l, L->n, L->n_blocks);
            continue;
        }
        double b = L->bound;
        double lz = wc_amg_eigen_estimate(L, 60, 1, amg->opts.pair_blocks, &s->par);
        double pw = wc_amg_eigen_estimate(L, 400, 0, amg->opts.pair_blocks, &s->par);
        double ap = 0, ptap = 0; /* 3x3 block products of T = A P and of P^T T (all of it) */
        if (l + 1 < amg->n_levels) {
            for (int k = 0; k < L->n_blocks; ++k) ap += L->p_start[L->col[k] + 1] - L->p_start[L->col[k]];
            for (int i = 0; i < L->n; ++i)
                ptap += (double)(L->p_start[i + 1] - L->p_start[i]) * (L->t_start[i + 1] - L->t_start[i]);
        }
        printf("| %d | %d | %d | %.4f | %.4f | %.4f | %.4f | %.0f k | %.0f k |\n", l, L->n, L->n_blocks, b, b / WC_AMG_SAFETY,
               lz, pw, ap / 1e3, ptap / 1e3);
    }
    free(ms);
    free(cpu);
    wc_state_destroy(s);
    wc_model_free(&m);
    return 0;
}
