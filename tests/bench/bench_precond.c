/* PCG's preconditioners on real systems (a benchmark: prints a table, asserts nothing).
 *
 * For each sheet size and stiffness: an n x n sheet (1 m) hanging from its two top corners,
 * flat at first (the hardest systems: every spring slack or stretched at once) is stepped for
 * --frames frames with the direct solver at one step per frame (1/30 s); then the system of the
 * next substep (wc_substep_prepare) is solved from a zero guess by PCG with each preconditioner
 * to relative residual --tol, and by CHOLMOD. Columns: iterations, setup and solve ms, the true
 * relative residual, the error ||dv - dv_direct|| / ||dv_direct||, and the hierarchy's
 * operator/grid complexity and levels (the IC(0) row: the breakdown shift its setup needed).
 *
 *   bench_precond [--sizes 32,64,128,256] [--k 1,10,100,1000,10000] [--frames 10] [--tol 1e-4]
 *                 [--threads N] [--drop]          (--drop: a sheet lying flat on a sphere)
 *                 [--rotations 0,1]  (the multigrid's near-null space: translations only (0) or
 *                                     the rigid-body modes (1); one "amg" row per value)
 *                 [--current]        (the rotations about the current positions instead of the
 *                                     rest positions: the hierarchy is built from a copy of the
 *                                     model whose rest positions are the state's)
 *                 [--natural]        (the sheet's particles in its grid's row-major order instead
 *                                     of the model's reverse Cuthill-McKee: IC(0)'s ordering) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "clock.h"
#include "precond_ic.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"

static int parse_list(const char* s, double* out, int cap) {
    int n = 0;
    while (*s && n < cap) {
        char* end;
        out[n++] = strtod(s, &end);
        if (end == s) break;
        s = *end == ',' ? end + 1 : end;
    }
    return n;
}

static double rel(const double* a, const double* b, int n3) {
    double num = 0, den = 0;
    for (int k = 0; k < n3; ++k) {
        num += (a[k] - b[k]) * (a[k] - b[k]);
        den += b[k] * b[k];
    }
    return den > 0 ? sqrt(num / den) : sqrt(num);
}

static int g_current = 0;
static int g_natural = 0;

/* ts_sheet (1 m, flat at y = 1, material x k_scale), its particles in the grid's own row-major
 * order when g_natural (wc_model_def.reorder 0) instead of the model's reverse Cuthill-McKee. */
static int sheet(wc_model* m, int n, double k_scale) {
    if (!g_natural) return ts_sheet(m, n, 1.0, 1.0, 0, k_scale);
    wc_source_mesh src;
    ts_quad_grid(&src, n, n, 1.0, 1.0, 0);
    for (int v = 0; v < src.n_verts; ++v) {
        double* p = src.pos + 3 * v;
        double gx = p[0], gy = p[1];
        p[0] = gx - 0.5;
        p[1] = 1.0;
        p[2] = gy - 0.5;
    }
    wc_model_def def = wc_default_model_def();
    def.reorder = 0;
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) {
        def.material.k[t] *= k_scale;
        def.material.d[t] *= k_scale;
    }
    wc_diag d = {0};
    wc_status st = wc_model_build(m, &src, &def, NULL, &d);
    wc_source_mesh_free(&src);
    return st == WC_OK;
}

