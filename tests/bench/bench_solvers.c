/* Benchmark (not a test): the speed case. An N x N sheet (default 100 x 100 = 10,000
 * particles, 1 m), horizontal, pinned at the two corners of one edge, default material and air,
 * 30 fps, one backward-Euler step per frame, for each solver. Prints a Markdown table of median
 * ms per frame by stage, iterations, and the trajectory error against the direct solver's
 * (converged) run: the largest distance of any particle at any frame, and the RMS distance at
 * the last frame, as a percentage of the sheet's size.
 *
 *   bench_solvers [--n N] [--frames F] [--threads T] [--tolerance TOL] [--max-iterations M]
 *                 [--substeps S] [--solvers pcg,jacobi,chebyshev,direct]
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "step.h"
#include "vec3.h"

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

static double median(double* v, int n) {
    qsort(v, (size_t)n, sizeof(double), cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static int build_sheet(wc_model* m, int n) {
    int nq = (n - 1) * (n - 1);
    double* pos = malloc(sizeof(double) * 3 * (size_t)n * n);
    int* sizes = malloc(sizeof(int) * (size_t)nq);
    int* idx = malloc(sizeof(int) * 4 * (size_t)nq);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) v3_set(pos + 3 * (i + n * j), (double)i / (n - 1) - 0.5, 1.0, (double)j / (n - 1) - 0.5);
    int q = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++q) {
            sizes[q] = 4;
            int c[4] = {i + n * j, i + 1 + n * j, i + 1 + n * (j + 1), i + n * (j + 1)};
            memcpy(idx + 4 * q, c, sizeof c);
        }
    wc_source_mesh src;
    wc_diag d = {0};
    weft_status st = wc_source_mesh_from_arrays(&src, NULL, pos, n * n, sizes, nq, idx, 1.0, &d);
    free(pos);
    free(sizes);
    free(idx);
    if (st != WEFT_OK) return 0;
    wc_model_def def = wc_default_model_def();
    st = wc_model_build(m, &src, &def, NULL, &d);
    wc_source_mesh_free(&src);
    if (st != WEFT_OK) fprintf(stderr, "model: %s\n", d.message);
    return st == WEFT_OK;
}

typedef struct run_result {
    double ms[6][4096]; /* forces, assemble, solve, collide, integrate, total per frame */
    int iterations, max_iterations, rollbacks, not_converged;
    double max_strain;
    double* traj;       /* (frames x n x 3) */
} run_result;

static int run(const wc_model* m, int n, wc_sim_def sd, int frames, run_result* out) {
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &sd, NULL, &d) != WEFT_OK) {
        fprintf(stderr, "state: %s\n", d.message);
        return 0;
    }
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    pins[0].particle = m->host_to_particle[0];
    pins[1].particle = m->host_to_particle[n - 1];
    for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, m->rest_pos + 3 * pins[k].particle);
    wc_state_set_pins(s, pins, 2, &d);
    int np = m->n_particles;
    for (int f = 0; f < frames; ++f) {
        wc_step_stats st;
        weft_status r = wc_step_frame(s, 1.0 / 30, &st, &d);
        if (r != WEFT_OK) fprintf(stderr, "frame %d: %s\n", f, d.message);
        double v[6] = {st.ms.forces, st.ms.assemble, st.ms.solve, st.ms.collide, st.ms.integrate, st.ms.total};
        for (int k = 0; k < 6; ++k) out->ms[k][f] = v[k];
        out->iterations += st.iterations;
        if (st.max_iterations > out->max_iterations) out->max_iterations = st.max_iterations;
        out->rollbacks += st.rollbacks;
        out->not_converged += st.not_converged;
        if (st.max_strain > out->max_strain) out->max_strain = st.max_strain;
        memcpy(out->traj + (size_t)f * 3 * np, s->x, sizeof(double) * 3 * (size_t)np);
    }
    wc_state_destroy(s);
    return 1;
}

