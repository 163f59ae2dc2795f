/* Regressions found by `weft bench torture` (plugin/cli/bench/cmd_bench_torture*.c), through the public
 * API only. Each case failed before its fix:
 *  - a NaN or Inf in a collider field its type does not use (a plane's radius, a sphere's
 *    half_height) was accepted: every numeric field of a def must be finite;
 *  - a step whose last-resort retry (the direct solver, accepted whenever it is finite) blew the
 *    cloth up to coordinates beyond float range returned WEFT_OK with infinite vertices: such a
 *    step is now STEP_FAILED with the cloth as it was;
 *  - finite host arrays and a valid unit_scale whose product lies beyond float range made a cloth
 *    whose vertices read back as Inf: refused at creation with OUT_OF_RANGE. */
#include <stdio.h>
#include "api_grid.h"
#include "check.h"

static weft_context* new_context(void) {
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = 1;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

/* 1 when every position and normal of the cloth, in both spaces, is finite */
static int outputs_finite(weft_context* ctx, weft_cloth c, int nv) {
    float* p = malloc(sizeof(float) * 3 * (size_t)nv);
    float* n = malloc(sizeof(float) * 3 * (size_t)nv);
    int ok = p && n, count = 0;
    for (int s = 0; s < 2 && ok; ++s) {
        ok = weft_cloth_get_vertices(ctx, c, s ? WEFT_SPACE_OBJECT : WEFT_SPACE_WORLD, p, n, nv, &count) == WEFT_OK;
        for (int i = 0; i < 3 * nv && ok; ++i) ok = isfinite(p[i]) && isfinite(n[i]);
    }
    free(p);
    free(n);
    return ok;
}

static void test_unused_collider_fields(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 4, 1.0, 0.0, 0, 0);
    const struct {
        weft_collider_type type;
        int field; /* 0: radius, 1: half_height */
        double value;
        weft_status expected;
    } cases[] = {
        {WEFT_COLLIDER_PLANE, 0, NAN, WEFT_ERROR_NONFINITE},
        {WEFT_COLLIDER_PLANE, 0, INFINITY, WEFT_ERROR_NONFINITE},
        {WEFT_COLLIDER_PLANE, 1, -INFINITY, WEFT_ERROR_NONFINITE},
        {WEFT_COLLIDER_SPHERE, 1, NAN, WEFT_ERROR_NONFINITE},
        {WEFT_COLLIDER_SPHERE, 1, INFINITY, WEFT_ERROR_NONFINITE},
        {WEFT_COLLIDER_CAPSULE, 1, NAN, WEFT_ERROR_NONFINITE},
        {WEFT_COLLIDER_PLANE, 0, -3.0, WEFT_OK},   /* unused and finite: ignored, as before */
        {WEFT_COLLIDER_SPHERE, 1, -3.0, WEFT_OK},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        weft_collider_def col = weft_default_collider_def();
        col.type = cases[k].type;
        if (cases[k].field == 0) col.radius = cases[k].value;
        else col.half_height = cases[k].value;
        weft_cloth_def def = weft_default_cloth_def();
        def.mesh = ag_desc(&m);
        def.colliders = &col;
        def.n_colliders = 1;
        weft_cloth c = {0};
        weft_status st = weft_cloth_create(ctx, &def, &c);
        CHECK_EQ_INT(st, cases[k].expected);
        if (st != WEFT_OK) {
            CHECK(c.id == 0);
            CHECK(strstr(weft_context_last_error(ctx), cases[k].field ? "colliders[0].half_height" : "colliders[0].radius"));
        } else {
            weft_frame fr = weft_default_frame();
            CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
            CHECK(outputs_finite(ctx, c, m.nv));
            CHECK_EQ_INT(weft_cloth_destroy(ctx, c), WEFT_OK);
        }
    }
    ag_free(&m);
    weft_context_destroy(ctx);
}

/* A 1 m sheet in a 100 km/s wind with a normal drag of 1e6 kg/(m^2 s) and no damping: the steps'
 * retries end in the last-resort direct solve, whose finite but exploding result used to be
 * accepted until the vertices overflowed float. Every step must now be OK with finite outputs,
 * or STEP_FAILED with the cloth exactly as before the call. */
static void test_blowup_step(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 4, 1.0, 0.0, 0, 0);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    for (int k = 0; k < 3; ++k) {
        def.wind[k] = 1e5;
        def.material.damping[k] = 0.0;
    }
    def.air_drag_normal = 1e6;
    weft_cloth c = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    unsigned char* before = malloc(info.snapshot_size);
    unsigned char* after = malloc(info.snapshot_size);
    int failed = 0, ok = 0;
    const double dts[6] = {1.0 / 600, 1.0 / 8000, 1.0 / 40, 1.0 / 60, 1.0 / 30, 1.0 / 60};
    for (int f = 0; f < 6; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = dts[f];
        CHECK_EQ_INT(weft_cloth_save(ctx, c, before, info.snapshot_size), WEFT_OK);
        weft_status st = weft_cloth_step(ctx, c, &fr, NULL);
        CHECK(st == WEFT_OK || st == WEFT_ERROR_STEP_FAILED);
        CHECK(outputs_finite(ctx, c, m.nv));
        if (st == WEFT_ERROR_STEP_FAILED) {
            ++failed;
            CHECK(weft_context_last_error(ctx)[0] != '\0');
            CHECK_EQ_INT(weft_cloth_save(ctx, c, after, info.snapshot_size), WEFT_OK);
            CHECK(memcmp(before, after, info.snapshot_size) == 0);
        } else {
            ++ok;
        }
    }
    printf("  blow-up scene: %d frames ok, %d step_failed\n", ok, failed);
    CHECK(failed > 0); /* the scene does blow up: the guard was exercised */
    free(before);
    free(after);
    ag_free(&m);
    weft_context_destroy(ctx);
}

/* Host arrays at 1e30 mesh units times unit_scale 1e12: 1e42 m, beyond float. */
static void test_create_beyond_float(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 3, 1.0, 0.0, 0, 0);
    for (int i = 0; i < 3 * m.nv; ++i) m.pos[i] *= 1e30f;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    def.unit_scale = 1e12;
    weft_cloth c = {0};
    weft_status st = weft_cloth_create(ctx, &def, &c);
    CHECK_EQ_INT(st, WEFT_ERROR_OUT_OF_RANGE);
    CHECK(strstr(weft_context_last_error(ctx), "def->mesh") != NULL);
    if (st == WEFT_OK) {
        CHECK(outputs_finite(ctx, c, m.nv));
        weft_cloth_destroy(ctx, c);
    }
    /* the same arrays at unit_scale 1e-12 (1e18 m) are fine */
    def.unit_scale = 1e-12;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    CHECK(outputs_finite(ctx, c, m.nv));
    ag_free(&m);
    weft_context_destroy(ctx);
}

int main(void) {
    RUN_TEST(test_unused_collider_fields);
    RUN_TEST(test_blowup_step);
    RUN_TEST(test_create_beyond_float);
    return TEST_SUMMARY();
}
