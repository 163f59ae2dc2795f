/* core's cloth object (core/cloth.h) and its backend table (core/cloth_backend.h), below the
 * facade: every bad input is refused with a clear message and leaves the cloth's snapshot
 * bytes unchanged; a failed frame is rolled back; snapshots restore bit-identically; the cloth
 * calls its backend inside begin/end groups, downloads a mirror before reading the particles and
 * uploads it after changing them; a batch on a backend that is not concurrent is one group, a
 * batch on two backends one group each (a group that cannot begin fails alone); creation in two
 * calls builds wc_cloth_create's cloth; the tables are complete; xform and serial basics. */
#include <stdlib.h>
#include "api_grid.h"
#include "check.h"
#include "cloth.h"
#include "serial.h"
#include "vec3.h"
#ifdef WEFT_TEST_HAVE_GPU
#include "wg_backend.h"
#endif

#define N 8
static ag_mesh g_mesh;
static const wc_snapshot_stamp g_stamp = {7u, 0x000700u};

/* ---- a recording backend: the CPU's operations, counted and checked for their groups ---------- */

static struct {
    int inside, begins, ends, misplaced, downloads, uploads, carries, teleports, backups, restores;
} g_rec;

static wc_status rec_begin(void* device, wc_diag* d) {
    if (g_rec.inside) ++g_rec.misplaced;   /* not nestable */
    g_rec.inside = 1;
    ++g_rec.begins;
    return wc_cloth_cpu.begin(device, d);
}
static void rec_end(void* device) {
    if (!g_rec.inside) ++g_rec.misplaced;
    g_rec.inside = 0;
    ++g_rec.ends;
    wc_cloth_cpu.end(device);
}
#define IN_GROUP() (g_rec.misplaced += !g_rec.inside)
static wc_status rec_create(wc_cloth* c, wc_diag* d) {
    g_rec.misplaced += g_rec.inside;
    return wc_cloth_cpu.create(c, d);
}
static wc_status rec_step(wc_cloth* c, double dt, wc_step_stats* st, wc_diag* d) {
    IN_GROUP();
    return wc_cloth_cpu.step_frame(c, dt, st, d);
}
static void rec_backup(wc_cloth* c) {
    IN_GROUP();
    ++g_rec.backups;
    wc_cloth_cpu.backup(c);
}
static void rec_restore_backup(wc_cloth* c) {
    IN_GROUP();
    ++g_rec.restores;
    wc_cloth_cpu.restore_backup(c);
}
static void rec_carry(wc_cloth* c, const wc_carry* k) {
    IN_GROUP();
    ++g_rec.carries;
    g_rec.teleports += k->teleport;
    wc_cloth_cpu.carry(c, k);
}
static wc_status rec_download(wc_cloth* c, wc_diag* d) {
    IN_GROUP();
    ++g_rec.downloads;
    return wc_cloth_cpu.download(c, d);
}
static wc_status rec_upload(wc_cloth* c, wc_diag* d) {
    IN_GROUP();
    ++g_rec.uploads;
    return wc_cloth_cpu.upload(c, d);
}
static double rec_max_abs(wc_cloth* c) {
    IN_GROUP();
    return wc_cloth_cpu.max_abs(c);
}
static wc_status rec_output(wc_cloth* c, const wc_output_request* r, wc_diag* d) {
    IN_GROUP();
    return wc_cloth_cpu.output(c, r, d);
}

static wc_cloth_backend recording(void) {
    wc_cloth_backend b = wc_cloth_cpu;
    b.name = "recording";
    b.begin = rec_begin;
    b.end = rec_end;
    b.create = rec_create;
    b.step_frame = rec_step;
    b.backup = rec_backup;
    b.restore_backup = rec_restore_backup;
    b.carry = rec_carry;
    b.download = rec_download;
    b.upload = rec_upload;
    b.max_abs = rec_max_abs;
    b.output = rec_output;
    return b;
}

/* ---- fixture ----------------------------------------------------------------------------------- */

static float g_identity[16], g_sphere_at[16];
static const float g_no_axis[3] = {0.0f, 0.0f, 0.0f};
static int g_top[N];