int main(int argc, char** argv) {
    int n = 100, frames = 60, threads = 0, max_it = 0, substeps = 1;
    double tol = -1;
    char solvers[128] = "direct,pcg,chebyshev,jacobi";
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--frames") && i + 1 < argc) frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--threads") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--tolerance") && i + 1 < argc) tol = atof(argv[++i]);
        else if (!strcmp(argv[i], "--max-iterations") && i + 1 < argc) max_it = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--substeps") && i + 1 < argc) substeps = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--solvers") && i + 1 < argc) snprintf(solvers, sizeof solvers, "%s", argv[++i]);
        else {
            fprintf(stderr, "usage: %s [--n N] [--frames F] [--threads T] [--tolerance TOL] [--max-iterations M] "
                            "[--substeps S] [--solvers pcg,jacobi,chebyshev,direct]\n", argv[0]);
            return 2;
        }
    }
    if (n < 2 || frames < 1 || frames > 4096 || substeps < 1) return 2;
    wc_model m;
    if (!build_sheet(&m, n)) return 1;
    int np = m.n_particles;
    wc_sim_def base = wc_default_sim_def();
    base.threads = threads;
    base.substeps = substeps;
    if (tol >= 0) base.solver.tolerance = tol;
    if (max_it > 0) base.solver.max_iterations = max_it;
    wc_par par;
    wc_par_init(&par, threads);
    printf("sheet %d x %d (%d particles, %d springs), %d frames at 30 fps, %d substep(s), %d thread(s), "
           "tolerance %g, max iterations %d\n\n", n, n, np, m.n_springs, frames, substeps, par.threads,
           base.solver.tolerance, base.solver.max_iterations);
    printf("| solver | ms/frame (median) | forces | assemble | solve | integrate | iterations/frame (mean, max) "
           "| rollbacks | max error %% of size | RMS error %% at end | max strain |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
    /* the direct solver's run is the reference: always run it first */
    run_result* ref = calloc(1, sizeof *ref);
    ref->traj = malloc(sizeof(double) * 3 * (size_t)np * frames);
    wc_sim_def sd = base;
    sd.solver.type = WC_SOLVER_DIRECT;
    if (!run(&m, n, sd, frames, ref)) return 1;
    char* tok = strtok(solvers, ",");
    while (tok) {
        int type = wc_solver_from_name(tok);
        const char* label = tok;
        tok = strtok(NULL, ",");
        if (type < 0) {
            fprintf(stderr, "unknown solver\n");
            return 2;
        }
        run_result* r = ref;
        if (type != WC_SOLVER_DIRECT) {
            r = calloc(1, sizeof *r);
            r->traj = malloc(sizeof(double) * 3 * (size_t)np * frames);
            sd = base;
            sd.solver.type = (wc_solver_type)type;
            if (!run(&m, n, sd, frames, r)) return 1;
        }
        double max_err = 0, rms = 0;
        for (int f = 0; f < frames; ++f)
            for (int i = 0; i < np; ++i) {
                double dd[3];
                v3_sub(dd, r->traj + ((size_t)f * np + i) * 3, ref->traj + ((size_t)f * np + i) * 3);
                double e = v3_norm(dd);
                if (e > max_err) max_err = e;
                if (f == frames - 1) rms += e * e;
            }
        rms = sqrt(rms / np);
        double med[6];
        for (int k = 0; k < 6; ++k) med[k] = median(r->ms[k], frames);
        printf("| %s | %.2f | %.2f | %.2f | %.2f | %.2f | %.1f, %d | %d | %.3g | %.3g | %.3g |\n", label,
               med[5], med[0], med[1], med[2], med[4], (double)r->iterations / frames, r->max_iterations, r->rollbacks,
               100 * max_err, 100 * rms, r->max_strain);
        fflush(stdout);
        if (r != ref) {
            free(r->traj);
            free(r);
        }
    }
    free(ref->traj);
    free(ref);
    wc_model_free(&m);
    return 0;
}
