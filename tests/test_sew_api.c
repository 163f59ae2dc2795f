/* Sewing through the public API (weft_cloth_def's sew_distance, seams and seam_close_time,
 * weft_cloth_info's n_seams and n_panels, validation, snapshots), scene files (mesh.sew_distance,
 * mesh.seams, mesh.seam_close_time), `weft inspect --sew-distance` (text and JSON), and the
 * Codim-IPC garment of /work/shared when present (skipped otherwise). */
#include <stdlib.h>
#include "check.h"
#include "scene.h"
#include "sew_tube.h"
#include "test_support.h"
#include "weft/weft.h"

/* ---- public API: info, validation, snapshots ------------------------------------------------ */

typedef struct api_tube {
    float* pos;
    tube t;
} api_tube;

static weft_cloth_def api_def(api_tube* at) {
    tube_make(&at->t);
    at->pos = malloc(sizeof(float) * 3 * (size_t)at->t.nv);
    for (int i = 0; i < 3 * at->t.nv; ++i) at->pos[i] = (float)at->t.pos[i];
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = at->pos;
    def.mesh.n_vertices = at->t.nv;
    def.mesh.face_sizes = at->t.sizes;
    def.mesh.n_faces = at->t.nf;
    def.mesh.indices = at->t.idx;
    return def;
}

