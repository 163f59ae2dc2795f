/* Newton iterations on the GPU backend through the public API (real EGL: llvmpipe without a
 * GPU): a 1 m sheet held by two corners swinging down, with two Newton iterations without and
 * with the line search on both backends (PCG with block Jacobi), GPU against CPU; the GPU's
 * Newton steps counted and its rollbacks at Newton 2 against Newton 1; frames of 0.1 s at Newton
 * 3, where the line search backtracks; Newton with colliders accepted on the GPU (its runs against
 * the CPU's: test_api_gpu_newton_contacts.c), with backward Euler and TR-BDF2. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"

#define N 12
#define FRAMES 40

static ap_pins g_pins;

typedef struct run_result {
    float pos[3 * N * N];
    int rollbacks, newton_steps, solves, backtracks, ok;
} run_result;

static void run_frames(weft_context* ctx, const ag_mesh* m, int newton, int line_search, int frames, double dt,
                       run_result* r) {
    memset(r, 0, sizeof *r);
    weft_cloth_def def = ap_pinned_sheet_def(m, &g_pins, newton, line_search);
    def.max_frame_time = dt;
    weft_cloth cloth = {0};
    weft_status st = weft_cloth_create(ctx, &def, &cloth);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        fprintf(stderr, "weft_cloth_create: %s\n", weft_context_last_error(ctx));
        return;
    }
    weft_frame fr = weft_default_frame();
    fr.dt = dt;
    for (int f = 0; f < frames; ++f) {
        weft_frame_stats fs;
        st = weft_cloth_step(ctx, cloth, &fr, &fs);
        CHECK_EQ_INT(st, WEFT_OK);
        if (st != WEFT_OK) return;
        r->rollbacks += fs.rollbacks;
        r->newton_steps += fs.newton_steps;
        r->solves += fs.solves;
        r->backtracks += fs.line_search_backtracks;
    }
    int n = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, r->pos, NULL, N * N, &n), WEFT_OK);
    r->ok = 1;
    CHECK_EQ_INT(weft_cloth_destroy(ctx, cloth), WEFT_OK);
}

static void run(weft_context* ctx, const ag_mesh* m, int newton, int line_search, run_result* r) {
    run_frames(ctx, m, newton, line_search, FRAMES, 1.0 / 60.0, r);
}

static double max_distance(const float* a, const float* b) {
    double most = 0.0;
    for (int i = 0; i < N * N; ++i) {
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) d2 += pow((double)a[3 * i + c] - b[3 * i + c], 2);
        most = fmax(most, sqrt(d2));
    }
    return most;
}

static run_result cpu2, gpu2, gpu1, cpu1, cpu_ls, gpu_ls;

static void test_newton_vs_cpu(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* cpu = ap_context(WEFT_BACKEND_CPU);
    weft_context* gpu = ap_context(WEFT_BACKEND_GPU);
    if (!cpu || !gpu) return;
    run(cpu, &m, 2, 0, &cpu2);
    run(gpu, &m, 2, 0, &gpu2);
    run(gpu, &m, 1, 0, &gpu1);
    run(cpu, &m, 1, 0, &cpu1);
    run(cpu, &m, 2, 1, &cpu_ls);
    run(gpu, &m, 2, 1, &gpu_ls);
    if (cpu2.ok && gpu2.ok && gpu1.ok && cpu1.ok) {
        double d2 = max_distance(gpu2.pos, cpu2.pos), d1 = max_distance(gpu1.pos, cpu1.pos);
        double n1 = max_distance(cpu2.pos, cpu1.pos), drop = 0.0;
        for (int i = 0; i < N * N; ++i) drop = fmax(drop, fabs(cpu2.pos[3 * i + 1] - m.pos[3 * i + 1]));
        printf("  %d frames, largest vertex distance GPU vs CPU: Newton 2 %.3g m, Newton 1 %.3g m (the CPU's Newton 2 "
               "vs its Newton 1: %.3g m; the sheet dropped %.3g m)\n", FRAMES, d2, d1, n1, drop);
        printf("  Newton 2: CPU %d solves, %d Newton steps, %d rollbacks; GPU %d solves, %d Newton steps, %d rollbacks\n",
               cpu2.solves, cpu2.newton_steps, cpu2.rollbacks, gpu2.solves, gpu2.newton_steps, gpu2.rollbacks);
        printf("  Newton 1: CPU %d rollbacks, GPU %d rollbacks\n", cpu1.rollbacks, gpu1.rollbacks);
        CHECK(drop > 0.3);
        CHECK(d2 < 5e-3);                 /* float vs double solvers, as test_api_gpu's Newton 1 */
        CHECK(d2 < 0.2 * n1);             /* the second iteration is followed, not just the first */
        CHECK(gpu2.newton_steps > 0);
        CHECK(gpu2.newton_steps >= cpu2.newton_steps / 2);
        CHECK(gpu2.rollbacks <= gpu1.rollbacks);
        CHECK(gpu2.rollbacks <= cpu2.rollbacks);
    }
    if (cpu_ls.ok && gpu_ls.ok) {
        double d = max_distance(gpu_ls.pos, cpu_ls.pos);
        printf("  Newton 2 with the line search: GPU vs CPU %.3g m; CPU %d solves, %d backtracks, %d rollbacks; GPU %d "
               "solves, %d backtracks, %d rollbacks\n", d, cpu_ls.solves, cpu_ls.backtracks, cpu_ls.rollbacks,
               gpu_ls.solves, gpu_ls.backtracks, gpu_ls.rollbacks);
        CHECK(d < 5e-3);
        CHECK(gpu_ls.newton_steps > 0);
        CHECK(gpu_ls.rollbacks <= cpu_ls.rollbacks);
    }
    weft_context_destroy(cpu);
    weft_context_destroy(gpu);
    ag_free(&m);
}

