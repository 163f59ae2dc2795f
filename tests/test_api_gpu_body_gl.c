/* A deforming body's vertices from a host GL buffer (weft_cloth_set_mesh_collider_gl_buffer)
 * through the public API, in a host context this test makes current (a headless EGL context on
 * whatever device there is: llvmpipe without a GPU). Two GPU cloths of one WEFT_GL_HOST_CURRENT
 * context, a 12 x 12 sheet dropped on an icosphere that breathes and rises 0.2 m: one gets the
 * body's vertices through weft_cloth_set_mesh_collider_vertices, the other the same floats
 * interleaved in a GL buffer (an offset, a 32-byte stride). With compute passes the buffer's body
 * stays on the GPU and is moved there in float, the arrays' on the CPU in double: their cloths
 * agree as closely as float's reach allows (BOUND: against a third cloth whose body is 1 ulp
 * off). With fragment passes (GL 3.3, or
 * WEFT_GPU_PASSES=fragment) the buffer is read back and both take core's path: positions bit
 * for bit every frame, snapshots byte for byte at the end. Either way a snapshot of the buffer's
 * cloth at frame 20, restored and replayed with the same calls, gives the same bits every frame
 * to frame 40; the sheet ends on the risen body (an independent check that the buffer's body
 * moved); the collision check, a teleporting frame and a rigidly moved one (which bring the
 * body back to the CPU) agree with the arrays' cloth. The host's buffer bindings are left alone.
 * The arrays' body takes the host's path here (WEFT_GPU_BODY=host) unless the environment says
 * otherwise; with WEFT_GPU_BODY=device (test_api_gpu_body_gl_device) both bodies move on the GPU
 * from the same floats: the same bits.
 * A sheet on a floor given the same floats every frame falls asleep through either call, and a
 * one-bit change of the buffer wakes it.
 * Every refusal (a null or destroyed handle, index, count, name, size, offset, stride, a mapped buffer, NaN, a
 * coordinate beyond 1e30, no current context, a CPU cloth, a headless context) has its status
 * and message, and leaves the state intact: the cloth's snapshot unchanged and its later frames
 * still equal to the reference's. */
#define _POSIX_C_SOURCE 200809L /* setenv (host_gl_passes.h) */
#include <GL/glew.h>
#include <math.h>
#include <stdint.h>
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
#define FRAMES 40
#define OFFSET 64                 /* bytes before the first vertex in the buffer */
#define STRIDE 32                 /* bytes per interleaved vertex: xyz, then 5 floats of other data */
#define SAVED_AT 20               /* the frame after which the buffer's cloth is saved and replayed */
/* The buffer's cloth against the arrays' when the body is moved on the GPU: the two bodies differ
 * by float rounding (the GPU interpolates the frame's floats in float, core in double), and the
 * sheet in contact with a moving body amplifies any such difference (a contact decided a step
 * apart, friction's stick or slip) for as long as the body moves. The yardstick is float's reach
 * itself: a third cloth fed by arrays whose every coordinate is one float ulp higher. The
 * buffer's cloth must stay within BOUND times that cloth's largest distance from the arrays'
 * (measured on llvmpipe: 3.64 mm against 3.68 mm, both at frame 29, the end of the rise), and
 * that distance within 2 cm (12.6 mm with fragment passes): a sheet that missed or passed through
 * the 0.3 m body would lie decimetres away. */
#define BOUND 1.5

static tmesh g_tm;
static float* g_rest;             /* (nv x 3) the icosphere, radius 0.3 m at the origin */
static ag_mesh g_sheet;

/* The body at frame f: breathing (radius +-5 %) and, from frame 10 to 29, rising 1 cm a frame. */
static void body_at(int f, float* out) {
    double s = 1.0 + 0.05 * sin(0.3 * f), rise = 0.01 * (f < 10 ? 0 : f < 30 ? f - 9 : 20);
    for (int i = 0; i < g_tm.nv; ++i)
        for (int k = 0; k < 3; ++k) out[3 * i + k] = (float)(s * g_rest[3 * i + k] + (k == 1 ? rise : 0.0));
}

