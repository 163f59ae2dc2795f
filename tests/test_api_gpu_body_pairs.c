/* A box's sharp-feature penalty pairs (core/mesh_pairs.h) when the box is kept on the GPU
 * (weft_cloth_set_mesh_collider_gl_buffer with compute passes: the pairs found on the GPU,
 * gpu/solver/wg_mesh_sharp.h) against the same box given as host arrays (core's detection on the
 * host), through the public API in a host context this test makes current (headless EGL on
 * whatever device there is: llvmpipe without a GPU). Two GPU cloths of one WEFT_GL_HOST_CURRENT
 * context, a 12 x 12 sheet dropped 0.2 m on a box 0.6 m wide whose corners it hangs over; the box
 * stands for 30 frames, then rises 0.2 m over 20 frames (its vertices given every frame, to one
 * cloth as arrays, to the other interleaved in a GL buffer), 60 frames. The two cloths get the
 * same pairs (found and active, summed over the frames, within 2 %), the same rollbacks, and lie
 * within STILL_BOUND of each other while the box stands, TWO_BOUND on the rise (their bodies differ
 * by float rounding: the GPU moves its body in float); both have pairs. The buffer's cloth saved at frame 25 and restored replays
 * frames 26-45 (the box rising) bit for bit. With fragment passes (WEFT_GPU_PASSES=fragment, GL 3.3)
 * the buffer is read back and both take core's path: the same bits at every frame; so too with the
 * arrays' body on the GPU (WEFT_GPU_BODY=device, test_api_gpu_body_pairs_device; by default the
 * arrays' body takes the host's path here).
 * Two bodies: the same with a second box beside the first, still and given as host arrays to both
 * cloths (collider 0, its pairs found on the host), the rising box collider 1 (found on the GPU for
 * the buffer's cloth, appended after the host body's): the same pairs, rollbacks and replay,
 * STILL_BOUND apart while the boxes stand (measured 4.8e-5 m) and TWO_BOUND once the box rises
 * (the sheet slides off the boxes' inner edges into the gap; measured 2.4 mm). */
#define _POSIX_C_SOURCE 200809L /* setenv (host_gl_passes.h) */
#include <GL/glew.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_grid.h"
#include "check.h"
#include "egl_context.h"
#include "host_context.h"
#include "host_gl_passes.h"
#include "test_meshes.h"

#define N 12
#define DT (1.0 / 30.0)
#define FRAMES 60
#define OFFSET 48                 /* bytes before the first vertex in the buffer */
#define STRIDE 24                 /* bytes per interleaved vertex: xyz, then a normal */
/* measured on llvmpipe: pairs found 1,604 (arrays) and 1,606 (buffer), active 1,592 and 1,592,
   2 rollbacks each; without the GPU's pairs the buffer's cloth had none, 4 rollbacks and lay
   6.1 cm from the arrays' */
/* while the box stands (one box and two bodies): measured 1.3e-5 and 4.8e-5 m; 3.2e-4 m before
   the contacts' closest-point ties took float's rounding (contact_query.glsl: a cloth point over a
   box corner judged behind the body, its pair dropped) */
#define STILL_BOUND 1e-4
#define SAVED_AT 25               /* the buffer's cloth saved after this frame, replayed to REPLAY_TO */
#define REPLAY_TO 45
#define PAIRS_NEAR 0.02
#define TWO_BOUND 1e-2            /* two bodies, the box rising: the sheet slides into the gap */

static const double LO[3] = {-0.3, 0.0, -0.3}, HI[3] = {0.3, 0.3, 0.3};
/* two bodies: a still box (LO_A, HI_A) and the rising one (LO_B, HI_B), 0.1 m apart */
static const double LO_A[3] = {-0.55, 0.0, -0.3}, HI_A[3] = {-0.05, 0.3, 0.3};
static const double LO_B[3] = {0.05, 0.0, -0.3}, HI_B[3] = {0.55, 0.3, 0.3};

