/* WEFT_GPU_SOLVE through the public API (real EGL: llvmpipe without a GPU): a hanging sheet
 * stepped on the GPU with PCG solved in one work group (=group), with block Jacobi and with the
 * multigrid, against the multi-pass chain (=passes), within float bounds and with the same
 * iteration counts to a few;
 * an unknown value refused by name at context creation; =group on fragment passes refused; a
 * cloth past the group's limit refused at creation under =group (either preconditioner), the
 * context left usable. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"

#define N 10            /* grid vertices per side: a 1 m sheet of 100 particles */
#define FRAMES 12

static ag_log g_log;

/* A GPU context with WEFT_GPU_SOLVE=solve (NULL: unset); want: the status expected */
static weft_context* gpu_ctx(const char* solve, weft_status want) {
    if (solve) setenv("WEFT_GPU_SOLVE", solve, 1);
    else unsetenv("WEFT_GPU_SOLVE");
    weft_context_def cd = ap_context_def(WEFT_BACKEND_GPU);
    cd.log = ag_log_fn;
    cd.log_user = &g_log;
    cd.log_level = WEFT_LOG_INFO;
    memset(&g_log, 0, sizeof g_log);
    weft_context* ctx = ap_create(&cd, want, &g_log);
    unsetenv("WEFT_GPU_SOLVE");
    return ctx;
}

/* The sheet m held by two corners (pins) with PCG and preconditioner pc, one linearised step. */
static weft_cloth_def sheet_def(const ag_mesh* m, weft_preconditioner pc, ap_pins* pins) {
    weft_cloth_def def = ap_pinned_sheet_def(m, pins, 1, 0);
    def.preconditioner = pc;
    return def;
}

/* The sheet stepped FRAMES frames in ctx with PCG and preconditioner pc: its vertices (3 nv
 * floats, the caller frees) and the iterations summed over the frames */
static float* run_sheet(weft_context* ctx, const ag_mesh* m, weft_preconditioner pc, int* iterations) {
    ap_pins pins;
    weft_cloth_def def = sheet_def(m, pc, &pins);
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    *iterations = 0;
    for (int f = 0; f < FRAMES; ++f) {
        weft_frame_stats st;
        weft_status s = weft_cloth_step(ctx, cloth, &fr, &st);
        CHECK_EQ_INT(s, WEFT_OK);
        if (s != WEFT_OK) {
            fprintf(stderr, "frame %d: %s\n", f, weft_context_last_error(ctx));
            break;
        }
        *iterations += st.iterations;
    }
    float* p = calloc((size_t)m->nv * 3, sizeof(float));
    int n = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, p, NULL, m->nv, &n), WEFT_OK);
    weft_cloth_destroy(ctx, cloth);
    return p;
}

/* The sheet with preconditioner pc stepped under =group (context a) and =passes (b): the largest
 * vertex distance between the two, how far the sheet fell, the iterations of each */
static void both_forms(weft_context* a, weft_context* b, const ag_mesh* m, weft_preconditioner pc, double* max_d,
                       double* drop, int* it_a, int* it_b) {
    float* pa = run_sheet(a, m, pc, it_a);
    float* pb = run_sheet(b, m, pc, it_b);
    *max_d = 0.0;
    *drop = 0.0;
    for (int i = 0; i < m->nv; ++i) {
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) d2 += (double)(pa[3 * i + c] - pb[3 * i + c]) * (pa[3 * i + c] - pb[3 * i + c]);
        *max_d = fmax(*max_d, sqrt(d2));
        *drop = fmax(*drop, 1.0 - pb[3 * i + 1]);
    }
    printf("%s: group vs passes after %d frames: max |dx| %.3g m, the sheet fell %.3g m; iterations %d / %d\n",
           pc == WEFT_PRECOND_AMG ? "multigrid" : "block Jacobi", FRAMES, *max_d, *drop, *it_a, *it_b);
    free(pa), free(pb);
}