/* A vertical N x N sheet pinned along its top row, a sphere below it. */
static wc_cloth_def sheet_def(wc_cloth_attachment_def* att, wc_cloth_collider_def* col) {
    wc_cloth_def d;
    memset(&d, 0, sizeof d);
    d.mesh.positions = g_mesh.pos;
    d.mesh.n_vertices = g_mesh.nv;
    d.mesh.face_sizes = g_mesh.sizes;
    d.mesh.n_faces = g_mesh.nf;
    d.mesh.indices = g_mesh.idx;
    d.mesh.unit_scale = 1.0;
    d.model = wc_default_model_def();
    d.sim = wc_default_sim_def();
    d.sim.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    d.sim.threads = 1;
    d.transform = g_identity;
    d.max_frame_time = 0.25;
    d.linear_inertia = 1.0;
    d.angular_inertia = 1.0;
    for (int i = 0; i < N; ++i) g_top[i] = i + N * (N - 1);
    att[0].vertices = g_top;
    att[0].n_vertices = N;
    att[0].bind_transform = g_identity;
    att[0].free_axis = g_no_axis;
    d.attachments = att;
    d.n_attachments = 1;
    col[0].type = WC_COLLIDER_SPHERE;
    col[0].radius = 0.2;
    col[0].thickness = 0.005;
    col[0].friction = 0.3;
    col[0].transform = g_sphere_at;
    d.colliders = col;
    d.n_colliders = 1;
    return d;
}

static wc_cloth* make(const wc_cloth_backend* b, double angular_inertia) {
    wc_cloth_attachment_def att[1];
    wc_cloth_collider_def col[1];
    wc_cloth_def def = sheet_def(att, col);
    def.angular_inertia = angular_inertia;
    wc_allocator a = {0};
    wc_diag d = {0};
    wc_cloth* c = NULL;
    wc_status st = wc_cloth_create(&c, &def, b, NULL, &a, &d);
    if (st != WC_OK) fprintf(stderr, "create: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return c;
}

static wc_cloth_frame frame(void) {
    wc_cloth_frame f;
    memset(&f, 0, sizeof f);
    f.dt = 1.0 / 60.0;
    return f;
}

static wc_status step(wc_cloth* c, const wc_cloth_frame* f) {
    wc_step_stats ss;
    wc_diag d = {0};
    wc_status st = wc_cloth_step(c, f, &ss, &d);
    if (st != WC_OK) fprintf(stderr, "step: %s\n", d.message);
    return st;
}

static unsigned char* snapshot(wc_cloth* c) {
    unsigned char* buf = malloc(c->snapshot_size);
    wc_diag d = {0};
    CHECK_EQ_INT(wc_cloth_save(c, &g_stamp, buf, &d), WC_OK);
    return buf;
}

/* st with a message holding needle, and the cloth's snapshot bytes as in before */
static void expect_refused(wc_cloth* c, const unsigned char* before, wc_status got, const wc_diag* d, wc_status want,
                           const char* needle) {
    CHECK_EQ_INT(got, want);
    if (!strstr(d->message, needle)) fprintf(stderr, "message \"%s\" lacks \"%s\"\n", d->message, needle);
    CHECK(strstr(d->message, needle) != NULL);
    unsigned char* after = snapshot(c);
    CHECK(memcmp(before, after, c->snapshot_size) == 0);
    free(after);
}

/* ---- tests ------------------------------------------------------------------------------------- */

static void test_snapshot_round_trip(void) {
    wc_cloth* c = make(&wc_cloth_cpu, 1.0);
    wc_cloth_frame f = frame();
    for (int k = 0; k < 5; ++k) CHECK_EQ_INT(step(c, &f), WC_OK);
    unsigned char* snap = snapshot(c);
    CHECK(memcmp(snap, "WEFTSNP3", 8) == 0);
    CHECK(memcmp(snap + 64, c->state->x, 3 * sizeof(double)) == 0);   /* x at byte 64 */
    int n = c->model.n_particles;
    double* x = malloc(3 * sizeof(double) * (size_t)n);
    for (int k = 0; k < 4; ++k) CHECK_EQ_INT(step(c, &f), WC_OK);
    memcpy(x, c->state->x, 3 * sizeof(double) * (size_t)n);
    wc_diag d = {0};
    CHECK_EQ_INT(wc_cloth_restore(c, &g_stamp, snap, c->snapshot_size, &d), WC_OK);
    for (int k = 0; k < 4; ++k) CHECK_EQ_INT(step(c, &f), WC_OK);
    CHECK(memcmp(x, c->state->x, 3 * sizeof(double) * (size_t)n) == 0);
    free(x);
    free(snap);
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);
}

