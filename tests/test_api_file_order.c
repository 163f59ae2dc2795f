/* Results of a file mesh come back in the file's own vertex order: a 6 x 6 sheet whose `v` lines
 * are shuffled (faces renumbered to match) reports vertex i at the file's vertex i, through the
 * C API (against the same mesh given as host arrays in the file's order, an independent path) and
 * through `weft run --out`; duplicate `v` lines at one position (a seam) share a particle. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_support.h"
#include "weft/weft.h"

#define N 6
#define NV (N * N)
#define NQ ((N - 1) * (N - 1))

static int perm[NV];       /* file line k holds grid vertex perm[k] */
static float file_pos[NV][3];
static int file_quads[NQ][4];

/* The shuffled sheet (0.2 m spacing in x and z, y = 0) written as OBJ text. */
static const char* write_shuffled_sheet(void) {
    for (int i = 0; i < NV; ++i) perm[i] = i;
    unsigned s = 12345u;
    for (int i = NV - 1; i > 0; --i) {   /* Fisher-Yates with a fixed LCG */
        s = s * 1103515245u + 12345u;
        int j = (int)((s >> 8) % (unsigned)(i + 1));
        int t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    int where[NV];
    for (int k = 0; k < NV; ++k) where[perm[k]] = k;
    static char text[8192];
    size_t len = 0;
    for (int k = 0; k < NV; ++k) {
        int g = perm[k];
        file_pos[k][0] = 0.2f * (float)(g % N);
        file_pos[k][1] = 0.0f;
        file_pos[k][2] = 0.2f * (float)(g / N);
        len += (size_t)snprintf(text + len, sizeof text - len, "v %.9g %.9g %.9g\n",
                                (double)file_pos[k][0], (double)file_pos[k][1], (double)file_pos[k][2]);
    }
    for (int j = 0, q = 0; j + 1 < N; ++j)
        for (int i = 0; i + 1 < N; ++i, ++q) {
            int a = j * N + i, c[4] = {a, a + 1, a + N + 1, a + N};
            for (int k = 0; k < 4; ++k) file_quads[q][k] = where[c[k]];
            len += (size_t)snprintf(text + len, sizeof text - len, "f %d %d %d %d\n",
                                    file_quads[q][0] + 1, file_quads[q][1] + 1, file_quads[q][2] + 1,
                                    file_quads[q][3] + 1);
        }
    return ts_write_tmp("file_order_sheet.obj", text);
}

static weft_context* new_context(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.backend = WEFT_BACKEND_CPU;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

/* A cloth of the sheet (file or host arrays) pinned at the file's vertices 0 and 1, scale 0.5. */
static weft_cloth make_sheet(weft_context* ctx, const char* path) {
    static int sizes[NQ];
    for (int q = 0; q < NQ; ++q) sizes[q] = 4;
    weft_cloth_def d = weft_default_cloth_def();
    if (path) {
        d.mesh.path = path;
    } else {
        d.mesh.positions = &file_pos[0][0];
        d.mesh.n_vertices = NV;
        d.mesh.face_sizes = sizes;
        d.mesh.n_faces = NQ;
        d.mesh.indices = &file_quads[0][0];
    }
    d.unit_scale = 0.5;
    static const int pinned[2] = {0, 1};
    weft_attachment_def a = weft_default_attachment_def();
    a.vertices = pinned;
    a.n_vertices = 2;
    d.attachments = &a;
    d.n_attachments = 1;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &cloth), WEFT_OK);
    return cloth;
}

static void get(weft_context* ctx, weft_cloth cloth, float* pos, int n) {
    int count = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, pos, NULL, n, &count), WEFT_OK);
    CHECK_EQ_INT(count, n);
}

static const char* sheet_path;

static void test_api_order(void) {
    const char* path = sheet_path;
    weft_context* ctx = new_context();
    weft_cloth file = make_sheet(ctx, path), arrays = make_sheet(ctx, NULL);
    float a[NV * 3], b[NV * 3];
    get(ctx, file, a, NV);   /* frame 0: the file's own positions times unit_scale */
    double worst = 0.0;
    for (int v = 0; v < NV; ++v)
        for (int k = 0; k < 3; ++k) worst = fmax(worst, fabs(a[3 * v + k] - 0.5 * file_pos[v][k]));
    CHECK(worst < 1e-7);
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, path, NULL, 0.5, &md), WEFT_OK);
    CHECK_EQ_INT(md.n_vertices, NV);
    for (int v = 0; v < md.n_vertices && v < NV; ++v)
        for (int k = 0; k < 3; ++k) CHECK_NEAR(md.positions[3 * v + k], 0.5 * file_pos[v][k], 1e-7);
    for (int c = 0; c < 4 * NQ && md.n_faces == NQ; ++c) CHECK_EQ_INT(md.indices[c], (&file_quads[0][0])[c]);
    weft_mesh_free(ctx, &md);
    for (int f = 1; f <= 5; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / 30.0;
        CHECK_EQ_INT(weft_cloth_step(ctx, file, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, arrays, &fr, NULL), WEFT_OK);
        get(ctx, file, a, NV);
        get(ctx, arrays, b, NV);
        double d = 0.0;
        for (int i = 0; i < 3 * NV; ++i) d = fmax(d, fabs(a[i] - b[i]));
        CHECK(d < 1e-6);   /* host arrays in the file's order: the same vertex i */
        for (int v = 0; v < 2; ++v)   /* the pins hold the file's vertices 0 and 1 */
            for (int k = 0; k < 3; ++k) CHECK_NEAR(a[3 * v + k], 0.5 * file_pos[v][k], 1e-6);
    }
    CHECK(a[3 * 2 + 1] < -0.01 || a[3 * 3 + 1] < -0.01);   /* the rest fell */
    weft_context_destroy(ctx);
}