static void test_group_vs_passes(void) {
    const char* passes_env = getenv("WEFT_GPU_PASSES");
    if (passes_env && strcmp(passes_env, "fragment") == 0) return;   /* test_bad_values covers it */
    ag_mesh m;
    ag_grid(&m, N, 1.0, 1.0, 0, 0);
    weft_context* a = gpu_ctx("group", WEFT_OK);
    weft_context* b = gpu_ctx("passes", WEFT_OK);   /* the same multigrid (smoothed P, rotations) */
    if (!a || !b) {
        printf("no GPU context with compute passes here: %s\n", g_log.last);
        weft_context_destroy(a);
        weft_context_destroy(b);
        ag_free(&m);
        return;
    }
    /* block Jacobi: the same float steps summed in another order, each solve converged to its
       tolerance */
    double max_d = 0.0, drop = 0.0;
    int it_a = 0, it_b = 0;
    both_forms(a, b, &m, WEFT_PRECOND_BLOCK_JACOBI, &max_d, &drop, &it_a, &it_b);
    CHECK(drop > 0.05);
    CHECK(max_d < 1e-3);
    CHECK(abs(it_a - it_b) <= FRAMES);
    /* the multigrid (its V-cycle in the group): the same, with far fewer iterations */
    int am_a = 0, am_b = 0;
    both_forms(a, b, &m, WEFT_PRECOND_AMG, &max_d, &drop, &am_a, &am_b);
    CHECK(drop > 0.05);
    CHECK(max_d < 1e-4);
    CHECK(abs(am_a - am_b) <= FRAMES);
    CHECK(2 * am_a < it_a);

    /* a cloth past the group's limit under =group: refused, naming the variable; the context
       still steps the small one */
    ag_mesh big;
    ag_grid(&big, 52, 1.0, 1.0, 0, 0);   /* 2,704 particles */
    ap_pins pins;
    for (int k = 0; k < 2; ++k) {
        weft_cloth_def def = sheet_def(&big, k ? WEFT_PRECOND_AMG : WEFT_PRECOND_BLOCK_JACOBI, &pins);
        weft_cloth cloth = {0};
        CHECK_EQ_INT(weft_cloth_create(a, &def, &cloth), WEFT_ERROR_UNSUPPORTED);
        printf("too large under =group: %s\n", weft_context_last_error(a));
        CHECK(strstr(weft_context_last_error(a), "WEFT_GPU_SOLVE=group") != NULL);
    }
    float* again = run_sheet(a, &m, WEFT_PRECOND_AMG, &it_a);
    free(again);
    ag_free(&big);
    weft_context_destroy(a);
    weft_context_destroy(b);
    ag_free(&m);
}

static void test_bad_values(void) {
    CHECK(gpu_ctx("fast", WEFT_ERROR_GPU) == NULL);
    printf("WEFT_GPU_SOLVE=fast: %s\n", g_log.last);
    CHECK(strstr(g_log.last, "WEFT_GPU_SOLVE='fast'") != NULL);
    /* =group on fragment passes: refused, naming both */
    const char* old = getenv("WEFT_GPU_PASSES");
    char* saved = old ? strdup(old) : NULL;
    setenv("WEFT_GPU_PASSES", "fragment", 1);
    CHECK(gpu_ctx("group", WEFT_ERROR_GPU) == NULL);
    printf("WEFT_GPU_SOLVE=group on fragment passes: %s\n", g_log.last);
    CHECK(strstr(g_log.last, "WEFT_GPU_SOLVE=group needs compute-shader passes") != NULL);
    weft_context_destroy(gpu_ctx("passes", WEFT_OK));   /* =passes is fine there */
    if (saved) setenv("WEFT_GPU_PASSES", saved, 1);
    else unsetenv("WEFT_GPU_PASSES");
    free(saved);
    weft_context_destroy(gpu_ctx("", WEFT_OK));   /* empty: unset */
}

int main(void) {
    RUN_TEST(test_group_vs_passes);
    RUN_TEST(test_bad_values);
    return TEST_SUMMARY();
}