static void test_bad_inputs(void) {
    wc_cloth* c = make(&wc_cloth_cpu, 1.0);
    wc_cloth_frame f = frame();
    for (int k = 0; k < 3; ++k) CHECK_EQ_INT(step(c, &f), WC_OK);
    unsigned char* before = snapshot(c);
    wc_diag d = {0};
    wc_step_stats ss;

    f.dt = 0.0;
    expect_refused(c, before, wc_cloth_step(c, &f, &ss, &d), &d, WC_ERROR_INVALID_ARGUMENT, "max_frame_time");
    f.dt = 0.5;
    expect_refused(c, before, wc_cloth_step(c, &f, &ss, &d), &d, WC_ERROR_INVALID_ARGUMENT, "max_frame_time");

    int outside[1] = {N * N}, first[1] = {0}, again[1] = {0};
    wc_cloth_attachment_def a[2] = {{first, 1, g_identity, g_no_axis}, {outside, 1, g_identity, g_no_axis}};
    expect_refused(c, before, wc_cloth_set_attachments(c, a, 2, "attachments", &d), &d, WC_ERROR_OUT_OF_RANGE,
                   "attachments[1].vertices[0] = 64 is outside [0, 64)");
    a[1].vertices = again;
    expect_refused(c, before, wc_cloth_set_attachments(c, a, 2, "attachments", &d), &d, WC_ERROR_INVALID_ARGUMENT,
                   "already pinned by attachments[0]");
    expect_refused(c, before, wc_cloth_set_attachments(c, a, -1, "attachments", &d), &d, WC_ERROR_INVALID_ARGUMENT,
                   "negative");
    expect_refused(c, before, wc_cloth_set_attachments(c, NULL, 1, "attachments", &d), &d, WC_ERROR_INVALID_ARGUMENT,
                   "attachments is NULL");

    float p[9] = {0};
    expect_refused(c, before, wc_cloth_set_mesh_vertices(c, 0, p, &d), &d, WC_ERROR_OUT_OF_RANGE,
                   "index 0 is outside [0, 0)");

    wc_output_request r;
    memset(&r, 0, sizeof r);
    r.position_buffer = 1;
    expect_refused(c, before, wc_cloth_write_gl_buffers(c, &r, &d), &d, WC_ERROR_UNSUPPORTED, "CPU backend");
    wc_gl_vertex_source gs = {.buffer = 1, .stride = 12, .n = 3};
    const float* got = NULL;
    wc_gl_vertex_result res;
    expect_refused(c, before, wc_cloth_read_mesh_gl(c, 0, &gs, &got, &res, &d), &d, WC_ERROR_OUT_OF_RANGE,
                   "index 0 is outside [0, 0)");
    expect_refused(c, before, wc_cloth_save(c, &g_stamp, NULL, &d), &d, WC_ERROR_INVALID_ARGUMENT, "buf is NULL");

    /* snapshots: truncated, not one, another library (the format named), damaged, another model */
    size_t sz = c->snapshot_size;
    unsigned char* snap = malloc(sz);
    memcpy(snap, before, sz);
    expect_refused(c, before, wc_cloth_restore(c, &g_stamp, snap, 20, &d), &d, WC_ERROR_INVALID_ARGUMENT, "truncated");
    expect_refused(c, before, wc_cloth_restore(c, &g_stamp, snap, sz - 1, &d), &d, WC_ERROR_INVALID_ARGUMENT,
                   "truncated");
    snap[7] = '2';   /* an older format's magic */
    expect_refused(c, before, wc_cloth_restore(c, &g_stamp, snap, sz, &d), &d, WC_ERROR_INVALID_ARGUMENT, "bad magic");
    snap[7] = '3';
    wc_snapshot_stamp other = {g_stamp.abi + 1, g_stamp.version};
    expect_refused(c, before, wc_cloth_restore(c, &other, snap, sz, &d), &d, WC_ERROR_SNAPSHOT_MISMATCH,
                   "another library version (format WEFTSNP3");
    snap[sz / 2] ^= 1;
    expect_refused(c, before, wc_cloth_restore(c, &g_stamp, snap, sz, &d), &d, WC_ERROR_INVALID_ARGUMENT, "damaged");
    snap[sz / 2] ^= 1;
    wc_cloth* b = make(&wc_cloth_cpu, 1.0);
    CHECK_EQ_INT(wc_cloth_set_attachments(b, a, 1, "attachments", &d), WC_OK);
    unsigned char* foreign = snapshot(b);
    expect_refused(c, before, wc_cloth_restore(c, &g_stamp, foreign, b->snapshot_size, &d), &d,
                   WC_ERROR_SNAPSHOT_MISMATCH, "another model");
    free(foreign);
    free(snap);
    free(before);
    CHECK_EQ_INT(wc_cloth_destroy(b, &d), WC_OK);
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);
}