/* A body's floats (nv vertices) interleaved at STRIDE after OFFSET bytes of other data, into buffer b. */
static void fill_buffer(GLuint b, const float* pos, int nv) {
    size_t bytes = OFFSET + (size_t)nv * STRIDE;
    unsigned char* img = malloc(bytes);
    for (size_t i = 0; i < bytes; ++i) img[i] = (unsigned char)(i * 37u);   /* not floats of the body */
    for (int i = 0; i < nv; ++i) memcpy(img + OFFSET + (size_t)i * STRIDE, pos + 3 * i, 12);
    glBindBuffer(GL_COPY_WRITE_BUFFER, b);
    glBufferSubData(GL_COPY_WRITE_BUFFER, 0, (GLsizeiptr)bytes, img);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    free(img);
}

static GLuint make_buffer(size_t bytes) {
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(GL_COPY_WRITE_BUFFER, b);
    glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)bytes, NULL, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    return b;
}

/* A cloth of the sheet with one mesh collider (nv vertices x, nt triangles t). */
static weft_cloth make_cloth_on(weft_context* ctx, const float* x, int nv, const int* t, int nt) {
    weft_mesh_collider_def m = weft_default_mesh_collider_def();
    m.mesh.positions = x;
    m.mesh.n_vertices = nv;
    m.mesh.indices = t;
    m.mesh.n_faces = nt;
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
    weft_cloth c = {0};
    weft_status st = weft_cloth_create(ctx, &def, &c);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) fprintf(stderr, "  create: %s\n", weft_context_last_error(ctx));
    return c;
}

static weft_cloth make_cloth(weft_context* ctx) { return make_cloth_on(ctx, g_rest, g_tm.nv, g_tm.t, g_tm.nt); }

static int has(weft_context* ctx, const char* text) {
    const char* e = weft_context_last_error(ctx);
    int ok = e && strstr(e, text) != NULL;
    if (!ok) fprintf(stderr, "  message \"%s\" lacks \"%s\"\n", e ? e : "(null)", text);
    return ok;
}

typedef struct bindings {
    GLint copy_read, copy_write, pack, unpack, array;
} bindings;

static void record(bindings* b) {
    glGetIntegerv(GL_COPY_READ_BUFFER_BINDING, &b->copy_read);
    glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &b->copy_write);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &b->pack);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &b->unpack);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &b->array);
}

/* Every refusal on cloth c of the host-current context, its snapshot unchanged by each. `buf`
 * holds the body (as fill_buffer wrote it); `host` is the current host context. */
