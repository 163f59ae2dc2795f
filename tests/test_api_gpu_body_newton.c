/* A box kept on the GPU (weft_cloth_set_mesh_collider_gl_buffer with compute passes: its
 * sharp-feature pairs found on the GPU, gpu/solver/wg_mesh_sharp.h) under the methods that take
 * the penalty pairs past the first system: Newton 2 with the line search (the pairs' exact terms
 * at each iterate, wc_penalty_pairs_newton, and their energy change in the search,
 * wc_penalty_pairs_energy, at x(w) = xb + he (v + w)), BDF2 and TR-BDF2 with it (xb read back;
 * TR-BDF2: each stage finds its pairs, the second on the body at the stage's end), and TR-BDF2 at
 * Newton 1 (the recheck passes on both stages' pairs). Through the public API, in a host context
 * this test makes current (headless EGL: llvmpipe without a GPU). Per method three cloths: two
 * GPU cloths of one WEFT_GL_HOST_CURRENT context, the box given to one as host arrays (core's
 * detection on the host) and to the other interleaved in a GL buffer (kept on the GPU), and a
 * CPU cloth given the arrays. A 12 x 12 sheet, turned 0.6 rad about y and shifted (no cloth edge
 * along a rim), dropped 0.2 m on a frictionless box 0.6 m wide whose corners it hangs over; the
 * box stands 12 frames, then slides 5 mm a frame along x for 10 (its vertices given every
 * frame), 24 frames. The buffer's cloth against the arrays': the same pairs (found and active,
 * summed over the frames, within PAIRS_NEAR), the same rollbacks, within DIST_BOUND at every
 * frame; the arrays' against the CPU's: the pairs within CPU_PAIRS, the same rollbacks (their
 * positions part by up to 7 cm on BDF2, float against double on a sheet sliding off a moving
 * box: printed, not bounded); none of the three deeper than DEPTH_BOUND in the box; the
 * buffer's cloth saved at frame SAVED_AT, restored and replayed through the slide bit for bit.
 * With fragment passes (GL 3.3) the buffer is read back: the two GPU cloths are bit-identical.
 * Measured on llvmpipe: buffer - arrays 3.7e-5 / 1.7e-4 / 2.9e-4 / 9.2e-5 m (Newton 2, BDF2,
 * TR-BDF2 at Newton 2, at Newton 1), the pairs found within 1 of each other on all four. Before
 * the contacts' closest-point ties took float's rounding of the coordinates (contact_query.glsl),
 * the GPU's find judged a cloth point 5 mm over a box corner behind the body and dropped the pair
 * core keeps there at first contact: 2.7 cm apart on BDF2, 6.4 mm on TR-BDF2 at Newton 1. */
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
#define FRAMES 24
#define SLIDE_FROM 13              /* the box slides STEP a frame from this frame ... */
#define SLIDE_TO 22                /* ... to this one (5 cm) */
#define STEP 0.005                /* m a frame the box slides along x */
#define ANGLE 0.6                 /* rad: the sheet turned about y ... */
#define SHIFT_X 0.02              /* ... and shifted (m) */
#define SHIFT_Z 0.01
#define OFFSET 48                 /* bytes before the first vertex in the buffer */
#define STRIDE 24                 /* bytes per interleaved vertex: xyz, then a normal */
#define SAVED_AT 14               /* the buffer's cloth saved after this frame, replayed to REPLAY_TO */
#define REPLAY_TO 22
#define PAIRS_NEAR 0.01           /* the pairs found and active: buffer against arrays, relative */
#define DIST_BOUND 1e-3           /* m: buffer against arrays, every frame */
#define CPU_PAIRS 0.03            /* the pairs found: the arrays' GPU cloth against the CPU's, relative */
#define DEPTH_BOUND 1e-3          /* m: deepest vertex inside the box */

static const double LO[3] = {-0.3, 0.0, -0.3}, HI[3] = {0.3, 0.3, 0.3};

typedef struct method {
    const char* name;
    weft_integrator integrator;
    int newton, search;
} method;

/* The box's slide along x at frame f (m). */
static double slide(int f) { return STEP * (f < SLIDE_FROM ? 0 : f <= SLIDE_TO ? f - SLIDE_FROM + 1 : SLIDE_TO - SLIDE_FROM + 1); }

static void set_body(const float* rest, int f, float* body) {
    for (int i = 0; i < 24; ++i) body[i] = rest[i] + (i % 3 == 0 ? (float)slide(f) : 0.0f);
}

/* Deepest vertex inside the box slid by dx (m; 0 when none). */
static double box_depth(const float* pos, int n, double dx) {
    double worst = 0.0;
    for (int i = 0; i < n; ++i) {
        double depth = INFINITY;
        for (int k = 0; k < 3; ++k) {
            double lo = LO[k] + (k == 0 ? dx : 0.0), hi = HI[k] + (k == 0 ? dx : 0.0);
            depth = fmin(depth, fmin(pos[3 * i + k] - lo, hi - pos[3 * i + k]));
        }
        worst = fmax(worst, depth);
    }
    return worst;
}

