/* The GPU backend beside the CPU backend (a benchmark, not a test: it prints tables and asserts
 * nothing about time). For square sheets of n x n particles (horizontal, pinned at two corners,
 * swinging down): median ms per frame (one substep, PCG with a fixed 30 iterations: tolerance 0)
 * on each backend (the step's retries off: exactly one substep is timed), the GPU's per-stage
 * times from GL timer queries, the relative residual each backend's last solve stopped at and
 * the distance between the two backends' positions after the frames (the error that comes with
 * the speed: 30 iterations of block-diagonal PCG are far from converged on fine sheets, and
 * with the step's checks off nothing rolls a bad step back), and the effective
 * bandwidth of the SpMV pass against a plain copy pass of the particle array. With tolerance 0 it
 * also counts the passes a PCG iteration queues (two more frames, at the cap and 10 past it).
 *
 *   [WEFT_GPU_PASSES=fragment|compute] bench_gpu [--sizes 32,100,316,1000] [--frames 5] [--iterations 30] [--tolerance 0] [--threads 0]
 *             [--skip-cpu] [--precond block_jacobi|amg]
 * (--tolerance T > 0: PCG stops at T or the iteration cap, for the error of converged steps;
 * --precond: PCG's preconditioner on both backends, block Jacobi by default; amg is core's
 * default multigrid on the CPU and the GPU's own, gpu/solver/wg_amg.h: smoothed prolongator unless
 * WEFT_GPU_AMG_SMOOTH=0)
 *
 * llvmpipe runs the passes on the CPU's cores: its figures say what the GL path costs there, not
 * what a GPU does. Run it where an NVIDIA device is visible to EGL for GPU figures. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "egl_context.h"
#include "gpu_compute_copy.h"
#include "sort.h"
#include "step.h"
#include "wg_sim.h"

#define MAX_SIZES 8
#define MAX_FRAMES 64

static int build_sheet(wc_model* m, int n) {
    int nv = n * n, nq = (n - 1) * (n - 1);
    double* pos = calloc((size_t)nv * 3, sizeof(double));
    int* sizes = calloc((size_t)nq, sizeof(int));
    int* idx = calloc((size_t)nq * 4, sizeof(int));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double* p = pos + 3 * (i + n * j);
            p[0] = (double)i / (n - 1) - 0.5;
            p[1] = 1.0;
            p[2] = (double)j / (n - 1) - 0.5;
        }
    int q = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++q) {
            sizes[q] = 4;
            int* c = idx + 4 * q;
            c[0] = i + n * j;
            c[1] = i + n * (j + 1);
            c[2] = i + 1 + n * (j + 1);
            c[3] = i + 1 + n * j;
        }
    wc_source_mesh src;
    wc_diag d = {0};
    wc_status st = wc_source_mesh_from_arrays(&src, NULL, pos, nv, sizes, nq, idx, 1.0, &d);
    free(pos), free(sizes), free(idx);
    if (st == WC_OK) {
        wc_model_def def = wc_default_model_def();
        st = wc_model_build(m, &src, &def, NULL, &d);
        wc_source_mesh_free(&src);
    }
    if (st != WC_OK) fprintf(stderr, "bench_gpu: model %d x %d: %s\n", n, n, d.message);
    return st == WC_OK;
}

static wc_state* make_state(const wc_model* m, int n, int iterations, double tolerance, int threads, wc_precond_type pc) {
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = pc;
    def.solver.tolerance = tolerance;
    def.solver.max_iterations = iterations;
    def.sleep_speed = 0.0;
    def.threads = threads;
    /* one substep of exactly `iterations` PCG iterations per frame, timed as such: no retries
       (a capped, unconverged solve can trip the energy check and be halved, which would time
       15 substeps); only a non-finite result would fail */
    def.direct_fallback = 0;
    def.max_halvings = 0;
    def.fail_energy_gain = 0.0;
    def.fail_energy_growth = 1e30;
    def.fail_strain = 1e30;
    def.max_pins = 2;
    wc_state* s = NULL;
    wc_diag d = {0};
    if (wc_state_create(&s, m, &def, NULL, &d) != WC_OK) return NULL;
    wc_pin pins[2] = {{m->host_to_particle[n * (n - 1)], {0, 0, 0}, {0, 0, 0}},
                      {m->host_to_particle[n * n - 1], {0, 0, 0}, {0, 0, 0}}};
    for (int k = 0; k < 2; ++k) memcpy(pins[k].target, s->x + 3 * pins[k].particle, sizeof pins[k].target);
    wc_state_set_pins(s, pins, 2, &d);
    return s;
}