static void refusals(weft_context* ctx, weft_cloth c, GLuint buf, wg_gl_context* host) {
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    size_t sz = info.snapshot_size;
    unsigned char* ref = malloc(sz);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, ref, sz), WEFT_OK);
    const int nv = g_tm.nv;
    const size_t bytes = OFFSET + (size_t)nv * STRIDE;
    weft_cloth stale = make_cloth(ctx), null_handle = {0};
    CHECK_EQ_INT(weft_cloth_destroy(ctx, stale), WEFT_OK);
    struct {
        const char* what;
        weft_cloth cloth;
        int index;
        unsigned buffer;
        size_t offset, stride;
        int n;
        weft_status want;
        const char* says;
    } rows[] = {
        {"null handle", null_handle, 0, buf, OFFSET, STRIDE, nv, WEFT_ERROR_INVALID_HANDLE, "handle"},
        {"destroyed cloth", stale, 0, buf, OFFSET, STRIDE, nv, WEFT_ERROR_INVALID_HANDLE, "destroyed"},
        {"index 1", c, 1, buf, OFFSET, STRIDE, nv, WEFT_ERROR_OUT_OF_RANGE, "index 1"},
        {"index -1", c, -1, buf, OFFSET, STRIDE, nv, WEFT_ERROR_OUT_OF_RANGE, "index -1"},
        {"wrong count", c, 0, buf, OFFSET, STRIDE, nv - 1, WEFT_ERROR_OUT_OF_RANGE, "n_vertices"},
        {"buffer 0", c, 0, 0, OFFSET, STRIDE, nv, WEFT_ERROR_INVALID_ARGUMENT, "buffer is 0"},
        {"not a buffer", c, 0, 987654u, OFFSET, STRIDE, nv, WEFT_ERROR_INVALID_ARGUMENT, "987654"},
        {"too small", c, 0, buf, OFFSET + STRIDE, STRIDE, nv, WEFT_ERROR_INVALID_ARGUMENT, "bytes"},
        {"offset past the end", c, 0, buf, bytes + 16, 0, nv, WEFT_ERROR_INVALID_ARGUMENT, "bytes"},
        {"stride too large", c, 0, buf, 0, STRIDE + 4, nv, WEFT_ERROR_INVALID_ARGUMENT, "bytes"},
        {"offset not a multiple of 4", c, 0, buf, OFFSET + 2, STRIDE, nv, WEFT_ERROR_INVALID_ARGUMENT, "multiples of 4"},
        {"stride 13", c, 0, buf, OFFSET, 13, nv, WEFT_ERROR_INVALID_ARGUMENT, "multiples of 4"},
        {"stride 8", c, 0, buf, OFFSET, 8, nv, WEFT_ERROR_INVALID_ARGUMENT, ">= 12"},
        {"stride overflowing", c, 0, buf, OFFSET, SIZE_MAX / 8 * 4, nv, WEFT_ERROR_INVALID_ARGUMENT, "overflows"},
    };
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; ++r) {
        weft_status st = weft_cloth_set_mesh_collider_gl_buffer(ctx, rows[r].cloth, rows[r].index, rows[r].buffer,
                                                                rows[r].offset, rows[r].stride, rows[r].n);
        CHECK_EQ_INT(st, rows[r].want);
        if (st != rows[r].want) fprintf(stderr, "  %s: %s\n", rows[r].what, weft_context_last_error(ctx));
        CHECK(has(ctx, rows[r].says));
        int same_ = ag_same_snapshot(ctx, c, ref, sz);
        if (!same_) fprintf(stderr, "  %s: state changed (%s)\n", rows[r].what, weft_context_last_error(ctx));
        CHECK(same_);
    }
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(NULL, c, 0, buf, OFFSET, STRIDE, nv),
                 WEFT_ERROR_INVALID_ARGUMENT);

    /* a buffer the host has mapped */
    glBindBuffer(GL_COPY_WRITE_BUFFER, buf);
    void* map = glMapBufferRange(GL_COPY_WRITE_BUFFER, 0, 16, GL_MAP_READ_BIT);
    CHECK(map != NULL);
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c, 0, buf, OFFSET, STRIDE, nv),
                 WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(has(ctx, "mapped"));
    glUnmapBuffer(GL_COPY_WRITE_BUFFER);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    CHECK(ag_same_snapshot(ctx, c, ref, sz));

    /* bad floats in the buffer: NaN, Inf, beyond 1e30; the buffer's own body restored after */
    float* pos = malloc((size_t)nv * 12);
    body_at(0, pos);
    const float bad[3] = {NAN, INFINITY, 2e30f};
    const weft_status want[3] = {WEFT_ERROR_NONFINITE, WEFT_ERROR_NONFINITE, WEFT_ERROR_OUT_OF_RANGE};
    const char* says[3] = {"vertex 5's coordinate 1 is NaN", "is Inf", "beyond"};
    GLuint other = make_buffer(bytes);
    for (int k = 0; k < 3; ++k) {
        float keep = pos[3 * 5 + 1];
        pos[3 * 5 + 1] = bad[k];
        fill_buffer(other, pos, g_tm.nv);
        pos[3 * 5 + 1] = keep;
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c, 0, other, OFFSET, STRIDE, nv), want[k]);
        CHECK(has(ctx, says[k]));
        CHECK(ag_same_snapshot(ctx, c, ref, sz));
    }
    glDeleteBuffers(1, &other);
    free(pos);

    /* no current context: the host's released for the call */
    wg_gl_end(host);
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, c, 0, buf, OFFSET, STRIDE, nv), WEFT_ERROR_GPU);
    char err[256];
    CHECK_EQ_INT(wg_gl_begin(host, err, sizeof err), WEFT_OK);
    CHECK(ag_same_snapshot(ctx, c, ref, sz));
    CHECK_EQ_INT(glGetError(), GL_NO_ERROR);
    free(ref);
}