static void test_create_refused(void) {
    wc_cloth_attachment_def att[1];
    wc_cloth_collider_def col[1];
    wc_cloth_def def = sheet_def(att, col);
    int idx[4] = {0, 1, 2, 99}, sizes[1] = {4};
    def.mesh.indices = idx;
    def.mesh.face_sizes = sizes;
    def.mesh.n_faces = 1;
    wc_allocator a = {0};
    wc_diag d = {0};
    wc_cloth* c = (wc_cloth*)&d;   /* not NULL: create sets it */
    CHECK_EQ_INT(wc_cloth_create(&c, &def, &wc_cloth_cpu, NULL, &a, &d), WC_ERROR_OUT_OF_RANGE);
    CHECK(c == NULL);
    CHECK(strncmp(d.message, "def->mesh: ", 11) == 0);
    def = sheet_def(att, col);
    float far[16];
    ag_identity(far);
    far[12] = 1e31f;   /* the outputs would not fit in float range */
    def.transform = far;
    CHECK_EQ_INT(wc_cloth_create(&c, &def, &wc_cloth_cpu, NULL, &a, &d), WC_ERROR_OUT_OF_RANGE);
    CHECK(strstr(d.message, "beyond the 1e+30 the float outputs hold") != NULL);
}

/* A frame that fails (its pins thrown beyond the outputs' range) is undone, and says so. */
static void test_failed_frame_rolls_back(void) {
    wc_cloth* c = make(&wc_cloth_cpu, 1.0);
    wc_cloth_frame f = frame();
    for (int k = 0; k < 3; ++k) CHECK_EQ_INT(step(c, &f), WC_OK);
    unsigned char* before = snapshot(c);
    float far[16];
    ag_identity(far);
    far[12] = 1e31f;
    f.attachment_transforms = far;
    wc_step_stats ss;
    wc_diag d = {0};
    expect_refused(c, before, wc_cloth_step(c, &f, &ss, &d), &d, WC_ERROR_STEP_FAILED,
                   "(the cloth was restored to its state before the call)");
    free(before);
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);
}

/* The backend's operations come in begin/end groups; a mirror is downloaded before the cloth
 * reads the particles and uploaded after it changed them; carries reach the backend. */
static void test_backend_calls(void) {
    wc_cloth_backend b = recording();
    memset(&g_rec, 0, sizeof g_rec);
    wc_cloth* c = make(&b, 0.0);
    wc_cloth_frame f = frame();
    CHECK_EQ_INT(step(c, &f), WC_OK);
    CHECK_EQ_INT(g_rec.backups, 1);
    CHECK_EQ_INT(g_rec.carries, 0);   /* the object did not move */
    float moved[16];
    ag_transform(moved, 0, 1, 0, 0.3, 0.0, 0.0, 0.0);
    f.object_transform = moved;   /* angular inertia 0: the rotation carries the cloth */
    CHECK_EQ_INT(step(c, &f), WC_OK);
    CHECK_EQ_INT(g_rec.carries, 1);
    CHECK_EQ_INT(g_rec.teleports, 0);
    ag_transform(moved, 0, 1, 0, 0.6, 0.5, 0.0, 0.0);
    f.teleport = 1;
    CHECK_EQ_INT(step(c, &f), WC_OK);
    CHECK_EQ_INT(g_rec.teleports, 1);
    int uploads = g_rec.uploads;
    f.teleport = 0;
    f.reset = 1;   /* the reset state is sent */
    CHECK_EQ_INT(step(c, &f), WC_OK);
    CHECK_EQ_INT(g_rec.uploads, uploads + 1);
    f.reset = 0;

    wc_diag d = {0};
    int downloads = g_rec.downloads;
    unsigned char* snap = snapshot(c);
    CHECK_EQ_INT(g_rec.downloads, downloads + 1);
    CHECK_EQ_INT(wc_cloth_restore(c, &g_stamp, snap, c->snapshot_size, &d), WC_OK);
    CHECK_EQ_INT(g_rec.uploads, uploads + 2);
    wc_cloth_attachment_def a[1] = {{g_top, N, g_identity, g_no_axis}};
    CHECK_EQ_INT(wc_cloth_set_attachments(c, a, 1, "attachments", &d), WC_OK);
    CHECK_EQ_INT(g_rec.downloads, downloads + 2);
    int crossings = -1;
    double deepest = -1.0;
    CHECK_EQ_INT(wc_cloth_check_collisions(c, &crossings, &deepest, &d), WC_OK);
    CHECK_EQ_INT(g_rec.downloads, downloads + 3);
    CHECK(crossings == 0 && deepest >= 0.0);
    float* pos = malloc(3 * sizeof(float) * (size_t)c->n_host);
    CHECK_EQ_INT(wc_cloth_vertices(c, 1, pos, NULL, &d), WC_OK);
    free(pos);

    float far[16];
    ag_identity(far);
    far[12] = 1e31f;
    f.attachment_transforms = far;
    wc_step_stats ss;
    CHECK_EQ_INT(wc_cloth_step(c, &f, &ss, &d), WC_ERROR_STEP_FAILED);
    CHECK_EQ_INT(g_rec.restores, 1);

    CHECK_EQ_INT(g_rec.misplaced, 0);
    CHECK_EQ_INT(g_rec.begins, g_rec.ends);
    CHECK(!g_rec.inside);
    free(snap);
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);
}

