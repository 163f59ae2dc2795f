/* A body from the host's arrays (weft_cloth_set_mesh_collider_vertices) or from a rigid transform
 * (weft_frame.mesh_collider_transforms) moved on the GPU (gpu/solver/wg_mesh_host.c: its frame's
 * end uploaded once a frame, the body's passes and its sharp-feature pairs on the GPU; the
 * default, WEFT_GPU_BODY=device) against the same body moved by core on the host
 * (WEFT_GPU_BODY=host), through the public API: one headless GPU context per setting (the switch
 * is read when the device is made). A 12 x 12 sheet dropped 0.2 m on a body:
 *  - arrays: a box 0.6 m wide (sharp: penalty pairs at its edges) stands 9 frames, then rises 1 cm
 *    a frame, 20 frames (its 8 vertices given every frame);
 *  - transform: an icosphere of radius 0.3 m stands 9 frames, then turns about the vertical at
 *    90 deg/s, 30 frames, friction carrying the sheet (the frame's rigid transform, no array call).
 * Checked: the debug log says the body moved on the GPU in the device context and on the host in
 * the other; the two cloths lie within STILL_BOUND of each other while the body stands and, once
 * it moves, within RISE_BOUND (the box: the GPU's sharp pairs decide in float) or ULP_FACTOR
 * times as far as a host cloth whose body is one float ulp off (the ball); the same pairs within
 * 2 % and the same rollbacks. A third cloth of the device context, given a bad input before each
 * good one from frame 5 (a NaN vertex: NONFINITE; a NaN transform: the step refused) and frames
 * that fail (STEP_FAILED, the cloth and its body restored) before those frames' good steps (a
 * gale at frames 1 and 14, the object thrown at 17 and at 7, where the failed frame's body is
 * frame 15's, moved though the body stands in the good frame that follows), stays bit-identical
 * to the device's cloth. A device cloth saved while the body moves, restored and replayed, gives
 * the same snapshot bytes. With fragment passes (WEFT_GPU_PASSES=fragment) both settings take the
 * host's path: bit-identical. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"
#include "test_meshes.h"

#define N 12
#define DT (1.0 / 30.0)
#define STAND 10                  /* the body stands for frames 1 .. STAND - 1 */
#define BAD_FROM 5                /* the third cloth's bad inputs, from this frame on */
#define MOVED_FAIL_AT 7           /* ... and its failed frames (also at frame 1) */
#define FAIL_AT 14
#define THROWN_AT 17
/* the largest distance device - host, measured on llvmpipe: 7.9e-6 m while the box stands (the
   ball: 3.5e-5 m); the box rising 3.0 mm (the one-ulp cloth 1.6 mm; the GPU's sharp pairs decide
   in float, as for the body from a host buffer: docs/design/gpu_bodies.md); the ball turning
   12.5 mm over 30 frames, the one-ulp cloth 10.1 mm */
#define STILL_BOUND 1e-4
#define RISE_BOUND 1e-2
#define ULP_FACTOR 2.0

static const double LO[3] = {-0.3, 0.0, -0.3}, HI[3] = {0.3, 0.3, 0.3};
static tmesh g_box, g_ball;
static float g_rest[24], g_ball_rest[3 * 200];
static ag_mesh g_sheet;

/* the last "GPU mesh colliders: R of M moved on the GPU" debug line's R (-1: none seen) */
static void body_log(weft_log_level level, const char* message, void* user) {
    int r = 0, m = 0;
    if (level == WEFT_LOG_DEBUG && sscanf(message, "GPU mesh colliders: %d of %d moved on the GPU", &r, &m) == 2)
        *(int*)user = r;
}

static weft_context* make_ctx(const char* body, int* resident) {
    setenv("WEFT_GPU_BODY", body, 1);
    weft_context_def cd = ap_context_def(WEFT_BACKEND_GPU);
    cd.log = body_log;
    cd.log_user = resident;
    cd.log_level = WEFT_LOG_DEBUG;
    weft_context* ctx = ap_create(&cd, WEFT_OK, NULL);
    unsetenv("WEFT_GPU_BODY");
    return ctx;
}

/* The box's vertices at frame f (arrays): standing, then rising. */
static void box_at(int f, float* out) {
    const double dy = 0.01 * (f < STAND ? 0 : f - STAND + 1);
    for (int i = 0; i < 24; ++i) out[i] = g_rest[i] + (float)(i % 3 == 1 ? dy : 0.0);
}

/* The ball's transform at frame f (transform): turning about y from frame 10 at 90 deg/s. */
static void turn_at(int f, float* M) {
    const double a = f < 10 ? 0.0 : (f - 9) * DT * 1.5707963267948966;
    ag_transform(M, 0.0, 1.0, 0.0, a, 0.0, 0.0, 0.0);
}

typedef struct feed {
    int transform;              /* 1: the rigid transform, 0: the arrays */
    int nudge;                  /* 1: the body one float ulp off (arrays: every coordinate up; the
                                   transform: shifted 3e-8 m along x, an ulp of 0.3 m) */
    float M[16];
} feed;