static void run_case(int n, double k_scale, int frames, double tol, int threads, int drop, const double* rots,
                     int n_rots) {
    wc_model m;
    if (!sheet(&m, n, k_scale)) return;
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_DIRECT;
    def.threads = threads;
    def.sleep_speed = 0;
    def.fail_energy_gain = 0;
    wc_state* s;
    wc_diag d = {0};
    if (wc_state_create(&s, &m, &def, NULL, &d) != WC_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        wc_model_free(&m);
        return;
    }
    if (drop) {
        wc_collider c = {0};
        c.type = WC_COLLIDER_SPHERE;
        c.radius = 0.3;
        c.center[1] = 0.65;
        c.thickness = 0.005;
        c.friction = 0.3;
        wc_state_set_colliders(s, &c, 1, &d);
    } else {
        wc_pin pins[2] = {{0}};
        pins[0].particle = ts_sheet_particle(&m, n, 0, 0);
        pins[1].particle = ts_sheet_particle(&m, n, n - 1, 0);
        for (int k = 0; k < 2; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
        wc_state_set_pins(s, pins, 2, &d);
    }
    for (int f = 0; f < frames; ++f) wc_step_frame(s, 1.0 / 30.0, NULL, &d);
    wc_step_stats st = {0};
    wc_substep_prepare(s, 1.0 / 30.0, 1.0, &st);
    int n3 = 3 * m.n_particles;
    double* ref = calloc((size_t)n3, sizeof(double));
    double* dv = calloc((size_t)n3, sizeof(double));
    wc_solve_result res;
    double t0 = wc_now_ms();
    wc_solve(s->solver, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, ref, &s->par, &res);
    double direct_ms = wc_now_ms() - t0;
    printf("| %4d | %6.0e | direct       |      |        | %8.1f |          |         |         |\n", n, k_scale,
           direct_ms);
    for (int row = 0; row < WC_PRECOND_COUNT + n_rots - 1; ++row) {
        int p = row < WC_PRECOND_AMG ? row : row < WC_PRECOND_AMG + n_rots ? WC_PRECOND_AMG : row - n_rots + 1;
        wc_solver_opts o = wc_default_solver_opts();
        o.preconditioner = (wc_precond_type)p;
        o.tolerance = tol;
        o.max_iterations = 1000;
        wc_solver* sv;
        double c0 = wc_now_ms();
        if (wc_solver_create(&sv, &m, &o, 0, NULL, &d) != WC_OK) {
            fprintf(stderr, "solver: %s\n", d.message);
            continue;
        }
        double create_ms = wc_now_ms() - c0;
        const char* name = wc_precond_name((wc_precond_type)p);
        if (sv->amg) { /* the near-null space asked for: rebuild the hierarchy with it */
            wc_amg_opts ao = wc_default_amg_opts();
            ao.rotations = (int)rots[row - WC_PRECOND_AMG];
            name = ao.rotations ? "amg rot" : "amg transl";
            wc_amg_destroy(sv->amg);
            sv->amg = NULL;
            c0 = wc_now_ms();
            wc_model mc = m;
            if (g_current) mc.rest_pos = s->x;
            if (wc_amg_create(&sv->amg, &mc, &ao, &sv->alloc, &d) != WC_OK) {
                fprintf(stderr, "amg: %s\n", d.message);
                wc_solver_destroy(sv);
                continue;
            }
            create_ms = wc_now_ms() - c0;
        }
        memset(dv, 0, sizeof(double) * (size_t)n3);
        t0 = wc_now_ms();
        wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res);
        double ms = wc_now_ms() - t0;
        char extra[96] = "";
        if (sv->amg)
            snprintf(extra, sizeof extra, "%d lev, op %.2f, grid %.2f, build %.0f ms", sv->amg->n_levels,
                     wc_amg_operator_complexity(sv->amg), wc_amg_grid_complexity(sv->amg), create_ms);
        if (sv->ic) snprintf(extra, sizeof extra, "shift %g%s", sv->ic->shift, sv->ic->jacobi ? " (block diagonal)" : "");
        if (sv->amg && getenv("XAMG_DEBUG"))
            for (int l = 0; l < sv->amg->n_levels; ++l)
                fprintf(stderr, "level %d: n %d blocks %d bound %g\n", l, sv->amg->lev[l].n, sv->amg->lev[l].n_blocks,
                        sv->amg->lev[l].bound);
        printf("| %4d | %6.0e | %-12s | %4d | %6.1f | %8.1f | %8.1e | %7.1e | %s |\n", n, k_scale,
               name, res.iterations, res.setup_ms, ms - res.setup_ms, res.residual,
               rel(dv, ref, n3), extra);
        fflush(stdout);
        wc_solver_destroy(sv);
    }
    free(ref);
    free(dv);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(int argc, char** argv) {
    double sizes[16], ks[16];
    int n_sizes = parse_list("32,64,128,256", sizes, 16), n_k = parse_list("1", ks, 16);
    int frames = 10, threads = 1, drop = 0;
    double rots[2] = {0, 1};
    int n_rots = 2;
    double tol = 1e-4;
    for (int a = 1; a < argc; ++a) {
        if (!strcmp(argv[a], "--sizes") && a + 1 < argc) n_sizes = parse_list(argv[++a], sizes, 16);
        else if (!strcmp(argv[a], "--k") && a + 1 < argc) n_k = parse_list(argv[++a], ks, 16);
        else if (!strcmp(argv[a], "--frames") && a + 1 < argc) frames = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--tol") && a + 1 < argc) tol = atof(argv[++a]);
        else if (!strcmp(argv[a], "--threads") && a + 1 < argc) threads = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--drop")) drop = 1;
        else if (!strcmp(argv[a], "--current")) g_current = 1;
        else if (!strcmp(argv[a], "--natural")) g_natural = 1;
        else if (!strcmp(argv[a], "--rotations") && a + 1 < argc) n_rots = parse_list(argv[++a], rots, 2);
        else {
            fprintf(stderr, "usage: bench_precond [--sizes LIST] [--k LIST] [--frames N] [--tol T] [--threads N] [--drop] [--rotations 0,1] [--current] [--natural]\n");
            return 2;
        }
    }
    printf("%s, %d frames at 1/30 s, then one solve to %.0e; %d thread(s)%s\n\n",
           drop ? "sheet dropped on a sphere" : "sheet hanging from two corners", frames, tol, threads,
           g_natural ? "; particles in grid order" : "");
    printf("| n | k x | preconditioner | it | setup ms | solve ms | residual | err vs direct | hierarchy (ic0: shift) |\n");
    printf("|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < n_sizes; ++i)
        for (int j = 0; j < n_k; ++j) run_case((int)sizes[i], ks[j], frames, tol, threads, drop, rots, n_rots);
    return 0;
}