/* A batch on a backend that is not concurrent (as the GPU's) runs in one begin/end group, one
 * cloth after the other; a cloth whose frame fails is rolled back alone, with its own message. */
static void test_batch_one_group(void) {
    wc_cloth_backend b = recording();
    b.concurrent = 0;
    memset(&g_rec, 0, sizeof g_rec);
    wc_cloth* c[3] = {make(&b, 0.0), make(&b, 0.0), make(&b, 0.0)};
    unsigned char* before = snapshot(c[1]);
    float far[16];
    ag_identity(far);
    far[12] = 1e31f;
    wc_cloth_batch_item items[3];
    memset(items, 0, sizeof items);
    for (int k = 0; k < 3; ++k) {
        items[k].cloth = c[k];
        items[k].frame = frame();
        items[k].index = k;
    }
    items[1].frame.attachment_transforms = far;   /* beyond the outputs' range: rolled back */
    int begins = g_rec.begins;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_cloth_step_batch(items, 3, &d), WC_OK);
    CHECK_EQ_INT(g_rec.begins, begins + 1);
    CHECK_EQ_INT(g_rec.ends, g_rec.begins);
    CHECK_EQ_INT(g_rec.misplaced, 0);
    for (int k = 0; k < 3; ++k) {
        CHECK_EQ_INT(items[k].index, k);   /* not reordered: one after the other */
        CHECK_EQ_INT(items[k].status, k == 1 ? WC_ERROR_STEP_FAILED : WC_OK);
        CHECK_EQ_INT(c[k]->state->frame, k == 1 ? 0 : 1);
    }
    CHECK(strstr(items[1].diag.message, "(the cloth was restored to its state before the call)") != NULL);
    unsigned char* after = snapshot(c[1]);
    CHECK(memcmp(before, after, c[1]->snapshot_size) == 0);
    free(before);
    free(after);
    for (int k = 0; k < 3; ++k) CHECK_EQ_INT(wc_cloth_destroy(c[k], &d), WC_OK);
}

/* A begin that fails: its group's cloths are not stepped. */
static wc_status failing_begin(void* device, wc_diag* d) {
    (void)device;
    return wc_fail(d, WC_ERROR_GPU, "the device is gone");
}

/* A batch of cloths on two backends (as an AUTO context's CPU and GPU cloths): one begin/end
 * group per backend, every cloth as it steps alone (bit for bit, against wc_cloth_step on a
 * twin); a group whose begin fails reports it on its own items, changes none of its cloths, and
 * the other group still steps. */