/* The two cloths of one host-current context, frame by frame; refusals on the buffer's cloth at
 * frame 15 (after its body was set for that frame). */
static void test_buffer_matches_arrays(void) {
    wg_gl_context* host = hc_host_begin();
    if (!host) return;
    /* the host's own buffer bindings, which the calls must leave alone */
    GLuint mine[3];
    glGenBuffers(3, mine);
    glBindBuffer(GL_COPY_READ_BUFFER, mine[0]);
    glBindBuffer(GL_COPY_WRITE_BUFFER, mine[1]);
    glBindBuffer(GL_ARRAY_BUFFER, mine[2]);
    bindings before, after;
    record(&before);

    weft_context* ctx = hc_context(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT);
    if (ctx) {
        weft_cloth a = make_cloth(ctx), b = make_cloth(ctx), u = make_cloth(ctx);   /* u: a body 1 ulp off */
        const int nv = g_tm.nv, n = N * N;
        GLuint buf = make_buffer(OFFSET + (size_t)nv * STRIDE);
        glBindBuffer(GL_COPY_READ_BUFFER, mine[0]);
        glBindBuffer(GL_COPY_WRITE_BUFFER, mine[1]);
        float* body = malloc((size_t)nv * 12);
        float *pa = malloc((size_t)n * 12), *pb = malloc((size_t)n * 12), *pu = malloc((size_t)n * 12);
        float* nudged = malloc((size_t)nv * 12);
        float* replay = malloc((size_t)(FRAMES - SAVED_AT) * (size_t)n * 12);   /* pb, frames after the save */
        weft_cloth_info info;
        CHECK_EQ_INT(weft_cloth_get_info(ctx, b, &info), WEFT_OK);
        unsigned char* saved = malloc(info.snapshot_size);
        weft_frame fr = weft_default_frame();
        fr.dt = DT;
        const int on_gpu = hg_body_on_gpu(), both = hg_arrays_on_gpu();
        int same = 1, count = 0;
        double far = 0.0, far_ulp = 0.0;
        for (int f = 1; f <= FRAMES; ++f) {
            body_at(f, body);
            CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, a, 0, body, nv), WEFT_OK);
            for (int i = 0; i < 3 * nv; ++i) nudged[i] = nextafterf(body[i], INFINITY);
            CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, u, 0, nudged, nv), WEFT_OK);
            fill_buffer(buf, body, g_tm.nv);
            glBindBuffer(GL_COPY_READ_BUFFER, mine[0]);
            glBindBuffer(GL_COPY_WRITE_BUFFER, mine[1]);
            record(&before);
            weft_status st = weft_cloth_set_mesh_collider_gl_buffer(ctx, b, 0, buf, OFFSET, STRIDE, nv);
            CHECK_EQ_INT(st, WEFT_OK);
            if (st != WEFT_OK) fprintf(stderr, "  frame %d: %s\n", f, weft_context_last_error(ctx));
            record(&after);
            CHECK(memcmp(&before, &after, sizeof before) == 0);
            if (f == 15) refusals(ctx, b, buf, host);
            CHECK_EQ_INT(weft_cloth_step(ctx, a, &fr, NULL), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_step(ctx, b, &fr, NULL), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_step(ctx, u, &fr, NULL), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, u, WEFT_SPACE_WORLD, pu, NULL, n, &count), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, a, WEFT_SPACE_WORLD, pa, NULL, n, &count), WEFT_OK);
            far_ulp = fmax(far_ulp, ag_max_distance(pa, pu, n));
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, b, WEFT_SPACE_WORLD, pb, NULL, n, &count), WEFT_OK);
            if (memcmp(pa, pb, (size_t)n * 12) != 0) {
                if (same && !on_gpu) fprintf(stderr, "  frame %d: the buffer's cloth differs from the arrays'\n", f);
                same = 0;
            }
            far = fmax(far, ag_max_distance(pa, pb, n));
            if (f == SAVED_AT) CHECK_EQ_INT(weft_cloth_save(ctx, b, saved, info.snapshot_size), WEFT_OK);
            if (f > SAVED_AT) memcpy(replay + (size_t)(f - SAVED_AT - 1) * (size_t)n * 3, pb, (size_t)n * 12);
        }
        /* the sheet rests on the risen body: its top near the body's (0.3 m x 1.05 sin + 0.2 m) */
        double top = -HUGE_VAL;
        for (int i = 0; i < n; ++i) top = fmax(top, pb[3 * i + 1]);
        printf("  %d frames, the body %s; bit-identical to the arrays' cloth: %s (farthest %.3g m); the sheet's "
               "top %.4f m (the body's top 0.5 m +- 1.5 cm)\n", FRAMES,
               on_gpu ? "moved on the GPU" : "read back", same ? "yes" : "no", far, top);
        printf("  the arrays' cloth with the body 1 ulp higher: farthest %.3g m\n", far_ulp);
        CHECK(far_ulp < 0.02);
        if (on_gpu && !both) CHECK(far <= BOUND * far_ulp);
        else CHECK(same);
        CHECK(top > 0.47 && top < 0.54);
        unsigned char* end_a = malloc(info.snapshot_size);
        unsigned char* end_b = malloc(info.snapshot_size);
        CHECK_EQ_INT(weft_cloth_save(ctx, a, end_a, info.snapshot_size), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_save(ctx, b, end_b, info.snapshot_size), WEFT_OK);
        if (!on_gpu || both) CHECK(memcmp(end_a, end_b, info.snapshot_size) == 0);

        /* the snapshot at SAVED_AT restored and the frames after it replayed: the same bits */
        CHECK_EQ_INT(weft_cloth_restore(ctx, b, saved, info.snapshot_size), WEFT_OK);
        int replayed = 1;
        for (int f = SAVED_AT + 1; f <= FRAMES; ++f) {
            body_at(f, body);
            fill_buffer(buf, body, g_tm.nv);
            CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, b, 0, buf, OFFSET, STRIDE, nv), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_step(ctx, b, &fr, NULL), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, b, WEFT_SPACE_WORLD, pb, NULL, n, &count), WEFT_OK);
            replayed &= memcmp(pb, replay + (size_t)(f - SAVED_AT - 1) * (size_t)n * 3, (size_t)n * 12) == 0;
        }
        CHECK(replayed);
        CHECK(ag_same_snapshot(ctx, b, end_b, info.snapshot_size));
        printf("  restored at frame %d and replayed to %d: bit-identical %s\n", SAVED_AT, FRAMES,
               replayed ? "yes" : "no");

        /* the body on the CPU where the host needs it: the collision check (the buffer's body
           and the arrays' are one surface to float's reach: the deepest particles agree), then a
           frame that teleports both cloths with their bodies given the same way */
        weft_collision_check ka, kb;
        CHECK_EQ_INT(weft_cloth_check_collisions(ctx, a, &ka), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_check_collisions(ctx, b, &kb), WEFT_OK);
        printf("  deepest behind the body: arrays' cloth %.3g m, buffer's %.3g m\n", ka.max_penetration,
               kb.max_penetration);
        CHECK(fabs(ka.max_penetration - kb.max_penetration) <= 1e-3);
        CHECK(kb.max_penetration < 5e-3);
        body_at(FRAMES + 1, body);
        fill_buffer(buf, body, g_tm.nv);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, a, 0, body, nv), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, b, 0, buf, OFFSET, STRIDE, nv), WEFT_OK);
        fr.flags = WEFT_FRAME_TELEPORT;
        CHECK_EQ_INT(weft_cloth_step(ctx, a, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, b, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, a, WEFT_SPACE_WORLD, pa, NULL, n, &count), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, b, WEFT_SPACE_WORLD, pb, NULL, n, &count), WEFT_OK);
        double jumped = ag_max_distance(pa, pb, n);
        printf("  a teleporting frame: the cloths %.3g m apart\n", jumped);
        CHECK(jumped <= 0.02);
        /* a frame with the body from the buffer again (on the GPU), then one that moves both
           bodies rigidly back to the creation shape (no vertices given): the buffer's body comes
           back to the CPU for it */
        fr.flags = 0;
        body_at(FRAMES + 2, body);
        fill_buffer(buf, body, g_tm.nv);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, a, 0, body, nv), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, b, 0, buf, OFFSET, STRIDE, nv), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, a, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, b, &fr, NULL), WEFT_OK);
        static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        fr.mesh_collider_transforms = identity;
        CHECK_EQ_INT(weft_cloth_step(ctx, a, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, b, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, a, WEFT_SPACE_WORLD, pa, NULL, n, &count), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, b, WEFT_SPACE_WORLD, pb, NULL, n, &count), WEFT_OK);
        double moved = ag_max_distance(pa, pb, n);
        printf("  a rigidly moved frame: the cloths %.3g m apart\n", moved);
        CHECK(moved <= 0.02);
        free(end_a), free(end_b), free(saved), free(replay);
        free(body), free(pa), free(pb), free(pu), free(nudged);
        glDeleteBuffers(1, &buf);
        weft_context_destroy(ctx);
    }
    glBindBuffer(GL_COPY_READ_BUFFER, 0);
    glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glDeleteBuffers(3, mine);
    wg_gl_end(host);
    wg_gl_context_destroy(host);
}