/* Two `v` lines at one position (a seam the file splits) and an unused `v` line: every line is a
 * host vertex; the twins report the same position, the unused one its rest position. */
static void test_seam_twins(void) {
    const char* path = ts_write_tmp("file_order_twins.obj",
                                    "v 1 0 0\nv 0 0 0\nv 9 9 9\nv 0 0 1\nv 1 0 1\nv 1 0 0\nv 2 0 0\nv 2 0 1\n"
                                    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                    "f 2/1 1/2 5/3 4/4\nf 6/1 7/2 8/3 5/4\n");
    weft_context* ctx = new_context();
    weft_cloth_def d = weft_default_cloth_def();
    d.mesh.path = path;
    static const int pinned[2] = {1, 3};   /* the x = 0 edge */
    weft_attachment_def a = weft_default_attachment_def();
    a.vertices = pinned;
    a.n_vertices = 2;
    d.attachments = &a;
    d.n_attachments = 1;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &cloth), WEFT_OK);
    weft_import_report r;
    CHECK_EQ_INT(weft_cloth_get_report(ctx, cloth, &r), WEFT_OK);
    CHECK_EQ_INT(r.source_vertices, 8);
    CHECK_EQ_INT(r.welded_vertices, 1);
    CHECK_EQ_INT(r.unused_vertices, 1);
    CHECK_EQ_INT(r.particles, 6);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 30.0;
    for (int f = 0; f < 3; ++f) CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_OK);
    float p[8 * 3];
    get(ctx, cloth, p, 8);
    for (int k = 0; k < 3; ++k) CHECK_NEAR(p[0 + k], p[15 + k], 0.0);   /* v 1 and v 6 */
    CHECK(p[1] < -0.01);                                                 /* and they fell */
    CHECK_NEAR(p[6], 9.0, 0.0);                                          /* the unused v 3 */
    CHECK_NEAR(p[3 + 0], 0.0, 1e-6);                                     /* pinned v 2 */
    CHECK_NEAR(p[9 + 2], 1.0, 1e-6);                                     /* pinned v 4 */
    weft_context_destroy(ctx);
}

/* `weft run --out`: frame 0 of every OBJ frame is the file itself, vertex by vertex. */
static void test_cli_frames(void) {
    const char* path = sheet_path;
    char scene[1024], args[2048], frame[1024];
    snprintf(scene, sizeof scene, "{\"mesh\": {\"file\": \"%s\", \"scale\": 0.5},"
             " \"pins\": [{\"vertices\": [0, 1]}], \"time\": {\"fps\": 30, \"frames\": 2}}", path);
    const char* json = ts_write_tmp("file_order_scene.json", scene);
    snprintf(args, sizeof args, "run '%s' --quiet --out '%s'", json, ts_tmp_path("file_order_out"));
    static ts_cli_result r;
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc) fprintf(stderr, "%s\n", r.err);
    for (int f = 1; f <= 2; ++f) {
        snprintf(frame, sizeof frame, "%s/frame_%04d.obj", ts_tmp_path("file_order_out"), f);
        FILE* fp = fopen(frame, "r");
        CHECK(fp != NULL);
        if (!fp) return;
        char line[256];
        int v = 0;
        double worst = 0.0;
        while (fgets(line, sizeof line, fp)) {
            double x, y, z;
            if (sscanf(line, "v %lf %lf %lf", &x, &y, &z) != 3) continue;
            if (v < NV) {   /* one frame's fall is under 0.05 m; a permutation is >= 0.1 m */
                worst = fmax(worst, fabs(x - 0.5 * file_pos[v][0]));
                worst = fmax(worst, fabs(z - 0.5 * file_pos[v][2]));
                worst = fmax(worst, fabs(y) > 0.05 ? 1.0 : 0.0);
                if (v < 2) CHECK(fabs(y) < 1e-6);   /* the pinned ones */
            }
            ++v;
        }
        fclose(fp);
        CHECK_EQ_INT(v, NV);
        CHECK(worst < 0.01);
    }
}

/* Points and lines among the faces, one of them the file's last line: only the polygons count,
 * in file order, over the file's v lines (a line's corners are read before it is known not to be
 * a polygon: they must not be kept). */
static void test_lines_among_faces(void) {
    const char* path = ts_write_tmp("file_order_lines.obj",
                                    "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nl 1 2\nf 1 2\n"
                                    "f 4 3 2\nf 1\nf 1 4 3\nf 2 3\n");
    weft_context* ctx = new_context();
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, path, NULL, 1.0, &md), WEFT_OK);
    CHECK_EQ_INT(md.n_vertices, 4);
    CHECK_EQ_INT(md.n_faces, 2);
    static const int want[6] = {3, 2, 1, 0, 3, 2};
    for (int c = 0; c < 6 && md.n_faces == 2; ++c) CHECK_EQ_INT(md.indices[c], want[c]);
    for (int k = 0; k < 3; ++k) CHECK_NEAR(md.positions[3 * 2 + k], k == 1 ? 0.0 : 1.0, 0.0);
    weft_mesh_free(ctx, &md);
    weft_context_destroy(ctx);
}

int main(void) {
    sheet_path = write_shuffled_sheet();
    RUN_TEST(test_api_order);
    RUN_TEST(test_seam_twins);
    RUN_TEST(test_cli_frames);
    RUN_TEST(test_lines_among_faces);
    return TEST_SUMMARY();
}
