/* weft_mesh_collider_def.push_speed through the public API: a sheet created 1.5 cm inside a box
 * (half of it over the box's top face, half beside the box) is let out at most push_speed x dt
 * per frame (one substep), reaches the thickness shell after about depth / push_speed, and is
 * stretched less on the way than with push_speed 0 (put on the shell at once: the half inside
 * jumps, the half beside the box stays); with 0 every vertex is on the shell after one frame.
 * Bad push_speed values (NaN, negative) are refused with a clear error and nothing created. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "api_grid.h"
#include "check.h"
#include "test_support.h"

#define N 12
#define DT (1.0 / 30.0)
#define TOP 0.3          /* m: the box's top face */
#define DEPTH 0.015      /* m: the sheet starts this far below it */
#define THICK 0.005      /* m */

static float g_box[8 * 3];
static int g_box_tris[12 * 3];

static void make_box(void) {
    const double lo[3] = {-0.3, 0.0, -0.3}, hi[3] = {0.3, TOP, 0.3};
    for (int k = 0; k < 8; ++k) {
        g_box[3 * k] = (float)((k & 1) ? hi[0] : lo[0]);
        g_box[3 * k + 1] = (float)((k & 2) ? hi[1] : lo[1]);
        g_box[3 * k + 2] = (float)((k & 4) ? hi[2] : lo[2]);
    }
    int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int k = 0; k < 6; ++k) {
        int t[6] = {q[k][0], q[k][1], q[k][2], q[k][0], q[k][2], q[k][3]};
        memcpy(g_box_tris + 6 * k, t, sizeof t);
    }
}

typedef struct run_result {
    double max_rise;     /* m: the largest rise of a vertex in one frame, over the inside half */
    double max_strain;   /* over every frame */
    int frames_to_shell; /* first frame after which every inside vertex is on the shell (-1: never) */
} run_result;

static run_result run(weft_context* ctx, double push_speed, int frames) {
    ag_mesh sheet;
    ag_grid(&sheet, N, 0.4, TOP - DEPTH, 0, 0);
    weft_mesh_collider_def m = weft_default_mesh_collider_def();
    m.mesh.positions = g_box;
    m.mesh.n_vertices = 8;
    m.mesh.indices = g_box_tris;
    m.mesh.n_faces = 12;
    m.thickness = THICK;
    m.friction = 0.0;
    m.push_speed = push_speed;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&sheet);
    def.n_mesh_colliders = 1;
    def.mesh_colliders = &m;
    def.gravity[1] = 0.0; /* the push alone */
    def.self_collision = 0;
    ag_transform(def.transform, 0, 1, 0, 0.0, 0.25, 0.0, 0.0); /* x in [0.05, 0.45]: the box ends at 0.3 */
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    int nv = sheet.nv, count = 0;
    float* prev = malloc(sizeof(float) * 3 * (size_t)nv);
    float* pos = malloc(sizeof(float) * 3 * (size_t)nv);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, prev, NULL, nv, &count), WEFT_OK);
    run_result r = {0.0, 0.0, -1};
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    for (int f = 1; f <= frames; ++f) {
        weft_frame_stats st;
        CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, &st), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, pos, NULL, nv, &count), WEFT_OK);
        r.max_strain = fmax(r.max_strain, st.max_strain);
        int all_on = 1;
        for (int i = 0; i < nv; ++i) {
            if (!(prev[3 * i] < 0.29)) continue; /* the half over the box (its edge zone left out) */
            r.max_rise = fmax(r.max_rise, (double)pos[3 * i + 1] - prev[3 * i + 1]);
            if (!(pos[3 * i + 1] >= TOP + THICK - 2e-4)) all_on = 0;
        }
        if (all_on && r.frames_to_shell < 0) r.frames_to_shell = f;
        memcpy(prev, pos, sizeof(float) * 3 * (size_t)nv);
    }
    free(prev);
    free(pos);
    ag_free(&sheet);
    CHECK_EQ_INT(weft_cloth_destroy(ctx, c), WEFT_OK);
    return r;
}

static void test_push_speed(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.backend = WEFT_BACKEND_CPU;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    CHECK_NEAR(weft_default_mesh_collider_def().push_speed, 0.05, 0.0);
    const double speed = 0.05, cap = speed * DT;
    run_result slow = run(ctx, speed, 20);
    run_result fast = run(ctx, 0.0, 3);
    double expect = (DEPTH + THICK) / cap; /* frames */
    printf("  push_speed %.2f m/s: largest rise %.4f m per frame (cap %.4f), on the shell after %d frames "
           "(depth / cap: %.1f), max strain %.4f\n", speed, slow.max_rise, cap, slow.frames_to_shell, expect,
           slow.max_strain);
    printf("  push_speed 0: largest rise %.4f m per frame, on the shell after %d frame(s), max strain %.4f\n",
           fast.max_rise, fast.frames_to_shell, fast.max_strain);
    CHECK(slow.max_rise <= cap * (1.0 + 1e-3) + 1e-6);
    CHECK(slow.max_rise >= 0.9 * cap);                 /* it does move at the cap */
    CHECK(slow.frames_to_shell >= (int)floor(expect) && slow.frames_to_shell <= (int)ceil(expect) + 2);
    CHECK_EQ_INT(fast.frames_to_shell, 1);
    CHECK(fast.max_rise >= DEPTH + THICK - 1e-4);
    CHECK(slow.max_strain < fast.max_strain);
    weft_context_destroy(ctx);
}

static void test_bad_push_speed(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    ag_mesh sheet;
    ag_grid(&sheet, N, 0.4, 0.5, 0, 0);
    const double bad[2] = {NAN, -0.01};
    const weft_status want[2] = {WEFT_ERROR_NONFINITE, WEFT_ERROR_INVALID_ARGUMENT};
    for (int k = 0; k < 2; ++k) {
        weft_mesh_collider_def m = weft_default_mesh_collider_def();
        m.mesh.positions = g_box;
        m.mesh.n_vertices = 8;
        m.mesh.indices = g_box_tris;
        m.mesh.n_faces = 12;
        m.push_speed = bad[k];
        weft_cloth_def def = weft_default_cloth_def();
        def.mesh = ag_desc(&sheet);
        def.n_mesh_colliders = 1;
        def.mesh_colliders = &m;
        weft_cloth c = {0};
        CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), want[k]);
        const char* msg = weft_context_last_error(ctx);
        printf("  push_speed %g: %s\n", bad[k], msg);
        CHECK(strstr(msg, "push_speed") != NULL);
    }
    ag_free(&sheet);
    weft_context_destroy(ctx);
}

int main(void) {
    make_box();
    RUN_TEST(test_push_speed);
    RUN_TEST(test_bad_push_speed);
    return TEST_SUMMARY();
}