static void test_batch_two_backends(void) {
    wc_cloth_backend b = recording();
    b.concurrent = 0;
    memset(&g_rec, 0, sizeof g_rec);
    /* interleaved: recording, CPU, recording, CPU; twins stepped alone */
    wc_cloth* c[4] = {make(&b, 0.0), make(&wc_cloth_cpu, 0.0), make(&b, 0.5), make(&wc_cloth_cpu, 0.5)};
    wc_cloth* twin[4] = {make(&wc_cloth_cpu, 0.0), make(&wc_cloth_cpu, 0.0), make(&wc_cloth_cpu, 0.5),
                         make(&wc_cloth_cpu, 0.5)};
    float turned[16];
    ag_transform(turned, 0, 1, 0, 0.3, 0.1, 0.0, 0.0);
    wc_cloth_batch_item items[4];
    wc_diag d = {0};
    for (int f = 0; f < 3; ++f) {
        memset(items, 0, sizeof items);
        for (int k = 0; k < 4; ++k) {
            items[k].cloth = c[k];
            items[k].frame = frame();
            items[k].frame.object_transform = f == 2 ? turned : NULL;
            items[k].index = k;
            wc_step_stats st;
            wc_cloth_frame fr = items[k].frame;
            CHECK_EQ_INT(wc_cloth_step(twin[k], &fr, &st, &d), WC_OK);
        }
        int begins = g_rec.begins;
        CHECK_EQ_INT(wc_cloth_step_batch(items, 4, &d), WC_OK);
        CHECK_EQ_INT(g_rec.begins, begins + 1);   /* the recording backend's two cloths: one group */
        CHECK_EQ_INT(g_rec.ends, g_rec.begins);
        wc_cloth_batch_sort_by_index(items, 4);
        for (int k = 0; k < 4; ++k) {
            CHECK(items[k].cloth == c[k]);
            CHECK_EQ_INT(items[k].status, WC_OK);
        }
    }
    CHECK_EQ_INT(g_rec.misplaced, 0);
    for (int k = 0; k < 4; ++k) {
        unsigned char *x = snapshot(c[k]), *y = snapshot(twin[k]);
        CHECK(memcmp(x, y, c[k]->snapshot_size) == 0);
        free(x);
        free(y);
    }

    /* the recording group cannot begin: its cloths stay, the CPU's step */
    unsigned char* before0 = snapshot(c[0]);
    b.begin = failing_begin;
    memset(items, 0, sizeof items);
    for (int k = 0; k < 4; ++k) {
        items[k].cloth = c[k];
        items[k].frame = frame();
        items[k].index = k;
    }
    CHECK_EQ_INT(wc_cloth_step_batch(items, 4, &d), WC_ERROR_GPU);
    CHECK(strstr(d.message, "the device is gone") != NULL);
    wc_cloth_batch_sort_by_index(items, 4);
    for (int k = 0; k < 4; ++k) {
        int failed = k == 0 || k == 2;
        CHECK_EQ_INT(items[k].status, failed ? WC_ERROR_GPU : WC_OK);
        CHECK_EQ_INT(c[k]->state->frame, failed ? 3 : 4);
        if (failed) CHECK(strstr(items[k].diag.message, "the device is gone") != NULL);
    }
    b.begin = rec_begin;
    unsigned char* after0 = snapshot(c[0]);
    CHECK(memcmp(before0, after0, c[0]->snapshot_size) == 0);
    free(before0);
    free(after0);
    for (int k = 0; k < 4; ++k) {
        CHECK_EQ_INT(wc_cloth_destroy(c[k], &d), WC_OK);
        CHECK_EQ_INT(wc_cloth_destroy(twin[k], &d), WC_OK);
    }
}

/* Creation in two calls (a caller choosing the backend by the model) gives wc_cloth_create's
 * cloth; a cloth with its model only, or whose second call failed, is destroyed whole. */
static void test_create_in_two_calls(void) {
    wc_cloth_attachment_def att[1];
    wc_cloth_collider_def col[1];
    wc_cloth_def def = sheet_def(att, col);
    wc_allocator a = {0};
    wc_diag d = {0};
    wc_cloth* whole = make(&wc_cloth_cpu, 1.0);
    wc_cloth* c = NULL;
    CHECK_EQ_INT(wc_cloth_create_model(&c, &def, &a, &d), WC_OK);
    CHECK(c && c->model.n_particles == N * N && c->state == NULL && c->backend == NULL);
    CHECK_EQ_INT(wc_cloth_create_rest(c, &def, &wc_cloth_cpu, NULL, &d), WC_OK);
    unsigned char *x = snapshot(c), *y = snapshot(whole);
    CHECK(c->snapshot_size == whole->snapshot_size && memcmp(x, y, c->snapshot_size) == 0);
    free(x);
    free(y);
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);
    CHECK_EQ_INT(wc_cloth_destroy(whole, &d), WC_OK);

    CHECK_EQ_INT(wc_cloth_create_model(&c, &def, &a, &d), WC_OK);   /* the model only */
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);

    float far[16];
    ag_identity(far);
    far[12] = 1e31f;
    def.transform = far;   /* the second call refuses it: beyond the outputs' range */
    CHECK_EQ_INT(wc_cloth_create_model(&c, &def, &a, &d), WC_OK);
    CHECK_EQ_INT(wc_cloth_create_rest(c, &def, &wc_cloth_cpu, NULL, &d), WC_ERROR_OUT_OF_RANGE);
    CHECK(strstr(d.message, "beyond the") != NULL);
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);

    /* a mesh the first call refuses: nothing made */
    def = sheet_def(att, col);
    def.mesh.n_faces = 0;
    c = (wc_cloth*)&a;
    CHECK(wc_cloth_create_model(&c, &def, &a, &d) != WC_OK);
    CHECK(c == NULL);
}

