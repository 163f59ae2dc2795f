/* WEFT_BACKEND_AUTO through the public API: the backend by the cloth.
 *  - here, with the crossover table: on a software device (llvmpipe: CI) or without a GPU every
 *    cloth runs on the CPU and its weft_cloth_info says why; on a hardware device a small cloth
 *    runs on the CPU and one past the table's crossover on the GPU; the creation's INFO line says
 *    which and why; CPU and GPU contexts say "asked for";
 *  - WEFT_AUTO_CROSSOVER=100 (the override, which keeps a software device too): in one context a
 *    64-particle sheet on the CPU, a 144-particle sheet on the GPU, and a 144-particle sheet with
 *    the direct solver (which the GPU refuses) on the CPU, each with the DEFAULT choices of its own
 *    backend; stepped together in weft_context_step, each ends as it does alone in a context of
 *    its backend (the CPU's bit for bit, the GPU's to float precision);
 *  - bad overrides refuse the AUTO context with a message naming the variable (nothing made);
 *    CPU and GPU contexts do not read it. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "api_grid.h"
#include "check.h"

#define FRAMES 6
#define DT (1.0 / 60.0)

static ag_log g_log;
static char g_created[512];   /* the last weft_cloth_create INFO line */

static void log_fn(weft_log_level level, const char* message, void* user) {
    ag_log_fn(level, message, user);
    if (strncmp(message, "weft_cloth_create: ", 19) == 0) snprintf(g_created, sizeof g_created, "%s", message);
}

/* env var name = value (NULL: unset); returns the old value (to free) */
static char* env_set(const char* name, const char* value) {
    const char* old = getenv(name);
    char* saved = old ? strdup(old) : NULL;
    if (value) setenv(name, value, 1);
    else unsetenv(name);
    return saved;
}

static void env_restore(const char* name, char* saved) {
    free(env_set(name, saved));
    free(saved);
}

static weft_status make_ctx(weft_backend backend, weft_context** out) {
    weft_context_def cd = weft_default_context_def();
    cd.backend = backend;
    cd.threads = 1;
    cd.log = log_fn;
    cd.log_user = &g_log;
    cd.log_level = WEFT_LOG_INFO;
    *out = NULL;
    return weft_context_create(WEFT_ABI, &cd, out);
}

/* One n x n sheet hanging from its top corners. */
typedef struct sheet {
    ag_mesh mesh;
    int pins[2];
    weft_attachment_def att;
    weft_cloth cloth;
    weft_cloth_info info;
} sheet;

static weft_status sheet_make(weft_context* ctx, sheet* s, int n, weft_solver solver) {
    memset(s, 0, sizeof *s);
    ag_grid(&s->mesh, n, 0.5, 1.0, 1, 0);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&s->mesh);
    def.solver = solver;
    def.preconditioner = solver == WEFT_SOLVER_PCG ? WEFT_PRECOND_BLOCK_JACOBI : WEFT_PRECOND_DEFAULT;
    s->pins[0] = n * (n - 1);
    s->pins[1] = n * n - 1;
    s->att = weft_default_attachment_def();
    s->att.vertices = s->pins;
    s->att.n_vertices = 2;
    def.attachments = &s->att;
    def.n_attachments = 1;
    g_created[0] = '\0';
    weft_status st = weft_cloth_create(ctx, &def, &s->cloth);
    if (st == WEFT_OK) CHECK_EQ_INT(weft_cloth_get_info(ctx, s->cloth, &s->info), WEFT_OK);
    return st;
}

static int has(const char* text, const char* needle) {
    if (strstr(text, needle)) return 1;
    fprintf(stderr, "  \"%s\" lacks \"%s\"\n", text, needle);
    return 0;
}

/* The cloth's frame f: its pins swing along x. */
static weft_frame frame_of(float* pin, int f) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    ag_transform(pin, 0, 1, 0, 0.0, 0.05 * f, 0.0, 0.0);
    fr.attachment_transforms = pin;
    return fr;
}

/* World positions after FRAMES frames of weft_cloth_step, alone in a context of backend b. */
static int alone(weft_backend b, int n, weft_solver solver, float* out) {
    weft_context* ctx = NULL;
    if (make_ctx(b, &ctx) != WEFT_OK) return 0;
    sheet s;
    CHECK_EQ_INT(sheet_make(ctx, &s, n, solver), WEFT_OK);
    float pin[16];
    for (int f = 0; f < FRAMES; ++f) {
        weft_frame fr = frame_of(pin, f);
        CHECK_EQ_INT(weft_cloth_step(ctx, s.cloth, &fr, NULL), WEFT_OK);
    }
    int count = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, s.cloth, WEFT_SPACE_WORLD, out, NULL, s.mesh.nv, &count), WEFT_OK);
    weft_context_destroy(ctx);
    ag_free(&s.mesh);
    return 1;
}