/* Sleeping on a body that stands still: the sheet dropped 1 cm onto a floor (a 4 m quad, its
 * normal up), one cloth given the floor's floats through the array call every frame, the other
 * the same floats through the buffer call (the same buffer, unchanged). Both fall asleep, the
 * buffer's cloth within SLEEP_FRAMES frames of the arrays' (on the GPU its contacts are computed
 * in float; read back, core's path: the same frame), and stay asleep while given the same floats;
 * then the buffer's contents change by one bit of one coordinate and the buffer's cloth wakes in
 * that frame, as the arrays' does given the same change. */
#define SLEEP_FRAMES 3
#define MAX_SLEEP_FRAMES 150

/* One frame of both: a's floor (4 vertices) through the array call, b's from buf. */
static void floor_frame(weft_context* ctx, weft_cloth a, weft_cloth b, const float* floor, GLuint buf,
                        weft_frame_stats* sa, weft_frame_stats* sb) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, a, 0, floor, 4), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, b, 0, buf, OFFSET, STRIDE, 4), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_step(ctx, a, &fr, sa), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_step(ctx, b, &fr, sb), WEFT_OK);
}

static void test_sleep_on_still_body(void) {
    wg_gl_context* host = hc_host_begin();
    if (!host) return;
    weft_context* ctx = hc_context(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT);
    if (ctx) {
        const float y = 0.49f;   /* the sheet lies at 0.5 m */
        float floor[12] = {-2, y, -2, -2, y, 2, 2, y, 2, 2, y, -2};
        const int quad[6] = {0, 1, 2, 0, 2, 3};
        weft_cloth a = make_cloth_on(ctx, floor, 4, quad, 2), b = make_cloth_on(ctx, floor, 4, quad, 2);
        GLuint buf = make_buffer(OFFSET + 4 * (size_t)STRIDE);
        fill_buffer(buf, floor, 4);
        weft_frame_stats sa, sb;
        int fell_a = 0, fell_b = 0, f = 1;
        for (; f <= MAX_SLEEP_FRAMES && !(fell_a && fell_b); ++f) {
            floor_frame(ctx, a, b, floor, buf, &sa, &sb);
            if (sa.fell_asleep) fell_a = f;
            if (sb.fell_asleep) fell_b = f;
        }
        printf("  a sheet on a still floor (the body %s): asleep after frame %d (arrays), %d (buffer)\n",
               hg_body_on_gpu() ? "on the GPU" : "read back", fell_a, fell_b);
        CHECK(fell_a > 0 && fell_b > 0);
        CHECK(abs(fell_a - fell_b) <= (hg_body_on_gpu() ? SLEEP_FRAMES : 0));
        for (int k = 0; k < 3; ++k, ++f) {   /* the same floats: both sleep on */
            floor_frame(ctx, a, b, floor, buf, &sa, &sb);
            CHECK(sa.asleep && sb.asleep);
        }
        floor[7] = nextafterf(floor[7], -INFINITY);   /* one bit of vertex 2's y */
        fill_buffer(buf, floor, 4);
        floor_frame(ctx, a, b, floor, buf, &sa, &sb);
        printf("  one bit of the floor changed at frame %d: woke (arrays) %d, (buffer) %d\n", f, sa.woke, sb.woke);
        CHECK(sa.woke && !sa.asleep);
        CHECK(sb.woke && !sb.asleep);
        glDeleteBuffers(1, &buf);
        weft_context_destroy(ctx);
    }
    wg_gl_end(host);
    wg_gl_context_destroy(host);
}

