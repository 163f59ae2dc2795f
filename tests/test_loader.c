/* host_glue/loader against the built libweft.so, as a host that loads plugins at run time:
 * the function table matches weft.h, a cloth steps through the table (free fall against the
 * backward-Euler closed form, pins holding), bad calls answer with a status and a message and
 * leave the cloth as it was, and the loader refuses a bad path, a library without the symbols and
 * one built for another ABI, with readable messages. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "weft_loader.h"

#define NX 5
#define NZ 5
#define NV (NX * NZ)
#define SPACING 0.1f
#define HEIGHT 1.0f

/* A flat NX x NZ grid of quads in the xz plane at y = HEIGHT. */
typedef struct grid {
    float positions[NV * 3];
    int face_sizes[(NX - 1) * (NZ - 1)];
    int indices[(NX - 1) * (NZ - 1) * 4];
} grid;

static void make_grid(grid* g) {
    for (int k = 0; k < NZ; ++k)
        for (int i = 0; i < NX; ++i) {
            float* p = g->positions + 3 * (k * NX + i);
            p[0] = (float)i * SPACING;
            p[1] = HEIGHT;
            p[2] = (float)k * SPACING;
        }
    int f = 0;
    for (int k = 0; k + 1 < NZ; ++k)
        for (int i = 0; i + 1 < NX; ++i, ++f) {
            int v = k * NX + i;
            g->face_sizes[f] = 4;
            g->indices[4 * f + 0] = v;
            g->indices[4 * f + 1] = v + NX;
            g->indices[4 * f + 2] = v + NX + 1;
            g->indices[4 * f + 3] = v + 1;
        }
}

static weft_cloth_def grid_def(const weft_api* w, const grid* g) {
    weft_cloth_def def = w->weft_default_cloth_def();
    def.mesh.positions = g->positions;
    def.mesh.n_vertices = NV;
    def.mesh.face_sizes = g->face_sizes;
    def.mesh.n_faces = (NX - 1) * (NZ - 1);
    def.mesh.indices = g->indices;
    def.air_drag_normal = 0.0; /* pure gravity: the closed form below is exact */
    def.air_drag_tangent = 0.0;
    return def;
}

typedef struct log_capture {
    char last[512];
    int count;
} log_capture;

static void capture_log(weft_log_level level, const char* message, void* user) {
    log_capture* c = user;
    (void)level;
    snprintf(c->last, sizeof c->last, "%s", message);
    c->count++;
}

static int open_real(weft_api* w) {
    char err[512];
    weft_status s = weft_loader_open(w, WEFT_LIBRARY, err, sizeof err);
    if (s != WEFT_OK) fprintf(stderr, "weft_loader_open: %s\n", err);
    CHECK_EQ_INT(s, WEFT_OK);
    return s == WEFT_OK;
}

static int header_lists_function(const char* name) {
    for (int i = 0; i < weft_loader_function_count(); ++i)
        if (strcmp(weft_loader_function_name(i), name) == 0) return 1;
    return 0;
}

/* Every WEFT_API declaration in weft.h is in the table, and the table has nothing else. */
static void test_table_lists_every_function_of_the_header(void) {
    const char* path = WEFT_SOURCE_DIR "/plugin/include/weft/weft.h";
    FILE* f = fopen(path, "r");
    CHECK(f != NULL);
    if (!f) return;
    char line[1024];
    int declared = 0;
    while (fgets(line, sizeof line, f)) {
        const char* api = strstr(line, "WEFT_API ");
        if (!api || line[0] == '#') continue;
        const char* paren = strchr(api, '(');
        CHECK(paren != NULL);
        if (!paren) continue;
        const char* end = paren;
        while (end > api && end[-1] == ' ') --end;
        const char* start = end;
        while (start > api && (start[-1] == '_' || (start[-1] >= 'a' && start[-1] <= 'z') ||
                               (start[-1] >= '0' && start[-1] <= '9')))
            --start;
        char name[128];
        snprintf(name, sizeof name, "%.*s", (int)(end - start), start);
        if (!header_lists_function(name)) fprintf(stderr, "not in the loader table: %s\n", name);
        CHECK(header_lists_function(name));
        ++declared;
    }
    fclose(f);
    CHECK_EQ_INT(declared, weft_loader_function_count());
    CHECK(weft_loader_function_name(-1) == NULL);
    CHECK(weft_loader_function_name(weft_loader_function_count()) == NULL);
}