static void test_api(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    if (!ctx) return;
    api_tube at;
    weft_cloth_def def = api_def(&at);
    def.sew_distance = SEW;
    weft_cloth sewn = {0}, plain = {0}, bad = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &sewn), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, sewn, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_seams, TUBE_SEAMS);
    CHECK_EQ_INT(info.n_panels, 1);

    /* refused: NaN, negative, count < 0, NULL list, index out of range, a vertex to itself */
    int sa[1] = {0}, sb[1] = {at.t.na_verts}, out[1] = {at.t.nv}, self[1] = {0};
    struct { double sew; int n; const int *a, *b; weft_status want; const char* word; } cases[] = {
        {NAN, 0, NULL, NULL, WEFT_ERROR_NONFINITE, "sew_distance"},
        {-1e-3, 0, NULL, NULL, WEFT_ERROR_INVALID_ARGUMENT, "sew_distance"},
        {0.0, -1, sa, sb, WEFT_ERROR_INVALID_ARGUMENT, "n_seams"},
        {0.0, 1, sa, NULL, WEFT_ERROR_INVALID_ARGUMENT, "seam_b is NULL"},
        {0.0, 1, NULL, sb, WEFT_ERROR_INVALID_ARGUMENT, "seam_a is NULL"},
        {0.0, 1, sa, out, WEFT_ERROR_OUT_OF_RANGE, "seam_b[0]"},
        {0.0, 1, out, sb, WEFT_ERROR_OUT_OF_RANGE, "seam_a[0]"},
        {0.0, 1, sa, self, WEFT_ERROR_INVALID_ARGUMENT, "itself"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        weft_cloth_def d2 = def;
        d2.sew_distance = cases[k].sew;
        d2.n_seams = cases[k].n;
        d2.seam_a = cases[k].a;
        d2.seam_b = cases[k].b;
        bad.id = 777;
        CHECK_EQ_INT(weft_cloth_create(ctx, &d2, &bad), cases[k].want);
        CHECK(bad.id == 0);
        CHECK(strstr(weft_context_last_error(ctx), cases[k].word) != NULL);
        printf("  API refused: %s\n", weft_context_last_error(ctx));
    }
    for (int k = 0; k < 2; ++k) {
        weft_cloth_def d2 = def;
        d2.seam_close_time = k ? -0.5 : NAN;
        bad.id = 777;
        CHECK_EQ_INT(weft_cloth_create(ctx, &d2, &bad), k ? WEFT_ERROR_INVALID_ARGUMENT : WEFT_ERROR_NONFINITE);
        CHECK(bad.id == 0);
        CHECK(strstr(weft_context_last_error(ctx), "seam_close_time") != NULL);
    }
    CHECK_NEAR(weft_default_cloth_def().seam_close_time, 0.5, 0);
    /* the sewn cloth is untouched and steps; its snapshot round-trips */
    weft_frame fr = weft_default_frame();
    for (int f = 0; f < 3; ++f) CHECK_EQ_INT(weft_cloth_step(ctx, sewn, &fr, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_info(ctx, sewn, &info), WEFT_OK);
    size_t size = info.snapshot_size;
    unsigned char* snap = malloc(size);
    CHECK_EQ_INT(weft_cloth_save(ctx, sewn, snap, size), WEFT_OK);
    float* v1 = malloc(sizeof(float) * 3 * (size_t)at.t.nv);
    float* v2 = malloc(sizeof(float) * 3 * (size_t)at.t.nv);
    CHECK_EQ_INT(weft_cloth_step(ctx, sewn, &fr, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, sewn, WEFT_SPACE_WORLD, v1, NULL, at.t.nv, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(ctx, sewn, snap, size), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_step(ctx, sewn, &fr, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, sewn, WEFT_SPACE_WORLD, v2, NULL, at.t.nv, NULL), WEFT_OK);
    CHECK(memcmp(v1, v2, sizeof(float) * 3 * (size_t)at.t.nv) == 0);
    /* the same mesh without seams is another model: its snapshot is refused */
    def.sew_distance = 0.0;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &plain), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_info(ctx, plain, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_seams, 0);
    CHECK_EQ_INT(info.n_panels, 2);
    if (info.snapshot_size == size) {
        weft_status st = weft_cloth_restore(ctx, plain, snap, size);
        CHECK(st != WEFT_OK);
        printf("  snapshot of the sewn cloth into the unsewn one: %s\n", weft_context_last_error(ctx));
    }
    free(snap), free(v1), free(v2);
    weft_cloth_destroy(ctx, sewn);
    weft_cloth_destroy(ctx, plain);
    weft_context_destroy(ctx);
    free(at.pos);
    tube_free(&at.t);
}

/* ---- CLI --------------------------------------------------------------------------------------- */

static const char* tube_obj(void) {
    tube t;
    tube_make(&t);
    size_t cap = 64 * (size_t)(t.nv + t.nf) + 64, len = 0;
    char* text = malloc(cap);
    for (int v = 0; v < t.nv; ++v)
        len += (size_t)snprintf(text + len, cap - len, "v %.9g %.9g %.9g\n", t.pos[3 * v], t.pos[3 * v + 1], t.pos[3 * v + 2]);
    for (int f = 0; f < t.nf; ++f)
        len += (size_t)snprintf(text + len, cap - len, "f %d %d %d %d\n", t.idx[4 * f] + 1, t.idx[4 * f + 1] + 1,
                                t.idx[4 * f + 2] + 1, t.idx[4 * f + 3] + 1);
    const char* path = ts_write_tmp("sew_tube.obj", text);
    free(text);
    tube_free(&t);
    return path;
}

/* The integer after "key": in JSON text (-1 when absent). */
static int json_int(const char* text, const char* key) {
    char k[64];
    snprintf(k, sizeof k, "\"%s\":", key);
    const char* p = strstr(text, k);
    return p ? atoi(p + strlen(k)) : -1;
}

static void test_cli_inspect(void) {
    static ts_cli_result r;
    char args[1024], want[64], path[512];
    snprintf(path, sizeof path, "%s", tube_obj()); /* ts_write_tmp's buffer is reused by ts_run_cli */
    snprintf(args, sizeof args, "inspect --sew-distance %g '%s'", SEW, path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    printf("%s", strstr(r.out, "  components") ? strstr(r.out, "  components") : r.out);
    CHECK(strstr(r.out, "seams") != NULL);
    snprintf(want, sizeof want, "%d", TUBE_SEAMS);
    const char* line = strstr(r.out, "  seams");
    CHECK(line && strstr(line, want) && strstr(line, want) < strchr(line, '\n'));
    line = strstr(r.out, "panels after sewing");
    CHECK(line && strchr(line, '1') && strchr(line, '1') < strchr(line, '\n'));
    snprintf(args, sizeof args, "inspect --json --sew-distance %g '%s'", SEW, path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK_EQ_INT(json_int(r.out, "seams"), TUBE_SEAMS);
    CHECK_EQ_INT(json_int(r.out, "panels"), 1);
    /* without the option: nothing sewn */
    snprintf(args, sizeof args, "inspect --json '%s'", path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(json_int(r.out, "seams"), 0);
    CHECK_EQ_INT(json_int(r.out, "panels"), 2);
    /* a bad distance is a usage error */
    snprintf(args, sizeof args, "inspect --sew-distance -1 '%s'", path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--sew-distance") != NULL);
    snprintf(args, sizeof args, "inspect --sew-distance nan '%s'", path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 2);
}

/* The Codim-IPC garment (stitched panels, not welded; README of the folder), when present. */
static void test_shared_garment(void) {
    const char* path = WEFT_SHARED_MESHES "/codimipc_dance/multilayer_garment.obj";
    FILE* f = fopen(path, "rb");
    if (!f) {
        printf("  (skipped: %s not present)\n", path);
        return;
    }
    fclose(f);
    static ts_cli_result r;
    char args[1024];
    snprintf(args, sizeof args, "inspect --json --sew-distance 0.005 '%s'", path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    int seams = json_int(r.out, "seams"), panels = json_int(r.out, "panels"), comps = json_int(r.out, "components");
    printf("  codimipc garment at 5 mm: %d components -> %d panels, %d seams\n", comps, panels, seams);
    CHECK(comps > 1);
    CHECK_EQ_INT(panels, 1);
    CHECK(seams > 100);
}

/* ---- scene files ------------------------------------------------------------------------------ */

static scene S; /* large: off the stack */

static void expect_scene_bad(const char* mesh, const char* word) {
    char text[512];
    snprintf(text, sizeof text, "{\"mesh\": {\"grid\": {\"n\": [3, 3], \"size\": [1, 1]}%s}}", mesh);
    cli_diag d = {0};
    weft_status st = scene_parse(&S, text, strlen(text), "scene.json", &d);
    CHECK(st != WEFT_OK);
    CHECK(strstr(d.message, word) != NULL);
    CHECK(S.seam_a == NULL && S.mesh.positions == NULL);
    printf("  scene refused: %s\n", d.message);
    scene_free(&S);
}

static void test_scene(void) {
    const char* good = "{\"mesh\": {\"grid\": {\"n\": [3, 3], \"size\": [1, 1]}, \"sew_distance\": 0.001, "
                       "\"seam_close_time\": 0.25, \"seams\": [[0, 8], [2, 6]]}}";
    cli_diag d = {0};
    CHECK_EQ_INT(scene_parse(&S, good, strlen(good), "scene.json", &d), WEFT_OK);
    CHECK_NEAR(S.def.sew_distance, 0.001, 0);
    CHECK_NEAR(S.def.seam_close_time, 0.25, 0);
    CHECK_EQ_INT(S.def.n_seams, 2);
    CHECK(S.def.seam_a == S.seam_a && S.def.seam_b == S.seam_b);
    if (S.seam_a && S.seam_b) CHECK(S.seam_a[1] == 2 && S.seam_b[1] == 6 && S.seam_a[0] == 0 && S.seam_b[0] == 8);
    /* the scene's def and mesh as the library takes them: both seams sewn */
    float pos[27];
    for (int i = 0; i < 27; ++i) pos[i] = (float)S.mesh.positions[i];
    weft_cloth_def def = S.def;
    def.mesh.positions = pos;
    def.mesh.n_vertices = S.mesh.n_vertices;
    def.mesh.face_sizes = S.mesh.face_sizes;
    def.mesh.n_faces = S.mesh.n_faces;
    def.mesh.indices = S.mesh.indices;
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    weft_cloth cloth = {0};
    weft_import_report report;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_report(ctx, cloth, &report), WEFT_OK);
    CHECK_EQ_INT(report.seams, 2);
    weft_context_destroy(ctx);
    scene_free(&S);
    /* defaults: no sewing */
    const char* plain = "{\"mesh\": {\"grid\": {\"n\": [3, 3], \"size\": [1, 1]}}}";
    CHECK_EQ_INT(scene_parse(&S, plain, strlen(plain), "scene.json", &d), WEFT_OK);
    CHECK(S.def.sew_distance == 0.0 && S.def.n_seams == 0 && S.seam_a == NULL);
    scene_free(&S);
    expect_scene_bad(", \"sew_distance\": -1", "mesh.sew_distance");
    expect_scene_bad(", \"seam_close_time\": -1", "mesh.seam_close_time");
    expect_scene_bad(", \"seams\": 3", "mesh.seams");
    expect_scene_bad(", \"seams\": [[0, 1, 2]]", "mesh.seams[0]");
    expect_scene_bad(", \"seams\": [[0, 1], [4, 4]]", "mesh.seams[1]");
    expect_scene_bad(", \"seams\": [[0, 1.5]]", "mesh.seams[0]");
    expect_scene_bad(", \"seams\": [[-1, 1]]", "mesh.seams[0]");
    expect_scene_bad(", \"seams\": [[0, 9]]", "outside");
}

int main(void) {
    RUN_TEST(test_api);
    RUN_TEST(test_scene);
    RUN_TEST(test_cli_inspect);
    RUN_TEST(test_shared_garment);
    return TEST_SUMMARY();
}