static void test_table_here(void) {
    char* saved = env_set("WEFT_AUTO_CROSSOVER", NULL);
    weft_context* ctx = NULL;
    CHECK_EQ_INT(make_ctx(WEFT_BACKEND_AUTO, &ctx), WEFT_OK);
    printf("  AUTO context: %s\n", g_log.last);
    sheet small, large;
    CHECK_EQ_INT(sheet_make(ctx, &small, 8, WEFT_SOLVER_PCG), WEFT_OK);
    printf("  8 x 8: %s\n", small.info.backend_reason);
    CHECK(has(g_created, "weft_cloth_create: 64 particles on the CPU backend: AUTO: "));
    CHECK(has(g_created, small.info.backend_reason));
    CHECK_EQ_INT(small.info.backend, WEFT_BACKEND_CPU);
    CHECK_EQ_INT(small.info.newton_iterations, 2);   /* the CPU's defaults */
    if (weft_context_backend(ctx) == WEFT_BACKEND_CPU) {
        /* no device kept: a software rasteriser, or none */
        CHECK(strstr(small.info.backend_reason, "is a software rasteriser, slower than the CPU backend") ||
              strstr(small.info.backend_reason, "AUTO: no GPU device ("));
    } else {
        /* a hardware device: the small sheet is below any crossover of the table */
        CHECK(has(small.info.backend_reason, "AUTO: 64 particles, below the GPU's crossover of "));
        CHECK_EQ_INT(sheet_make(ctx, &large, 110, WEFT_SOLVER_PCG), WEFT_OK);
        printf("  110 x 110: %s\n", large.info.backend_reason);
        CHECK_EQ_INT(large.info.backend, WEFT_BACKEND_GPU);
        CHECK(has(large.info.backend_reason, "AUTO: 12100 particles, at or above the GPU's crossover of "));
        CHECK(has(g_created, "on the GPU backend: AUTO: "));
        ag_free(&large.mesh);
    }
    weft_context_destroy(ctx);
    ag_free(&small.mesh);

    CHECK_EQ_INT(make_ctx(WEFT_BACKEND_CPU, &ctx), WEFT_OK);
    CHECK_EQ_INT(sheet_make(ctx, &small, 8, WEFT_SOLVER_PCG), WEFT_OK);
    CHECK(has(small.info.backend_reason, "asked for (weft_context_def.backend CPU)"));
    weft_context_destroy(ctx);
    ag_free(&small.mesh);
    if (make_ctx(WEFT_BACKEND_GPU, &ctx) == WEFT_OK) {
        CHECK_EQ_INT(sheet_make(ctx, &small, 8, WEFT_SOLVER_PCG), WEFT_OK);
        CHECK_EQ_INT(small.info.backend, WEFT_BACKEND_GPU);
        CHECK(has(small.info.backend_reason, "asked for (weft_context_def.backend GPU)"));
        /* asked for, the GPU still refuses what it lacks */
        sheet direct;
        CHECK_EQ_INT(sheet_make(ctx, &direct, 8, WEFT_SOLVER_DIRECT), WEFT_ERROR_UNSUPPORTED);
        ag_free(&direct.mesh);
        weft_context_destroy(ctx);
        ag_free(&small.mesh);
    }
    env_restore("WEFT_AUTO_CROSSOVER", saved);
}

/* Largest |a - b| over n floats. */
static double max_diff(const float* a, const float* b, int n) {
    double m = 0.0;
    for (int i = 0; i < n; ++i) {
        double d = a[i] > b[i] ? (double)a[i] - b[i] : (double)b[i] - a[i];
        if (!(d <= m)) m = d;
    }
    return m;
}