typedef struct totals {
    int pairs, active, rollbacks, newton_steps, backtracks, bdf2;
    double depth;
} totals;

static void run_method(const method* me) {
    wg_gl_context* host = hc_host_begin();
    if (!host) return;
    weft_context* ctx = hc_context(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT);
    weft_context* cpu = hc_context(WEFT_BACKEND_CPU, weft_default_context_def().gl_mode);
    tmesh bx;
    box(&bx, LO, HI);
    float body[24], rest[24];
    for (int i = 0; i < 24; ++i) rest[i] = (float)bx.x[i];
    ag_mesh sheet;
    ag_grid(&sheet, N, 1.0, 0.5, 0, 0);
    /* turned about y and shifted: no cloth edge parallel to a rim (a cloth edge along a rim has
       no well-defined closest points: float and double part there) */
    const double ca = cos(ANGLE), sa = sin(ANGLE);
    for (int i = 0; i < N * N; ++i) {
        double x0 = sheet.pos[3 * i], z0 = sheet.pos[3 * i + 2];
        sheet.pos[3 * i] = (float)(ca * x0 - sa * z0 + SHIFT_X);
        sheet.pos[3 * i + 2] = (float)(sa * x0 + ca * z0 + SHIFT_Z);
    }
    weft_mesh_collider_def m = weft_default_mesh_collider_def();
    m.mesh.positions = rest;
    m.mesh.n_vertices = 8;
    m.mesh.indices = bx.t;
    m.mesh.n_faces = bx.nt;
    m.friction = 0.0;   /* (with friction the sheet's stick and slip part the runs by centimetres) */
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&sheet);
    def.n_mesh_colliders = 1;
    def.mesh_colliders = &m;
    def.solver = WEFT_SOLVER_PCG;
    def.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    def.integrator = me->integrator;
    def.newton_iterations = me->newton;
    def.line_search = me->search;
    def.self_collision = 0;
    weft_cloth c[3];   /* GPU arrays, GPU buffer, CPU arrays */
    int ok = ctx && cpu;
    for (int k = 0; ok && k < 3; ++k) CHECK_EQ_INT(weft_cloth_create(k < 2 ? ctx : cpu, &def, &c[k]), WEFT_OK);
    GLuint buf = 0;
    glGenBuffers(1, &buf);
    const int on_gpu = hg_body_on_gpu(), both = hg_arrays_on_gpu();
    totals t[3];
    memset(t, 0, sizeof t);
    float pos[3][3 * N * N];
    double far = 0.0, far_cpu[2] = {0.0, 0.0};
    int same = 1, count = 0;
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    weft_cloth_info info = {0};
    if (ok) CHECK_EQ_INT(weft_cloth_get_info(ctx, c[1], &info), WEFT_OK);
    unsigned char* saved = malloc(info.snapshot_size + 1);
    float* replay = malloc((size_t)(REPLAY_TO - SAVED_AT) * sizeof pos[1]);
    for (int f = 1; ok && f <= FRAMES; ++f) {
        set_body(rest, f, body);
        hg_fill_buffer(buf, body, 8, OFFSET, STRIDE);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c[0], 0, body, 8), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c[1], 0, buf, OFFSET, STRIDE, 8), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(cpu, c[2], 0, body, 8), WEFT_OK);
        for (int k = 0; k < 3; ++k) {
            weft_context* x = k < 2 ? ctx : cpu;
            weft_frame_stats fs;
            CHECK_EQ_INT(weft_cloth_step(x, c[k], &fr, &fs), WEFT_OK);
            t[k].pairs += fs.mesh_pairs;
            t[k].active += fs.mesh_pairs_active;
            t[k].rollbacks += fs.rollbacks;
            t[k].newton_steps += fs.newton_steps;
            t[k].backtracks += fs.line_search_backtracks;
            t[k].bdf2 += fs.bdf2_substeps;
            CHECK_EQ_INT(weft_cloth_get_vertices(x, c[k], WEFT_SPACE_WORLD, pos[k], NULL, N * N, &count), WEFT_OK);
            t[k].depth = fmax(t[k].depth, box_depth(pos[k], N * N, slide(f)));
        }
        same &= memcmp(pos[0], pos[1], sizeof pos[0]) == 0;
        far = fmax(far, ag_max_distance(pos[0], pos[1], N * N));
        for (int k = 0; k < 2; ++k) far_cpu[k] = fmax(far_cpu[k], ag_max_distance(pos[k], pos[2], N * N));
        if (f == SAVED_AT) CHECK_EQ_INT(weft_cloth_save(ctx, c[1], saved, info.snapshot_size), WEFT_OK);
        if (f > SAVED_AT && f <= REPLAY_TO) memcpy(replay + (size_t)(f - SAVED_AT - 1) * 3 * N * N, pos[1], sizeof pos[1]);
    }
    double top = -HUGE_VAL;
    for (int i = 0; i < N * N; ++i) top = fmax(top, pos[1][3 * i + 1]);
    /* the buffer's cloth restored to frame SAVED_AT and replayed through the slide: the same bits */
    int replayed = ok;
    if (ok) CHECK_EQ_INT(weft_cloth_restore(ctx, c[1], saved, info.snapshot_size), WEFT_OK);
    for (int f = SAVED_AT + 1; ok && f <= REPLAY_TO; ++f) {
        set_body(rest, f, body);
        hg_fill_buffer(buf, body, 8, OFFSET, STRIDE);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c[1], 0, buf, OFFSET, STRIDE, 8), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, c[1], &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c[1], WEFT_SPACE_WORLD, pos[1], NULL, N * N, &count), WEFT_OK);
        replayed &= memcmp(pos[1], replay + (size_t)(f - SAVED_AT - 1) * 3 * N * N, sizeof pos[1]) == 0;
    }
    free(saved);
    free(replay);
    printf("  %s, the body %s: pairs found (active) arrays %d (%d), buffer %d (%d), CPU %d (%d); rollbacks %d, %d, %d; "
           "Newton steps %d, %d, %d; backtracks %d, %d, %d; BDF2 substeps %d, %d, %d\n",
           me->name, on_gpu ? "on the GPU" : "read back", t[0].pairs, t[0].active, t[1].pairs, t[1].active, t[2].pairs,
           t[2].active, t[0].rollbacks, t[1].rollbacks, t[2].rollbacks, t[0].newton_steps, t[1].newton_steps,
           t[2].newton_steps, t[0].backtracks, t[1].backtracks, t[2].backtracks, t[0].bdf2, t[1].bdf2, t[2].bdf2);
    printf("    buffer - arrays %.3g m (bit-identical: %s), arrays - CPU %.3g m, buffer - CPU %.3g m; deepest in the box "
           "%.3g, %.3g, %.3g m; the buffer's sheet top %.3f m; replay from frame %d to %d: %s\n",
           far, same ? "yes" : "no", far_cpu[0], far_cpu[1], t[0].depth, t[1].depth, t[2].depth, top, SAVED_AT,
           REPLAY_TO, replayed ? "bit-identical" : "DIFFERENT");
    CHECK(replayed);
    for (int k = 0; k < 3; ++k) {
        CHECK(t[k].active > 0);
        CHECK(t[k].depth < DEPTH_BOUND);
    }
    CHECK(fabs((double)t[1].pairs - t[0].pairs) <= PAIRS_NEAR * t[0].pairs);
    CHECK(fabs((double)t[1].active - t[0].active) <= PAIRS_NEAR * t[0].active);
    CHECK_EQ_INT(t[1].rollbacks, t[0].rollbacks);
    CHECK(far < DIST_BOUND);
    CHECK(fabs((double)t[2].pairs - t[0].pairs) <= CPU_PAIRS * t[2].pairs);
    CHECK_EQ_INT(t[0].rollbacks, t[2].rollbacks);
    CHECK(top > 0.3 - 0.01);   /* on the box */
    if (me->newton > 1 || me->search) CHECK(t[1].newton_steps > 0);
    if (!on_gpu || both) CHECK(same);
    glDeleteBuffers(1, &buf);
    if (ctx) weft_context_destroy(ctx);
    if (cpu) weft_context_destroy(cpu);
    ag_free(&sheet);
    wg_gl_end(host);
    wg_gl_context_destroy(host);
}

static const method METHODS[] = {
    {"backward Euler, Newton 2 + line search", WEFT_INTEGRATOR_BACKWARD_EULER, 2, 1},
    {"BDF2, Newton 2 + line search", WEFT_INTEGRATOR_BDF2, 2, 1},
    {"TR-BDF2, Newton 2 + line search", WEFT_INTEGRATOR_TRBDF2, 2, 1},
    {"TR-BDF2, Newton 1", WEFT_INTEGRATOR_TRBDF2, 1, 0},
};

static void test_newton2(void) { run_method(&METHODS[0]); }
static void test_bdf2(void) { run_method(&METHODS[1]); }
static void test_trbdf2(void) { run_method(&METHODS[2]); }
static void test_trbdf2_newton1(void) { run_method(&METHODS[3]); }

int main(void) {
    hg_body_setting();   /* the arrays' body on the host's path unless WEFT_GPU_BODY says otherwise */
    RUN_TEST(test_newton2);
    RUN_TEST(test_bdf2);
    RUN_TEST(test_trbdf2);
    RUN_TEST(test_trbdf2_newton1);
    return TEST_SUMMARY();
}