/* Frames that fail with the body from the buffer (moved on the GPU with compute passes): two
 * buffer cloths of one context given the same buffer every frame, the reference r and the cloth
 * f, which is also given, after that frame's buffer call, a frame that fails:
 *  - WIND_FAILS_AT: a wind of 1e150 m/s (float's infinity on the GPU: non-finite forces in every
 *    retry of the first substep, after the body's substep passes ran);
 *  - FAR_FAILS_AT (twice): the object thrown 1e31 m away (the inertia defaults leave the
 *    simulation alone, so the whole frame runs and ends the body's frame on the GPU; then the
 *    outputs in object space are beyond 1e30).
 * Each returns STEP_FAILED saying the cloth was restored; f then steps the frame as r does. The
 * cloth and the body must be back at the frame's start with the buffer's vertices still pending:
 * f's positions bit-identical to r's at every frame; right after the second far failure (the
 * snapshot pulls both bodies back to the CPU) and at the end, the two snapshots byte-identical. */
#define WIND_FAILS_AT 14
#define FAR_FAILS_AT 18
#define FAR_FAILS_AGAIN_AT 24
#define FAIL_FRAMES 30

static int failed_frame(weft_context* ctx, weft_cloth c, const weft_frame* fr) {
    weft_status st = weft_cloth_step(ctx, c, fr, NULL);
    CHECK_EQ_INT(st, WEFT_ERROR_STEP_FAILED);
    return st == WEFT_ERROR_STEP_FAILED && has(ctx, "restored to its state before the call");
}