static void test_override_mixed(void) {
    char* saved = env_set("WEFT_AUTO_CROSSOVER", "100");
    weft_context* ctx = NULL;
    CHECK_EQ_INT(make_ctx(WEFT_BACKEND_AUTO, &ctx), WEFT_OK);
    sheet s[3];
    CHECK_EQ_INT(sheet_make(ctx, &s[0], 8, WEFT_SOLVER_PCG), WEFT_OK);      /* 64: below */
    CHECK_EQ_INT(sheet_make(ctx, &s[1], 12, WEFT_SOLVER_PCG), WEFT_OK);     /* 144: at or above */
    CHECK_EQ_INT(sheet_make(ctx, &s[2], 12, WEFT_SOLVER_DIRECT), WEFT_OK);  /* refused by the GPU */
    for (int k = 0; k < 3; ++k) printf("  cloth %d: %s\n", k, s[k].info.backend_reason);
    const int gpu = weft_context_backend(ctx) == WEFT_BACKEND_GPU;
    if (!gpu) {
        printf("  no GPU device here: every cloth on the CPU\n");
        for (int k = 0; k < 3; ++k) {
            CHECK_EQ_INT(s[k].info.backend, WEFT_BACKEND_CPU);
            CHECK(has(s[k].info.backend_reason, "AUTO: no GPU device ("));
        }
    } else {
        CHECK_EQ_INT(s[0].info.backend, WEFT_BACKEND_CPU);
        CHECK(has(s[0].info.backend_reason, "AUTO: 64 particles, below the GPU's crossover of 100 on "));
        CHECK(has(s[0].info.backend_reason, "(WEFT_AUTO_CROSSOVER)"));
        CHECK_EQ_INT(s[1].info.backend, WEFT_BACKEND_GPU);
        CHECK(has(s[1].info.backend_reason, "AUTO: 144 particles, at or above the GPU's crossover of 100 on "));
        CHECK_EQ_INT(s[2].info.backend, WEFT_BACKEND_CPU);
        CHECK(has(s[2].info.backend_reason, "AUTO: the GPU lacks what this cloth uses (GPU backend: the GPU backend "
                                            "has no direct solver"));
        /* each with its own backend's defaults: the same method on both (two Newton iterations
           with the line search) */
        for (int k = 0; k < 3; ++k) {
            CHECK_EQ_INT(s[k].info.newton_iterations, 2);
            CHECK_EQ_INT(s[k].info.line_search, 1);
        }
    }

    /* all three in one weft_context_step a frame */
    float pin[3][16];
    for (int f = 0; f < FRAMES; ++f) {
        weft_cloth cloths[3];
        weft_frame frames[3];
        weft_status statuses[3];
        for (int k = 0; k < 3; ++k) {
            cloths[k] = s[k].cloth;
            frames[k] = frame_of(pin[k], f);
        }
        CHECK_EQ_INT(weft_context_step(ctx, 3, cloths, frames, NULL, statuses), WEFT_OK);
        for (int k = 0; k < 3; ++k) CHECK_EQ_INT(statuses[k], WEFT_OK);
    }
    const int sides[3] = {8, 12, 12};
    const weft_solver solvers[3] = {WEFT_SOLVER_PCG, WEFT_SOLVER_PCG, WEFT_SOLVER_DIRECT};
    for (int k = 0; k < 3; ++k) {
        int nv = s[k].mesh.nv, count = 0;
        float* got = malloc(sizeof(float) * 3 * (size_t)nv);
        float* ref = malloc(sizeof(float) * 3 * (size_t)nv);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, s[k].cloth, WEFT_SPACE_WORLD, got, NULL, nv, &count), WEFT_OK);
        if (alone(s[k].info.backend, sides[k], solvers[k], ref)) {
            double diff = max_diff(got, ref, 3 * nv);
            printf("  cloth %d (%s): %.3g m from its run alone\n", k, s[k].info.backend == WEFT_BACKEND_GPU ? "GPU" : "CPU",
                   diff);
            /* the CPU's step is the same bits in a batch; the GPU's the same passes in float */
            CHECK(s[k].info.backend == WEFT_BACKEND_CPU ? diff == 0.0 : diff < 1e-5);
            CHECK(max_diff(got, s[k].mesh.pos, 3 * nv) > 1e-3);   /* it moved: not two rest shapes compared */
        }
        free(got);
        free(ref);
    }
    weft_context_destroy(ctx);
    for (int k = 0; k < 3; ++k) ag_free(&s[k].mesh);
    env_restore("WEFT_AUTO_CROSSOVER", saved);
}

static void test_bad_override(void) {
    const char* bad[] = {"abc", "-1", "1e3", " 5", "2000000000"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char* saved = env_set("WEFT_AUTO_CROSSOVER", bad[k]);
        memset(&g_log, 0, sizeof g_log);
        weft_context* ctx = (weft_context*)&g_log;
        CHECK_EQ_INT(make_ctx(WEFT_BACKEND_AUTO, &ctx), WEFT_ERROR_INVALID_ARGUMENT);
        CHECK(ctx == NULL);
        char want[128];
        snprintf(want, sizeof want, "weft_context_create: WEFT_AUTO_CROSSOVER='%s' is not a particle count", bad[k]);
        CHECK(has(g_log.last, want));
        CHECK_EQ_INT(g_log.count[WEFT_LOG_ERROR], 1);
        /* a CPU context does not read it */
        CHECK_EQ_INT(make_ctx(WEFT_BACKEND_CPU, &ctx), WEFT_OK);
        weft_context_destroy(ctx);
        env_restore("WEFT_AUTO_CROSSOVER", saved);
    }
    /* empty: unset, the table */
    char* saved = env_set("WEFT_AUTO_CROSSOVER", "");
    weft_context* ctx = NULL;
    CHECK_EQ_INT(make_ctx(WEFT_BACKEND_AUTO, &ctx), WEFT_OK);
    weft_context_destroy(ctx);
    env_restore("WEFT_AUTO_CROSSOVER", saved);
}

int main(void) {
    RUN_TEST(test_table_here);
    RUN_TEST(test_override_mixed);
    RUN_TEST(test_bad_override);
    return TEST_SUMMARY();
}