/* Ten frames of 0.1 s in one substep each at Newton 3 with the line search: the search backtracks
 * on both backends, the GPU as often as the CPU within a few, and the two end close. */
static void test_backtracking(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* cpu = ap_context(WEFT_BACKEND_CPU);
    weft_context* gpu = ap_context(WEFT_BACKEND_GPU);
    if (!cpu || !gpu) return;
    run_frames(cpu, &m, 3, 1, 10, 0.1, &cpu_ls);
    run_frames(gpu, &m, 3, 1, 10, 0.1, &gpu_ls);
    if (cpu_ls.ok && gpu_ls.ok) {
        double d = max_distance(gpu_ls.pos, cpu_ls.pos);
        printf("  0.1 s frames at Newton 3 with the search: GPU vs CPU %.3g m; backtracks CPU %d, GPU %d; Newton steps "
               "CPU %d, GPU %d; rollbacks CPU %d, GPU %d\n", d, cpu_ls.backtracks, gpu_ls.backtracks,
               cpu_ls.newton_steps, gpu_ls.newton_steps, cpu_ls.rollbacks, gpu_ls.rollbacks);
        CHECK(cpu_ls.backtracks > 0);
        CHECK(gpu_ls.backtracks > 0);
        CHECK(abs(gpu_ls.backtracks - cpu_ls.backtracks) <= cpu_ls.backtracks / 4 + 2);
        CHECK(gpu_ls.rollbacks <= cpu_ls.rollbacks);
        CHECK(d < 0.05);   /* a 1 m sheet falling ~1 m in steps of 0.1 s, solved to 1e-4 in float and double */
    }
    weft_context_destroy(cpu);
    weft_context_destroy(gpu);
    ag_free(&m);
}

/* Newton 2, and Newton 1 with the line search, with a collider on the GPU: accepted and stepped
 * (test_api_gpu_newton_contacts.c compares them with the CPU), backward Euler and TR-BDF2 alike. */
static void test_colliders_accepted(void) {
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.5, 0, 0);
    weft_context* gpu = ap_context(WEFT_BACKEND_GPU);
    if (!gpu) return;
    weft_cloth_def def = ap_pinned_sheet_def(&m, &g_pins, 2, 0);
    weft_collider_def sph = weft_default_collider_def();
    sph.type = WEFT_COLLIDER_SPHERE;
    sph.radius = 0.3;
    def.colliders = &sph;
    def.n_colliders = 1;
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    weft_cloth cloth = {0};
    for (int k = 0; k < 2; ++k) {
        def.newton_iterations = k == 0 ? 2 : 1;
        def.line_search = k;
        CHECK_EQ_INT(weft_cloth_create(gpu, &def, &cloth), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(gpu, cloth, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_destroy(gpu, cloth), WEFT_OK);
    }
    def.integrator = WEFT_INTEGRATOR_TRBDF2;
    CHECK_EQ_INT(weft_cloth_create(gpu, &def, &cloth), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_step(gpu, cloth, &fr, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_destroy(gpu, cloth), WEFT_OK);
    weft_context_destroy(gpu);
    ag_free(&m);
}

int main(void) {
    RUN_TEST(test_newton_vs_cpu);
    RUN_TEST(test_backtracking);
    RUN_TEST(test_colliders_accepted);
    return TEST_SUMMARY();
}