/* Frame f's inputs: the arrays (bad first when bad), or the frame's transform into fd->M. */
static weft_status give(weft_context* ctx, weft_cloth c, int f, feed* fd, int bad) {
    if (fd->transform) {
        turn_at(f, fd->M);
        if (fd->nudge) fd->M[12] += 3e-8f;
        return WEFT_OK;
    }
    float body[24];
    box_at(f, body);
    for (int i = 0; fd->nudge && i < 24; ++i) body[i] = nextafterf(body[i], INFINITY);
    if (bad) {
        float wrong[24];
        memcpy(wrong, body, sizeof wrong);
        wrong[3 * 5 + 1] = NAN;
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, wrong, 8), WEFT_ERROR_NONFINITE);
    }
    return weft_cloth_set_mesh_collider_vertices(ctx, c, 0, body, 8);
}

/* A frame that fails (the body given): a gale of 1e150 m/s (non-finite forces in every retry of
   the first substep, after the body's passes ran), or the object thrown 1e31 m away (the whole
   frame runs, the body's frame ended on the GPU; then the outputs are beyond 1e30). */
static void fail(weft_context* ctx, weft_cloth c, const feed* fd, int thrown) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    const double gale[3] = {1e150, 0.0, 1e150};
    float far[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e31f, 0, 0, 1};
    if (thrown) fr.object_transform = far;
    else fr.wind = gale;
    fr.mesh_collider_transforms = fd->transform ? fd->M : NULL;
    CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_ERROR_STEP_FAILED);
}

static weft_status step(weft_context* ctx, weft_cloth c, feed* fd, int bad, weft_frame_stats* fs) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    if (fd->transform && bad) {
        float wrong[16];
        memcpy(wrong, fd->M, sizeof wrong);
        wrong[12] = NAN;
        fr.mesh_collider_transforms = wrong;
        CHECK(weft_cloth_step(ctx, c, &fr, fs) != WEFT_OK);
    }
    fr.mesh_collider_transforms = fd->transform ? fd->M : NULL;
    return weft_cloth_step(ctx, c, &fr, fs);
}

static weft_status replay_feed(weft_context* ctx, weft_cloth c, int f, void* user) {
    return give(ctx, c, f + 1, user, 0);
}

static weft_status replay_frame(weft_context* ctx, weft_cloth c, int f, weft_frame_stats* fs, void* user) {
    (void)f;
    return step(ctx, c, user, 0, fs);
}