int main(int argc, char** argv) {
    int sizes[MAX_SIZES] = {32, 100, 316, 1000}, n_sizes = 4, frames = 5, iterations = 30, threads = 0, skip_cpu = 0;
    double tolerance = 0.0;
    wc_precond_type pc = WC_PRECOND_BLOCK_JACOBI;
    for (int a = 1; a < argc; ++a) {
        if (!strcmp(argv[a], "--sizes") && a + 1 < argc) {
            n_sizes = 0;
            for (char* t = strtok(argv[++a], ","); t && n_sizes < MAX_SIZES; t = strtok(NULL, ",")) sizes[n_sizes++] = atoi(t);
        } else if (!strcmp(argv[a], "--frames") && a + 1 < argc) {
            frames = atoi(argv[++a]);
        } else if (!strcmp(argv[a], "--iterations") && a + 1 < argc) {
            iterations = atoi(argv[++a]);
        } else if (!strcmp(argv[a], "--tolerance") && a + 1 < argc) {
            tolerance = atof(argv[++a]);
        } else if (!strcmp(argv[a], "--threads") && a + 1 < argc) {
            threads = atoi(argv[++a]);
        } else if (!strcmp(argv[a], "--precond") && a + 1 < argc && (!strcmp(argv[a + 1], "amg") ||
                                                                      !strcmp(argv[a + 1], "block_jacobi"))) {
            pc = !strcmp(argv[++a], "amg") ? WC_PRECOND_AMG : WC_PRECOND_BLOCK_JACOBI;
        } else if (!strcmp(argv[a], "--skip-cpu")) {
            skip_cpu = 1;
        } else {
            fprintf(stderr, "usage: bench_gpu [--sizes 32,100,316,1000] [--frames 5] [--iterations 30] [--tolerance 0] "
                            "[--threads 0] [--skip-cpu]\n");
            return 2;
        }
    }
    if (frames < 1) frames = 1;
    if (frames > MAX_FRAMES) frames = MAX_FRAMES;
    wg_gl_context_desc cd;
    memset(&cd, 0, sizeof cd);
    wg_gl_context* gl = NULL;
    wg_device* dev = NULL;
    char err[512];
    if (wg_gl_context_create(&cd, &gl, err, sizeof err) != WC_OK || wg_gl_begin(gl, err, sizeof err) != WC_OK ||
        wg_device_create(gl, &dev, err, sizeof err) != WC_OK) {
        fprintf(stderr, "bench_gpu: %s\n", err);
        return 1;
    }
    printf("# GPU backend vs CPU backend\n\n%s; the passes are %s\n\nPCG (%s), %d iterations per solve at most (tolerance %g), 1 "
           "substep of 1/30 s per frame, median of %d frames after one warm-up frame; CPU threads: %d (0 = OpenMP "
           "default). Stages of the GPU from GL timer queries%s.\n\n",
           wg_gl_context_description(gl), dev->compute ? "compute shaders" : "fragment shaders", wc_precond_name(pc),
           iterations, tolerance, frames, threads, dev->has_timer ? "" : " (unavailable here)");
    printf("| particles | CPU ms/frame | GPU ms/frame | CPU/GPU | GPU forces | assemble | solve | collide+integrate | "
           "residual CPU | residual GPU | max |x_gpu - x_cpu| (m) | GPU MiB | GPU passes/frame | it./frame CPU | GPU | GPU passes/iteration |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    double bw[MAX_SIZES][6];
    int bw_n[MAX_SIZES];
    for (int k = 0; k < n_sizes; ++k) {
        int n = sizes[k];
        wc_model m;
        if (!build_sheet(&m, n)) continue;
        wc_state* c = make_state(&m, n, iterations, tolerance, threads, pc);
        wc_state* s = make_state(&m, n, iterations, tolerance, threads, pc);
        wg_sim* g = NULL;
        wc_diag d = {0};
        if (!c || !s || wg_sim_create(dev, s, NULL, &g, &d) != WC_OK) {
            fprintf(stderr, "bench_gpu: %d x %d: %s\n", n, n, d.message);
            return 1;
        }
        double tc[MAX_FRAMES], tg[MAX_FRAMES], stage[4][MAX_FRAMES], passes[MAX_FRAMES], itc[MAX_FRAMES],
            itg[MAX_FRAMES];
        wc_step_stats st, sc;
        memset(&sc, 0, sizeof sc);
        for (int f = 0; f <= frames; ++f) {
            double t0 = wc_now_ms();
            if (!skip_cpu) wc_step_frame(c, 1.0 / 30.0, &sc, &d);
            double t1 = wc_now_ms();
            long long p0 = wg_sim_debug_passes(g);
            wg_sim_step_frame(g, s, 1.0 / 30.0, &st, &d);
            double t2 = wc_now_ms();
            if (f == 0) continue;
            passes[f - 1] = (double)(wg_sim_debug_passes(g) - p0);
            itc[f - 1] = sc.iterations;
            itg[f - 1] = st.iterations;
            tc[f - 1] = t1 - t0;
            tg[f - 1] = t2 - t1;
            stage[0][f - 1] = st.ms.forces;
            stage[1][f - 1] = st.ms.assemble;
            stage[2][f - 1] = st.ms.solve;
            stage[3][f - 1] = st.ms.collide + st.ms.integrate;
        }
        wg_sim_download(g, s, &d);
        double e = 0.0;
        for (int i = 0; i < 3 * m.n_particles && !skip_cpu; ++i) e = fmax(e, fabs(s->x[i] - c->x[i]));
        /* passes a PCG iteration (fixed iterations only): a frame at the cap + 10 against one at the
           cap, after the measured frames */
        double per_it = NAN;
        if (tolerance == 0.0) {
            long long p[3] = {wg_sim_debug_passes(g), 0, 0};
            wc_step_stats extra;   /* the table's columns keep the measured frames' stats */
            for (int j = 1; j < 3; ++j) {
                s->def.solver.max_iterations = iterations + 10 * (j - 1);
                wg_sim_step_frame(g, s, 1.0 / 30.0, &extra, &d);
                p[j] = wg_sim_debug_passes(g);
            }
            s->def.solver.max_iterations = iterations;
            per_it = (double)((p[2] - p[1]) - (p[1] - p[0])) / 10.0;
        }
        double mc = skip_cpu ? NAN : wc_sort_median(tc, frames), mg = wc_sort_median(tg, frames);
        printf("| %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2f | %.2g | %.2g | %.2g | %.1f | %.0f | %.0f | %.0f | %.1f |\n",
               m.n_particles, mc,
               mg, mc / mg, wc_sort_median(stage[0], frames), wc_sort_median(stage[1], frames),
               wc_sort_median(stage[2], frames), wc_sort_median(stage[3], frames), skip_cpu ? NAN : sc.residual,
               st.residual, skip_cpu ? NAN : e, (double)wg_sim_gpu_bytes(g) / (1024.0 * 1024.0),
               wc_sort_median(passes, frames), skip_cpu ? NAN : wc_sort_median(itc, frames), wc_sort_median(itg, frames),
               per_it);
        fflush(stdout);
        bw_n[k] = m.n_particles;
        wg_sim_debug_bandwidth(g, 10, &bw[k][0], &bw[k][1], &bw[k][2], &bw[k][3]);
        gpu_compute_copy(m.n_particles, 10, &bw[k][4], &bw[k][5]);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_state_destroy(c);
        wc_model_free(&m);
    }
    printf("\n## SpMV pass against a copy pass (effective bandwidth; the ratio is the physical-limit measure)\n\n"
           "The copy pass is the solver's (%s); beside it the same copy by a hand-written compute shader (GL 4.3: "
           "texture to image, and shader storage buffer to buffer; - where the context has none), which tells how "
           "much of the device the solver's passes reach.\n\n"
           "| particles | SpMV ms | SpMV GB/s | copy ms | copy GB/s | SpMV / copy | compute copy, texture GB/s | "
           "compute copy, buffer GB/s |\n|---|---|---|---|---|---|---|---|\n",
           dev->compute ? "a compute shader writing an image" : "a fragment shader rendering into a texture");
    for (int k = 0; k < n_sizes; ++k) {
        double gs = bw[k][2] / (bw[k][0] * 1e6), gc = bw[k][3] / (bw[k][1] * 1e6);
        printf("| %d | %.3f | %.2f | %.3f | %.2f | %.0f %% |", bw_n[k], bw[k][0], gs, bw[k][1], gc, 100.0 * gs / gc);
        for (int c = 4; c < 6; ++c)
            if (bw[k][c] > 0.0) printf(" %.2f |", bw[k][3] / (bw[k][c] * 1e6));
            else printf(" - |");
        printf("\n");
    }
    wg_device_destroy(dev);
    wg_gl_end(gl);
    wg_gl_context_destroy(gl);
    return 0;
}