static void test_tables(void) {
    const wc_cloth_backend* tables[2] = {&wc_cloth_cpu, NULL};
#ifdef WEFT_TEST_HAVE_GPU
    tables[1] = &wg_cloth_backend;
    CHECK(wg_cloth_backend.mirror == 1);
    CHECK(wg_cloth_backend.concurrent == 0);   /* one GL context: a batch's cloths in turn */
    wc_backend_defaults g;
    const wc_defaults_query gq = {16, 0, WC_INTEGRATOR_BE};
    wg_cloth_backend.defaults(NULL, &gq, &g);   /* no device: fragment passes, block Jacobi */
    CHECK_EQ_INT(g.preconditioner, WC_PRECOND_BLOCK_JACOBI);
    CHECK(g.newton_forcing == 1e-2);   /* at every size */
    CHECK(g.tolerance == 1e-4);        /* at every size */
    CHECK_EQ_INT(g.newton_iterations, 2);   /* the CPU's method */
    CHECK_EQ_INT(g.line_search, 1);
    CHECK_EQ_INT(g.garment_self_collision, 1);
#endif
    for (int t = 0; t < 2 && tables[t]; ++t) {
        const wc_cloth_backend* b = tables[t];
        CHECK(b->name && b->device_create && b->device_destroy && b->defaults && b->begin && b->end && b->create &&
              b->supports &&
              b->destroy && b->step_frame && b->backup && b->restore_backup && b->carry && b->download &&
              b->upload && b->max_abs && b->output && b->write_gl && b->stats && b->read_gl &&
              b->mesh_pull);
    }
    wc_backend_defaults cpu;
    /* below WC_CPU_IC0_BELOW particles IC(0) with forcing 0, the multigrid with 1e-2 from it up;
       with backward Euler the tolerance 1e-3 at both sizes (1e-2 and 1e-4 where the def names a
       preconditioner) */
    for (int named = 0; named < 2; ++named) {
        const wc_defaults_query below = {WC_CPU_IC0_BELOW - 1, named, WC_INTEGRATOR_BE};
        wc_cloth_cpu.defaults(NULL, &below, &cpu);
        CHECK_EQ_INT(cpu.preconditioner, WC_PRECOND_IC0);
        CHECK(cpu.newton_forcing == (named ? 1e-2 : 0.0));
        CHECK(cpu.tolerance == (named ? 1e-4 : 1e-3));
    }
    /* the second-order integrators keep 1e-4 at both sizes (their error is not the time step's alone) */
    for (int integ = WC_INTEGRATOR_BDF2; integ <= WC_INTEGRATOR_TRBDF2; ++integ)
        for (int size = 0; size < 2; ++size) {
            const wc_defaults_query second = {WC_CPU_IC0_BELOW - 1 + size, 0, (wc_integrator)integ};
            wc_cloth_cpu.defaults(NULL, &second, &cpu);
            CHECK_EQ_INT(cpu.preconditioner, size ? WC_PRECOND_AMG : WC_PRECOND_IC0);
            CHECK(cpu.newton_forcing == (size ? 1e-2 : 0.0));
            CHECK(cpu.tolerance == 1e-4);
        }
    const wc_defaults_query at_named = {WC_CPU_IC0_BELOW, 1, WC_INTEGRATOR_BE};
    wc_cloth_cpu.defaults(NULL, &at_named, &cpu);
    CHECK(cpu.tolerance == 1e-4);   /* a named preconditioner keeps 1e-4 from the threshold up too */
    const wc_defaults_query at = {WC_CPU_IC0_BELOW, 0, WC_INTEGRATOR_BE};
    wc_cloth_cpu.defaults(NULL, &at, &cpu);
    CHECK(cpu.newton_forcing == 1e-2);
    CHECK(cpu.tolerance == 1e-3);
    CHECK_EQ_INT(cpu.preconditioner, WC_PRECOND_AMG);
    const wc_defaults_query big = {WC_CPU_LOOSE_BELOW, 0, WC_INTEGRATOR_BE};
    const wc_defaults_query under = {WC_CPU_LOOSE_BELOW - 1, 0, WC_INTEGRATOR_BE};
    wc_backend_defaults bd, ud;
    wc_cloth_cpu.defaults(NULL, &big, &bd);
    wc_cloth_cpu.defaults(NULL, &under, &ud);
    CHECK(bd.tolerance == 1e-4 && ud.tolerance == 1e-3);   /* 1e-3 to the sizes measured only */
    CHECK_EQ_INT(bd.preconditioner, WC_PRECOND_AMG);
    CHECK_EQ_INT(cpu.newton_iterations, 2);
    CHECK_EQ_INT(cpu.line_search, 1);
    CHECK_EQ_INT(cpu.garment_self_collision, 1);
    CHECK(wc_cloth_cpu.mirror == 0);
    CHECK(wc_cloth_cpu.concurrent == 1);
    void* device = (void*)&cpu;
    int software = 1;
    char info[64];
    wc_device_desc dd;
    memset(&dd, 0, sizeof dd);
    CHECK_EQ_INT(wc_cloth_cpu.device_create(&dd, &device, &software, info, sizeof info), WC_OK);
    CHECK(device == NULL && software == 0);
    wc_cloth* c = make(&wc_cloth_cpu, 1.0);
    wc_backend_stats s = {1, 1};
    wc_cloth_backend_stats(c, &s);
    CHECK(s.device_bytes == 0 && s.passes == 0);
    wc_diag d = {0};
    CHECK_EQ_INT(wc_cloth_destroy(c, &d), WC_OK);
}