static void test_open_resolves_every_function(void) {
    weft_api w;
    if (!open_real(&w)) return;
    CHECK(w.handle != NULL);
#define CHECK_RESOLVED_(ret, name, params) CHECK(w.name != NULL);
    WEFT_LOADER_FUNCTIONS(CHECK_RESOLVED_)
#undef CHECK_RESOLVED_
    weft_version_info v = w.weft_version();
    CHECK_EQ_INT(v.abi, WEFT_ABI);
    CHECK_EQ_INT(v.major, WEFT_VERSION_MAJOR);
    CHECK_EQ_INT(v.minor, WEFT_VERSION_MINOR);
    CHECK(strcmp(w.weft_status_string(WEFT_ERROR_ABI_MISMATCH), "ABI version mismatch") == 0);
    weft_loader_close(&w);
    CHECK(w.handle == NULL && w.weft_version == NULL && w.weft_cloth_step == NULL);
    weft_loader_close(&w); /* closing twice is harmless */
    weft_loader_close(NULL);
}

/* A free cloth with no air drag: every particle follows backward Euler under gravity exactly
 * (springs at rest, uniform velocity: no internal force), so after N frames of h the drop is
 * g h^2 N (N + 1) / 2 and x, z are unchanged. */
static void test_free_fall_through_the_table(void) {
    weft_api w;
    if (!open_real(&w)) return;
    weft_context_def cd = w.weft_default_context_def();
    weft_context* ctx = NULL;
    CHECK_EQ_INT(w.weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    grid g;
    make_grid(&g);
    weft_cloth_def def = grid_def(&w, &g);
    weft_cloth cloth = {0};
    weft_status s = w.weft_cloth_create(ctx, &def, &cloth);
    if (s != WEFT_OK) fprintf(stderr, "weft_cloth_create: %s\n", w.weft_context_last_error(ctx));
    CHECK_EQ_INT(s, WEFT_OK);
    const int frames = 10;
    const double h = 1.0 / 60.0;
    for (int n = 0; n < frames && s == WEFT_OK; ++n) {
        weft_frame fr = w.weft_default_frame();
        fr.dt = h;
        s = w.weft_cloth_step(ctx, cloth, &fr, NULL);
        CHECK_EQ_INT(s, WEFT_OK);
    }
    float pos[NV * 3];
    int count = 0;
    CHECK_EQ_INT(w.weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, pos, NULL, NV, &count),
                 WEFT_OK);
    CHECK_EQ_INT(count, NV);
    const double drop = 9.81 * h * h * frames * (frames + 1) / 2.0;
    for (int v = 0; v < NV; ++v) {
        CHECK_NEAR(pos[3 * v + 0], g.positions[3 * v + 0], 1e-5);
        CHECK_NEAR(pos[3 * v + 1], HEIGHT - drop, 1e-4);
        CHECK_NEAR(pos[3 * v + 2], g.positions[3 * v + 2], 1e-5);
    }
    w.weft_context_destroy(ctx);
    weft_loader_close(&w);
}

/* The row z = 0 pinned to the world: it stays put while the rest swings down, and no spring
 * stretches far (the far row is at most 10 % farther from its pinned column vertex than at rest). */