static void run_body(int transform) {
    int res_host = -1, res_dev = -1;
    weft_context* ctx[2] = {make_ctx("host", &res_host), make_ctx("device", &res_dev)};
    if (!ctx[0] || !ctx[1]) return;
    const int ball = transform;
    weft_mesh_collider_def m = weft_default_mesh_collider_def();
    m.mesh.positions = ball ? g_ball_rest : g_rest;
    m.mesh.n_vertices = ball ? g_ball.nv : 8;
    m.mesh.indices = ball ? g_ball.t : g_box.t;
    m.mesh.n_faces = ball ? g_ball.nt : g_box.nt;
    m.friction = 0.5;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&g_sheet);
    def.n_mesh_colliders = 1;
    def.mesh_colliders = &m;
    def.solver = WEFT_SOLVER_PCG;
    def.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    def.newton_iterations = 1;
    def.line_search = 0;
    def.self_collision = 0;
    /* c[0] the host's body, c[1] the device's, c[2] the device's given bad inputs too, c[3] the
       host's body one ulp off */
    weft_cloth c[4];
    CHECK_EQ_INT(weft_cloth_create(ctx[0], &def, &c[0]), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_create(ctx[1], &def, &c[1]), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_create(ctx[1], &def, &c[2]), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_create(ctx[0], &def, &c[3]), WEFT_OK);
    weft_context* of[4] = {ctx[0], ctx[1], ctx[1], ctx[0]};
    int pairs[4] = {0}, active[4] = {0}, rollbacks[4] = {0}, intact = 1, count = 0, host_seen = -1, dev_seen = -1;
    float pos[4][3 * N * N];
    double far = 0.0, ulp_far = 0.0;
    int far_at = 0;
    const int frames = transform ? 30 : 20, saved_at = transform ? 15 : 12, replay_to = 20 + 5 * transform;
    double still_far = 0.0;
    for (int f = 1; f <= frames; ++f) {
        for (int k = 0; k < 4; ++k) {
            feed fd = {transform, k == 3, {0}};
            const int bad = k == 2 && f >= BAD_FROM;
            CHECK_EQ_INT(give(of[k], c[k], f, &fd, bad), WEFT_OK);
            if (k == 2 && (f == 1 || f == MOVED_FAIL_AT || f == FAIL_AT || f == THROWN_AT)) {
                feed other = fd;   /* MOVED_FAIL_AT: the failed frame's body is frame 15's */
                if (f == MOVED_FAIL_AT) CHECK_EQ_INT(give(of[k], c[k], 15, &other, 0), WEFT_OK);
                fail(of[k], c[k], &other, f == THROWN_AT || f == MOVED_FAIL_AT);
                if (f == MOVED_FAIL_AT) CHECK_EQ_INT(give(of[k], c[k], f, &fd, 0), WEFT_OK);
            }
            weft_frame_stats fs;
            CHECK_EQ_INT(step(of[k], c[k], &fd, bad, &fs), WEFT_OK);
            pairs[k] += fs.mesh_pairs;
            active[k] += fs.mesh_pairs_active;
            rollbacks[k] += fs.rollbacks;
            CHECK_EQ_INT(weft_cloth_get_vertices(of[k], c[k], WEFT_SPACE_WORLD, pos[k], NULL, N * N, &count), WEFT_OK);
        }
        if (f == 1) host_seen = res_host, dev_seen = res_dev;
        intact &= memcmp(pos[1], pos[2], sizeof pos[1]) == 0;
        const double d = ag_max_distance(pos[0], pos[1], N * N);
        if (d > far) far = d, far_at = f;
        if (f < STAND) still_far = far;
        ulp_far = fmax(ulp_far, ag_max_distance(pos[0], pos[3], N * N));
        if (getenv("BODY_HOST_VERBOSE"))
            printf("    frame %d: %.3g m (one ulp: %.3g m)\n", f, d, ag_max_distance(pos[0], pos[3], N * N));
    }
    double top = -HUGE_VAL;
    for (int i = 0; i < N * N; ++i) top = fmax(top, pos[1][3 * i + 1]);
    const char* passes = getenv("WEFT_GPU_PASSES");
    const int fragment = passes && strcmp(passes, "fragment") == 0;
    printf("  %s, %d frames: the body moved on the GPU in %d / %d of the contexts' cloths (host / device "
           "setting); device - host %.3g m at most (frame %d; %.3g while the body stands), the one-ulp cloth %.3g m; "
           "pairs found (active) host %d (%d), device %d (%d); rollbacks %d, %d; the bad inputs' cloth %s; the "
           "device's sheet's highest at %.3f m\n",
           transform ? "a ball turning (rigid transform)" : "a box rising (arrays)", frames, host_seen, dev_seen,
           far, far_at, still_far, ulp_far, pairs[0], active[0], pairs[1], active[1], rollbacks[0], rollbacks[1],
           intact ? "bit-identical" : "DIFFERENT", top);
    CHECK_EQ_INT(host_seen, 0);
    CHECK_EQ_INT(dev_seen, fragment ? 0 : 1);
    CHECK(still_far < STILL_BOUND);
    if (transform) CHECK(far <= ULP_FACTOR * ulp_far + STILL_BOUND);
    else CHECK(far < RISE_BOUND);
    if (fragment) CHECK(far == 0.0);
    if (!transform) CHECK(active[0] > 0 && active[1] > 0);
    CHECK(fabs((double)pairs[1] - pairs[0]) <= 0.02 * pairs[0]);
    CHECK_EQ_INT(rollbacks[1], rollbacks[0]);
    CHECK(intact);
    CHECK_EQ_INT(rollbacks[2], rollbacks[1]);
    /* on the risen box (its top at 0.41 m) */
    if (!transform) CHECK(top > 0.41 && top < 0.41 + 0.02);
    /* the device's cloth restored to frame SAVED_AT (the body moving) and replayed */
    feed fd = {transform, 0, {0}};
    weft_cloth r;
    CHECK_EQ_INT(weft_cloth_create(ctx[1], &def, &r), WEFT_OK);
    ag_replay rp = ag_snapshot_replay(ctx[1], r, saved_at, replay_to, replay_feed, replay_frame, &fd);
    printf("  the device's cloth saved at frame %d, restored, replayed to %d: %s\n", saved_at, replay_to,
           rp.ok && rp.restored_same && rp.same ? "the same bytes" : "DIFFERENT");
    CHECK(rp.ok && rp.restored_same && rp.same);
    weft_context_destroy(ctx[0]);
    weft_context_destroy(ctx[1]);
}

static void test_arrays(void) { run_body(0); }
static void test_transform(void) { run_body(1); }

int main(void) {
    box(&g_box, LO, HI);
    for (int i = 0; i < 24; ++i) g_rest[i] = (float)g_box.x[i];
    const double centre[3] = {0.0, 0.0, 0.0};
    icosphere(&g_ball, 2, 0.3, centre);
    for (int i = 0; i < 3 * g_ball.nv; ++i) g_ball_rest[i] = (float)g_ball.x[i];
    ag_grid(&g_sheet, N, 1.0, 0.5, 0, 0);
    RUN_TEST(test_arrays);
    RUN_TEST(test_transform);
    ag_free(&g_sheet);
    return TEST_SUMMARY();
}