/* The box at frame f: standing until frame 29, then rising 1 cm a frame to 0.2 m at frame 49. */
static void set_body(const float* rest, int f, float* body) {
    const double dy = 0.01 * (f < 30 ? 0 : f < 50 ? f - 29 : 20);
    for (int i = 0; i < 24; ++i) body[i] = rest[i] + (i % 3 == 1 ? (float)dy : 0.0f);
}

typedef struct totals {
    int pairs, active, rollbacks;
} totals;

/* One box (two = 0) or a still box beside the rising one (two = 1). */
static void run_boxes(int two) {
    wg_gl_context* host = hc_host_begin();
    if (!host) return;
    weft_context* ctx = hc_context(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT);
    tmesh bx, still;
    box(&bx, two ? LO_B : LO, two ? HI_B : HI);
    box(&still, LO_A, HI_A);
    float body[24], rest[24], rest_still[24];
    for (int i = 0; i < 24; ++i) rest[i] = (float)bx.x[i], rest_still[i] = (float)still.x[i];
    ag_mesh sheet;
    ag_grid(&sheet, N, 1.0, 0.5, 0, 0);
    weft_mesh_collider_def m[2] = {weft_default_mesh_collider_def(), weft_default_mesh_collider_def()};
    const int mb = two;   /* the rising box's collider */
    m[mb].mesh.positions = rest;
    m[mb].mesh.n_vertices = 8;
    m[mb].mesh.indices = bx.t;
    m[mb].mesh.n_faces = bx.nt;
    m[mb].friction = 0.5;
    m[0].mesh.positions = two ? rest_still : rest;   /* the still box (two) */
    if (two) {
        m[0].mesh.n_vertices = 8;
        m[0].mesh.indices = still.t;
        m[0].mesh.n_faces = still.nt;
        m[0].friction = 0.5;
    }
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&sheet);
    def.n_mesh_colliders = 1 + two;
    def.mesh_colliders = m;
    def.solver = WEFT_SOLVER_PCG;
    def.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    def.newton_iterations = 1;
    def.line_search = 0;
    def.self_collision = 0;
    weft_cloth c[2];
    for (int k = 0; ctx && k < 2; ++k) CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c[k]), WEFT_OK);
    GLuint buf = 0;
    glGenBuffers(1, &buf);
    const int on_gpu = hg_body_on_gpu(), both = hg_arrays_on_gpu();
    totals t[2] = {{0, 0, 0}, {0, 0, 0}};
    float pos[2][3 * N * N];
    double far = 0.0, still_far = 0.0;   /* farthest apart, over all frames and while the box stands */
    int same = 1, count = 0;
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    weft_cloth_info info = {0};
    if (ctx) CHECK_EQ_INT(weft_cloth_get_info(ctx, c[1], &info), WEFT_OK);
    unsigned char* saved = malloc(info.snapshot_size + 1);
    float* replay = malloc((size_t)(REPLAY_TO - SAVED_AT) * sizeof pos[1]);
    for (int f = 1; ctx && f <= FRAMES; ++f) {
        set_body(rest, f, body);
        hg_fill_buffer(buf, body, 8, OFFSET, STRIDE);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c[0], mb, body, 8), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c[1], mb, buf, OFFSET, STRIDE, 8), WEFT_OK);
        for (int k = 0; k < 2; ++k) {
            weft_frame_stats fs;
            CHECK_EQ_INT(weft_cloth_step(ctx, c[k], &fr, &fs), WEFT_OK);
            t[k].pairs += fs.mesh_pairs;
            t[k].active += fs.mesh_pairs_active;
            t[k].rollbacks += fs.rollbacks;
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c[k], WEFT_SPACE_WORLD, pos[k], NULL, N * N, &count), WEFT_OK);
        }
        same &= memcmp(pos[0], pos[1], sizeof pos[0]) == 0;
        far = fmax(far, ag_max_distance(pos[0], pos[1], N * N));
        if (f < 30) still_far = far;
        if (f == SAVED_AT) CHECK_EQ_INT(weft_cloth_save(ctx, c[1], saved, info.snapshot_size), WEFT_OK);
        if (f > SAVED_AT && f <= REPLAY_TO) memcpy(replay + (size_t)(f - SAVED_AT - 1) * 3 * N * N, pos[1], sizeof pos[1]);
    }
    double top = -HUGE_VAL, low = HUGE_VAL;
    for (int i = 0; i < N * N; ++i) {
        top = fmax(top, pos[1][3 * i + 1]);
        low = fmin(low, pos[1][3 * i + 1]);
    }
    /* the buffer's cloth restored to frame SAVED_AT (the box rising, the pairs found again on
       the GPU in each substep) and replayed: the same bits */
    int replayed = ctx != NULL;
    if (ctx) CHECK_EQ_INT(weft_cloth_restore(ctx, c[1], saved, info.snapshot_size), WEFT_OK);
    for (int f = SAVED_AT + 1; ctx && f <= REPLAY_TO; ++f) {
        set_body(rest, f, body);
        hg_fill_buffer(buf, body, 8, OFFSET, STRIDE);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c[1], mb, buf, OFFSET, STRIDE, 8), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, c[1], &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c[1], WEFT_SPACE_WORLD, pos[1], NULL, N * N, &count), WEFT_OK);
        replayed &= memcmp(pos[1], replay + (size_t)(f - SAVED_AT - 1) * 3 * N * N, sizeof pos[1]) == 0;
    }
    printf("  the buffer's cloth restored at frame %d and replayed to %d: %s\n", SAVED_AT, REPLAY_TO,
           replayed ? "bit-identical" : "DIFFERENT");
    CHECK(replayed);
    free(saved);
    free(replay);
    printf("  %s, %d frames, the body %s: pairs found (active) arrays %d (%d), buffer %d (%d); rollbacks %d, %d; "
           "farthest apart %.3g m (%.3g while the box stands; bit-identical: %s); the buffer's sheet from %.3f to %.3f m\n",
           two ? "a still box (host arrays) beside the rising one" : "one box", FRAMES, on_gpu ? "on the GPU" : "read back", t[0].pairs, t[0].active, t[1].pairs, t[1].active,
           t[0].rollbacks, t[1].rollbacks, far, still_far, same ? "yes" : "no", low, top);
    CHECK(t[0].active > 0 && t[1].active > 0);
    CHECK(fabs((double)t[1].pairs - t[0].pairs) <= PAIRS_NEAR * t[0].pairs);
    CHECK(fabs((double)t[1].active - t[0].active) <= PAIRS_NEAR * t[0].active);
    CHECK_EQ_INT(t[1].rollbacks, t[0].rollbacks);
    CHECK(still_far < STILL_BOUND);
    /* one box, rising: measured 4.7 mm at frame 32 (0.17 mm at the end): the GPU keeps a pair core
       drops at a cloth point 0.5 um from the box's vertical edge under a corner (in front of the
       body or behind it is not decided in float) */
    CHECK(far < TWO_BOUND);
    CHECK(top > 0.5 - 0.01);                       /* on the risen box (its top at 0.5 m) */
    if (!two) CHECK(top < 0.5 + 0.02);             /* (two: the sheet folds above the gap) */
    if (!on_gpu || both) CHECK(same);
    glDeleteBuffers(1, &buf);
    if (ctx) weft_context_destroy(ctx);
    ag_free(&sheet);
    wg_gl_end(host);
    wg_gl_context_destroy(host);
}

static void test_box_pairs(void) { run_boxes(0); }
static void test_two_bodies(void) { run_boxes(1); }

int main(void) {
    hg_body_setting();
    RUN_TEST(test_box_pairs);
    RUN_TEST(test_two_bodies);
    return TEST_SUMMARY();
}