static void test_pinned_row_holds(void) {
    weft_api w;
    if (!open_real(&w)) return;
    weft_context_def cd = w.weft_default_context_def();
    weft_context* ctx = NULL;
    CHECK_EQ_INT(w.weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    grid g;
    make_grid(&g);
    weft_cloth_def def = grid_def(&w, &g);
    int pinned[NX];
    for (int i = 0; i < NX; ++i) pinned[i] = i;
    weft_attachment_def att = w.weft_default_attachment_def();
    att.vertices = pinned;
    att.n_vertices = NX;
    def.attachments = &att;
    def.n_attachments = 1;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(w.weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(w.weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_vertices, NV);
    CHECK_EQ_INT(info.n_attachments, 1);
    CHECK_EQ_INT(info.n_pinned_particles, NX);
    for (int n = 0; n < 30; ++n) {
        weft_frame fr = w.weft_default_frame();
        fr.dt = 1.0 / 60.0;
        CHECK_EQ_INT(w.weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_OK);
    }
    float pos[NV * 3];
    int count = 0;
    CHECK_EQ_INT(w.weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, pos, NULL, NV, &count),
                 WEFT_OK);
    for (int v = 0; v < NX; ++v)
        for (int c = 0; c < 3; ++c) CHECK_NEAR(pos[3 * v + c], g.positions[3 * v + c], 1e-6);
    for (int i = 0; i < NX; ++i) {
        const float* far = pos + 3 * ((NZ - 1) * NX + i);
        CHECK(far[1] < HEIGHT - 0.1f); /* swung down */
        double dx = far[0] - pos[3 * i], dy = far[1] - pos[3 * i + 1], dz = far[2] - pos[3 * i + 2];
        CHECK(sqrt(dx * dx + dy * dy + dz * dz) < 1.1 * (NZ - 1) * SPACING);
    }
    w.weft_context_destroy(ctx);
    weft_loader_close(&w);
}

/* Bad calls through the table: a status, a message naming the argument, nothing changed. */
static void test_bad_calls_leave_the_cloth_intact(void) {
    weft_api w;
    if (!open_real(&w)) return;
    weft_context_def cd = w.weft_default_context_def();
    weft_context* ctx = NULL;
    CHECK_EQ_INT(w.weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    grid g;
    make_grid(&g);
    weft_cloth_def def = grid_def(&w, &g);
    weft_cloth cloth = {0};
    CHECK_EQ_INT(w.weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    weft_frame fr = w.weft_default_frame();
    fr.dt = 1.0 / 60.0;
    CHECK_EQ_INT(w.weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_OK);
    float before[NV * 3], after[NV * 3];
    int count = 0;
    CHECK_EQ_INT(w.weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, before, NULL, NV, &count),
                 WEFT_OK);

    fr.dt = -1.0;
    CHECK_EQ_INT(w.weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(w.weft_context_last_status(ctx), WEFT_ERROR_INVALID_ARGUMENT);
    const char* msg = w.weft_context_last_error(ctx);
    printf("  step(dt = -1): %s\n", msg);
    CHECK(strstr(msg, "dt") != NULL);

    /* capacity too small: OUT_OF_RANGE and the buffer untouched */
    memset(after, 0x7f, sizeof after);
    float canary = after[0];
    CHECK_EQ_INT(w.weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, after, NULL, NV - 1,
                                           &count),
                 WEFT_ERROR_OUT_OF_RANGE);
    CHECK(after[0] == canary);
    printf("  get_vertices(capacity %d): %s\n", NV - 1, w.weft_context_last_error(ctx));

    /* a forged handle */
    weft_cloth forged = {cloth.id ^ 0x5a5a5a5a00000000ull};
    CHECK_EQ_INT(w.weft_cloth_step(ctx, forged, &fr, NULL), WEFT_ERROR_INVALID_HANDLE);

    CHECK_EQ_INT(w.weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, after, NULL, NV, &count),
                 WEFT_OK);
    CHECK(memcmp(before, after, sizeof before) == 0);
    w.weft_context_destroy(ctx);
    weft_loader_close(&w);
}

/* weft_context_create(WEFT_ABI + 1) through the table: refused with no context. The def is not
 * read at all (under another ABI its layout is unknown), so its logger is not called either. */
static void test_context_abi_mismatch_refused(void) {
    weft_api w;
    if (!open_real(&w)) return;
    log_capture cap = {{0}, 0};
    weft_context_def cd = w.weft_default_context_def();
    cd.log = capture_log;
    cd.log_user = &cap;
    weft_context* ctx = (weft_context*)&cap; /* must come back NULL */
    CHECK_EQ_INT(w.weft_context_create(WEFT_ABI + 1, &cd, &ctx), WEFT_ERROR_ABI_MISMATCH);
    CHECK(ctx == NULL);
    CHECK_EQ_INT(cap.count, 0);
    ctx = (weft_context*)&cap;
    CHECK_EQ_INT(w.weft_context_create(WEFT_ABI - 1, NULL, &ctx), WEFT_ERROR_ABI_MISMATCH);
    CHECK(ctx == NULL);
    /* the same def with the right ABI works */
    CHECK_EQ_INT(w.weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    CHECK(ctx != NULL);
    w.weft_context_destroy(ctx);
    weft_loader_close(&w);
}

static void test_bad_path_refused(void) {
    weft_api w;
    memset(&w, 0xab, sizeof w);
    char err[512];
    const char* path = WEFT_TEST_TMPDIR "/no_such_dir/libweft.so";
    CHECK_EQ_INT(weft_loader_open(&w, path, err, sizeof err), WEFT_ERROR_IO);
    printf("  %s\n", err);
    char want[512];
    snprintf(want, sizeof want, "%s: cannot open: ", path);
    CHECK(strncmp(err, want, strlen(want)) == 0);
    CHECK(strstr(err, "No such file") != NULL); /* dlerror's reason follows */
    CHECK(w.handle == NULL && w.weft_version == NULL);
    /* a short error buffer is truncated and terminated */
    char small[8];
    CHECK_EQ_INT(weft_loader_open(&w, path, small, sizeof small), WEFT_ERROR_IO);
    CHECK(strlen(small) == sizeof small - 1);
    CHECK_EQ_INT(weft_loader_open(&w, path, NULL, 0), WEFT_ERROR_IO);
    CHECK_EQ_INT(weft_loader_open(&w, NULL, err, sizeof err), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err, "path") != NULL);
    CHECK_EQ_INT(weft_loader_open(NULL, WEFT_LIBRARY, err, sizeof err),
                 WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err, "api") != NULL);
}