static void test_failed_frames_roll_back(void) {
    wg_gl_context* host = hc_host_begin();
    if (!host) return;
    weft_context* ctx = hc_context(WEFT_BACKEND_GPU, WEFT_GL_HOST_CURRENT);
    if (ctx) {
        weft_cloth r = make_cloth(ctx), f = make_cloth(ctx);
        const int nv = g_tm.nv, n = N * N;
        GLuint buf = make_buffer(OFFSET + (size_t)nv * STRIDE);
        float* body = malloc((size_t)nv * 12);
        float *pr = malloc((size_t)n * 12), *pf = malloc((size_t)n * 12);
        weft_cloth_info info;
        CHECK_EQ_INT(weft_cloth_get_info(ctx, r, &info), WEFT_OK);
        unsigned char *sr = malloc(info.snapshot_size), *sf = malloc(info.snapshot_size);
        weft_frame fr = weft_default_frame(), windy = weft_default_frame(), far = weft_default_frame();
        fr.dt = windy.dt = far.dt = DT;
        const double gale[3] = {1e150, 0.0, 1e150};
        windy.wind = gale;
        float thrown[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1e31f, 0, 0, 1};
        far.object_transform = thrown;
        int count = 0, failed = 0, same = 1, first_diff = 0, saved_same = 0;
        for (int k = 1; k <= FAIL_FRAMES; ++k) {
            body_at(k, body);
            fill_buffer(buf, body, nv);
            CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, r, 0, buf, OFFSET, STRIDE, nv), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(ctx, f, 0, buf, OFFSET, STRIDE, nv), WEFT_OK);
            if (k == WIND_FAILS_AT) failed += failed_frame(ctx, f, &windy);
            if (k == FAR_FAILS_AT || k == FAR_FAILS_AGAIN_AT) failed += failed_frame(ctx, f, &far);
            if (k == FAR_FAILS_AGAIN_AT) {
                CHECK_EQ_INT(weft_cloth_save(ctx, r, sr, info.snapshot_size), WEFT_OK);
                CHECK_EQ_INT(weft_cloth_save(ctx, f, sf, info.snapshot_size), WEFT_OK);
                saved_same = memcmp(sr, sf, info.snapshot_size) == 0;
            }
            CHECK_EQ_INT(weft_cloth_step(ctx, r, &fr, NULL), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_step(ctx, f, &fr, NULL), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, r, WEFT_SPACE_WORLD, pr, NULL, n, &count), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_get_vertices(ctx, f, WEFT_SPACE_WORLD, pf, NULL, n, &count), WEFT_OK);
            if (same && memcmp(pr, pf, (size_t)n * 12) != 0) {
                same = 0;
                first_diff = k;
                fprintf(stderr, "  frame %d: the cloth that failed frames differs from the reference by %.3g m\n", k,
                        ag_max_distance(pr, pf, n));
            }
        }
        CHECK_EQ_INT(weft_cloth_save(ctx, r, sr, info.snapshot_size), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_save(ctx, f, sf, info.snapshot_size), WEFT_OK);
        const int end_same = memcmp(sr, sf, info.snapshot_size) == 0;
        printf("  the body %s: %d failed frames (a gale at frame %d, the object thrown at %d and %d); bit-identical to "
               "the reference every frame: %s (first difference at frame %d); snapshots after the last failure and "
               "at frame %d the same: %s, %s\n", hg_body_on_gpu() ? "on the GPU" : "read back", failed, WIND_FAILS_AT,
               FAR_FAILS_AT, FAR_FAILS_AGAIN_AT, same ? "yes" : "no", first_diff, FAIL_FRAMES,
               saved_same ? "yes" : "no", end_same ? "yes" : "no");
        CHECK_EQ_INT(failed, 3);
        CHECK(same);
        CHECK(saved_same);
        CHECK(end_same);
        free(sr), free(sf), free(body), free(pr), free(pf);
        glDeleteBuffers(1, &buf);
        weft_context_destroy(ctx);
    }
    wg_gl_end(host);
    wg_gl_context_destroy(host);
}