static void test_xform_and_serial(void) {
    float m[16];
    ag_transform(m, 0, 0, 1, 0.7, 1.0, 2.0, 3.0);
    wc_xform x, inv;
    wc_xform_from_floats(&x, m);
    CHECK(x.t[0] == 1.0 && x.t[1] == 2.0 && x.t[2] == 3.0 && x.R[1] == (double)m[4]);
    wc_xform_inverse(&x, &inv);
    double p[3] = {0.3, -0.2, 5.0}, q[3], back[3];
    wc_xform_point(&x, p, q);
    wc_xform_point(&inv, q, back);
    for (int k = 0; k < 3; ++k) CHECK_NEAR(back[k], p[k], 1e-12);
    double Rc[9];
    CHECK_EQ_INT(wc_rotation_fraction(x.R, 1.0, Rc), 1);
    CHECK(memcmp(Rc, x.R, sizeof Rc) == 0);   /* the whole rotation: the host's matrix itself */
    CHECK_EQ_INT(wc_rotation_fraction(x.R, 0.0, Rc), 0);
    CHECK(Rc[0] == 1.0 && Rc[1] == 0.0 && Rc[4] == 1.0);

    unsigned char buf[32];
    int a = -5;
    long long b = 1LL << 40;
    wc_serial w = wc_serial_writer(buf, 4);
    wc_serial_i32(&w, &a);
    wc_serial_i64(&w, &b);
    CHECK_EQ_INT(w.off, 16);
    wc_serial k = wc_serial_counter(4);
    wc_serial_i32(&k, &a);
    wc_serial_i64(&k, &b);
    CHECK_EQ_INT(k.off, 16);
    int a2 = 0;
    long long b2 = 0;
    wc_serial r = wc_serial_reader(buf, 4);
    CHECK(wc_serial_reading(&r) && !wc_serial_reading(&w));
    wc_serial_i32(&r, &a2);
    wc_serial_i64(&r, &b2);
    CHECK(a2 == -5 && b2 == b);
}

int main(void) {
    ag_grid(&g_mesh, N, 1.0, 1.0, 1, 0);
    ag_identity(g_identity);
    ag_transform(g_sphere_at, 1, 0, 0, 0.0, 0.0, -0.5, 0.3);
    RUN_TEST(test_snapshot_round_trip);
    RUN_TEST(test_bad_inputs);
    RUN_TEST(test_create_refused);
    RUN_TEST(test_failed_frame_rolls_back);
    RUN_TEST(test_backend_calls);
    RUN_TEST(test_batch_one_group);
    RUN_TEST(test_batch_two_backends);
    RUN_TEST(test_create_in_two_calls);
    RUN_TEST(test_tables);
    RUN_TEST(test_xform_and_serial);
    ag_free(&g_mesh);
    return TEST_SUMMARY();
}
