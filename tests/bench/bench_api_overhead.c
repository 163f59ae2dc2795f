/* Benchmark (not a test): what the public API costs on top of the core, measured in one process
 * on identical work. The hanging sheet (N x N grid, 1 m, horizontal, pinned at the two corners of
 * its z = +0.5 edge, default material, 30 fps, 1 substep) is built twice from the same float
 * positions: once through libweft.so (weft_cloth_create, an attachment for the pins, then
 * weft_cloth_step with identity object and attachment transforms, as `weft run` drives it) and
 * once directly on core (wc_model_build, wc_state_create, wc_state_set_pins, wc_step_frame, as
 * `weft run` did before). Every frame steps both (which one first alternates), so machine noise
 * hits both alike; both runs must do the same solver iterations and reach the same positions
 * (checked: the exit status is 1 otherwise). Prints per-frame medians, the median of the paired
 * differences (API - core) and the cost of reading the results (weft_cloth_get_vertices vs
 * copying core's positions to host order).
 *
 *   bench_api_overhead [--n N] [--frames F] [--threads T]
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clock.h"
#include "cloth_backend.h"
#include "sort.h"
#include "step.h"
#include "weft/weft.h"

static double now_ms(void) { return wc_now_ms(); }


int main(int argc, char** argv) {
    int n = 32, frames = 90, threads = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--n") == 0) n = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--frames") == 0) frames = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--threads") == 0) threads = atoi(argv[i + 1]);
    }
    if (n < 2 || frames < 1 || threads < 0) {
        fprintf(stderr, "usage: bench_api_overhead [--n N >= 2] [--frames F >= 1] [--threads T >= 0]\n");
        return 2;
    }
    const int nv = n * n, nq = (n - 1) * (n - 1);
    float* posf = malloc(sizeof(float) * 3 * (size_t)nv);
    double* posd = malloc(sizeof(double) * 3 * (size_t)nv);
    int* sizes = malloc(sizeof(int) * (size_t)nq);
    int* idx = malloc(sizeof(int) * 4 * (size_t)nq);
    float* out = malloc(sizeof(float) * 3 * (size_t)nv);
    double* host = malloc(sizeof(double) * 3 * (size_t)nv);
    double* t_api = malloc(sizeof(double) * (size_t)frames);
    double* t_core = malloc(sizeof(double) * (size_t)frames);
    double* t_diff = malloc(sizeof(double) * (size_t)frames);
    double* r_api = malloc(sizeof(double) * (size_t)frames);
    double* r_core = malloc(sizeof(double) * (size_t)frames);
    if (!posf || !posd || !sizes || !idx || !out || !host || !t_api || !t_core || !t_diff || !r_api || !r_core) return 1;
    for (int j = 0; j < n; ++j)   /* the scene grid: vertex i + n j at (-0.5 + i/(n-1), 0, -0.5 + j/(n-1)) */
        for (int i = 0; i < n; ++i) {
            float* p = posf + 3 * (i + n * j);
            p[0] = (float)(-0.5 + (double)i / (n - 1));
            p[1] = 0.0f;
            p[2] = (float)(-0.5 + (double)j / (n - 1));
        }
    for (int k = 0; k < 3 * nv; ++k) posd[k] = posf[k];
    int q = 0;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i, ++q) {
            const int a = i + n * j;
            sizes[q] = 4;
            idx[4 * q + 0] = a;
            idx[4 * q + 1] = a + n;
            idx[4 * q + 2] = a + n + 1;
            idx[4 * q + 3] = a + 1;
        }
    int pinned[2] = {n * (n - 1), n * n - 1};

    /* API */
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = threads;
    weft_context* ctx = NULL;
    if (weft_context_create(WEFT_ABI, &cd, &ctx) != WEFT_OK) return 1;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = posf;
    def.mesh.n_vertices = nv;
    def.mesh.face_sizes = sizes;
    def.mesh.n_faces = nq;
    def.mesh.indices = idx;
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = pinned;
    att.n_vertices = 2;
    def.attachments = &att;
    def.n_attachments = 1;
    weft_cloth cloth;
    if (weft_cloth_create(ctx, &def, &cloth) != WEFT_OK) {
        fprintf(stderr, "%s\n", weft_context_last_error(ctx));
        return 1;
    }
    static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

    /* core */
    wc_diag d = {0};
    wc_source_mesh src;
    wc_model model;
    wc_state* state = NULL;
    if (wc_source_mesh_from_arrays(&src, NULL, posd, nv, sizes, nq, idx, 1.0, &d) != WC_OK) return 1;
    wc_model_def md = wc_default_model_def();
    if (wc_model_build(&model, &src, &md, NULL, &d) != WC_OK) return 1;
    wc_sim_def sd = wc_default_sim_def();
    sd.threads = threads;
    /* the CPU backend's defaults for this size (core/cloth_cpu.c, resolved by plugin/backend.c) */
    wc_backend_defaults o;
    const wc_defaults_query dq = {model.n_particles, 0, sd.integrator};
    wc_cloth_cpu.defaults(NULL, &dq, &o);
    sd.solver.preconditioner = o.preconditioner;
    sd.newton_forcing = o.newton_forcing;
    sd.solver.tolerance = o.tolerance;
    sd.newton_iterations = o.newton_iterations;
    sd.line_search = o.line_search;
    if (wc_state_create(&state, &model, &sd, NULL, &d) != WC_OK) return 1;
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    for (int k = 0; k < 2; ++k) {
        pins[k].particle = model.host_to_particle[pinned[k]];
        memcpy(pins[k].target, model.rest_pos + 3 * pins[k].particle, sizeof pins[k].target);
    }
    if (wc_state_set_pins(state, pins, 2, &d) != WC_OK) return 1;

    const double dt = 1.0 / 30.0;
    long long it_api = 0, it_core = 0;
    double max_diff = 0;
    for (int f = 0; f < frames; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = dt;
        fr.object_transform = identity;
        fr.attachment_transforms = identity;
        weft_frame_stats fs;
        wc_step_stats ss;
        weft_status a;
        wc_status b;
        double ta, tb;   /* the two calls in alternating order, so neither always runs first */
        if (f % 2 == 0) {
            double t0 = now_ms();
            a = weft_cloth_step(ctx, cloth, &fr, &fs);
            double t1 = now_ms();
            b = wc_step_frame(state, dt, &ss, &d);
            ta = t1 - t0;
            tb = now_ms() - t1;
        } else {
            double t0 = now_ms();
            b = wc_step_frame(state, dt, &ss, &d);
            double t1 = now_ms();
            a = weft_cloth_step(ctx, cloth, &fr, &fs);
            tb = t1 - t0;
            ta = now_ms() - t1;
        }
        if (a != WEFT_OK || b != WC_OK) return 1;
        double t2 = now_ms();
        int count = 0;
        weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, out, NULL, nv, &count);
        double t3 = now_ms();
        for (int v = 0; v < nv; ++v) memcpy(host + 3 * v, state->x + 3 * model.host_to_particle[v], 3 * sizeof(double));
        double t4 = now_ms();
        t_api[f] = ta;
        t_core[f] = tb;
        t_diff[f] = t_api[f] - t_core[f];
        r_api[f] = t3 - t2;
        r_core[f] = t4 - t3;
        it_api += fs.iterations;
        it_core += ss.iterations;
        for (int k = 0; k < 3 * nv; ++k) max_diff = fmax(max_diff, fabs(out[k] - host[k]));
    }
    printf("hanging sheet %d x %d, %d frames, %d thread%s (0: OpenMP's default)\n", n, n, frames, threads,
           threads == 1 ? "" : "s");
    printf("solver iterations: API %lld, core %lld; largest position difference %.3g m (float outputs)\n", it_api,
           it_core, max_diff);
    const double m_api = wc_sort_median(t_api, frames), m_core = wc_sort_median(t_core, frames);
    const double m_diff = wc_sort_median(t_diff, frames);
    printf("| path | step ms/frame (median) | read results ms/frame (median) |\n|---|---|---|\n");
    printf("| API (weft_cloth_step, weft_cloth_get_vertices) | %.3f | %.4f |\n", m_api, wc_sort_median(r_api, frames));
    printf("| core (wc_step_frame, host-order copy) | %.3f | %.4f |\n", m_core, wc_sort_median(r_core, frames));
    printf("paired difference API - core: median %.4f ms/frame (%.2f %% of the core's median)\n", m_diff,
           100.0 * m_diff / m_core);
    weft_context_destroy(ctx);
    wc_state_destroy(state);
    wc_model_free(&model);
    wc_source_mesh_free(&src);
    free(posf);
    free(posd);
    free(sizes);
    free(idx);
    free(out);
    free(host);
    free(t_api);
    free(t_core);
    free(t_diff);
    free(r_api);
    free(r_core);
    return it_api == it_core && max_diff < 1e-5 ? 0 : 1;
}