/* A CPU cloth, and a GPU cloth of a headless context: refused, naming what to use instead. */
static void test_other_contexts(void) {
    weft_context* cpu = hc_context(WEFT_BACKEND_CPU, WEFT_GL_HEADLESS);
    if (cpu) {
        weft_cloth c = make_cloth(cpu);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(cpu, c, 0, 1, 0, 0, g_tm.nv), WEFT_ERROR_UNSUPPORTED);
        CHECK(has(cpu, "CPU backend") && has(cpu, "weft_cloth_set_mesh_collider_vertices"));
        weft_context_destroy(cpu);
    }
    weft_context* gpu = hc_context(WEFT_BACKEND_GPU, WEFT_GL_HEADLESS);
    if (gpu) {
        weft_cloth c = make_cloth(gpu);
        CHECK_EQ_INT(weft_cloth_set_mesh_collider_gl_buffer(gpu, c, 0, 1, 0, 0, g_tm.nv), WEFT_ERROR_UNSUPPORTED);
        CHECK(has(gpu, "HEADLESS"));
        weft_frame fr = weft_default_frame();
        fr.dt = DT;
        CHECK_EQ_INT(weft_cloth_step(gpu, c, &fr, NULL), WEFT_OK);
        weft_context_destroy(gpu);
    }
}

int main(void) {
    hg_body_setting();
    double centre[3] = {0.0, 0.0, 0.0};
    icosphere(&g_tm, 2, 0.3, centre);
    g_rest = malloc((size_t)g_tm.nv * 12);
    for (int i = 0; i < 3 * g_tm.nv; ++i) g_rest[i] = (float)g_tm.x[i];
    ag_grid(&g_sheet, N, 1.0, 0.5, 0, 0);
    RUN_TEST(test_buffer_matches_arrays);
    RUN_TEST(test_sleep_on_still_body);
    RUN_TEST(test_failed_frames_roll_back);
    RUN_TEST(test_other_contexts);
    ag_free(&g_sheet);
    free(g_rest);
    return TEST_SUMMARY();
}