static void test_library_without_symbols_refused(void) {
    weft_api w;
    char err[512];
    CHECK_EQ_INT(weft_loader_open(&w, WEFT_FIXTURE_NO_SYMBOLS, err, sizeof err),
                 WEFT_ERROR_ABI_MISMATCH);
    printf("  %s\n", err);
    char want[512];
    snprintf(want, sizeof want, "%s: missing symbol weft_version", WEFT_FIXTURE_NO_SYMBOLS);
    CHECK(strcmp(err, want) == 0);
    CHECK(w.handle == NULL);
}

static void test_library_of_another_abi_refused(void) {
    weft_api w;
    char err[512];
    CHECK_EQ_INT(weft_loader_open(&w, WEFT_FIXTURE_OLD_ABI, err, sizeof err),
                 WEFT_ERROR_ABI_MISMATCH);
    printf("  %s\n", err);
    char want[64];
    snprintf(want, sizeof want, ": ABI %d != %d (", WEFT_FIXTURE_ABI, WEFT_ABI);
    CHECK(strstr(err, want) != NULL);
    CHECK(w.handle == NULL && w.weft_cloth_step == NULL);
}

/* Two tables on one library (two hosts in a process): closing one leaves the other working. */
static void test_two_tables_are_independent(void) {
    weft_api a, b;
    if (!open_real(&a)) return;
    if (!open_real(&b)) {
        weft_loader_close(&a);
        return;
    }
    weft_context_def cd = a.weft_default_context_def();
    weft_context* ctx = NULL;
    weft_loader_close(&a);
    CHECK_EQ_INT(b.weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    CHECK(ctx != NULL);
    CHECK_EQ_INT(b.weft_context_last_status(ctx), WEFT_OK);
    b.weft_context_destroy(ctx);
    weft_loader_close(&b);
}

int main(void) {
    RUN_TEST(test_table_lists_every_function_of_the_header);
    RUN_TEST(test_open_resolves_every_function);
    RUN_TEST(test_free_fall_through_the_table);
    RUN_TEST(test_pinned_row_holds);
    RUN_TEST(test_bad_calls_leave_the_cloth_intact);
    RUN_TEST(test_context_abi_mismatch_refused);
    RUN_TEST(test_bad_path_refused);
    RUN_TEST(test_library_without_symbols_refused);
    RUN_TEST(test_library_of_another_abi_refused);
    RUN_TEST(test_two_tables_are_independent);
    return TEST_SUMMARY();
}
