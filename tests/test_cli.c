/* The `weft` command-line tool, run as a user would (WEFT_CLI is its path): inspect --json on
 * small OBJ files this test writes and on the bundled skirt, the one-line error of a file that
 * cannot be imported (exit 1), and usage errors (exit 2). */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_support.h"
#include "weft/weft.h"

static double num(const cJSON* obj, const char* key) {
    const cJSON* item = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(item) ? item->valuedouble : -1e300;
}

static double vec(const cJSON* obj, const char* key, int i) {
    const cJSON* arr = cJSON_GetObjectItemCaseSensitive(obj, key);
    const cJSON* item = cJSON_IsArray(arr) && cJSON_GetArraySize(arr) == 3 ? cJSON_GetArrayItem(arr, i) : NULL;
    return cJSON_IsNumber(item) ? item->valuedouble : -1e300;
}

/* A 2 x 2 quad grid (3 x 3 positions, 0..2 in X and Y) whose quads each have their own UVs, so
 * the importer sees 16 vertices that weld to 9 particles. */
static const char* grid_obj(void) {
    static const char text[] =
        "# 2x2 quads, each with its own vertices and UVs (split at every quad edge)\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\n"
        "v 0 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 1 1 0\nv 2 1 0\nv 2 2 0\nv 1 2 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "f 1/1 2/2 3/3 4/4\n"
        "f 5/1 6/2 7/3 8/4\n"
        "f 9/1 10/2 11/3 12/4\n"
        "f 13/1 14/2 15/3 16/4\n";
    return ts_write_tmp("cli_grid.obj", text);
}

static cJSON* inspect_json(const char* path, const char* extra, ts_cli_result* r) {
    char args[2048];
    snprintf(args, sizeof args, "inspect '%s' --json %s", path, extra);
    ts_run_cli(args, r);
    CHECK_EQ_INT(r->rc, 0);
    CHECK(r->err[0] == '\0');
    cJSON* root = cJSON_Parse(r->out);
    CHECK(cJSON_IsObject(root));
    if (!cJSON_IsObject(root)) fprintf(stderr, "stdout was: %s\nstderr was: %s\n", r->out, r->err);
    return cJSON_IsObject(root) ? root : NULL;
}

static void test_grid_json(void) {
    static ts_cli_result r;
    const char* path = grid_obj();
    cJSON* j = inspect_json(path, "", &r);
    if (!j) return;
    static const char* const keys[] = {
        "file", "particles", "triangles", "source_vertices", "polygons", "points", "lines",
        "edges", "boundary_edges", "non_manifold_edges", "degenerate_triangles",
        "duplicate_faces", "flipped_faces", "unused_vertices", "welded_vertices", "components",
        "boundary_loops", "springs", "bbox_min", "bbox_max", "unit_scale", "weld_distance",
        "warnings"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i) {
        int has = cJSON_HasObjectItem(j, keys[i]);
        CHECK(has);
        if (!has) fprintf(stderr, "  missing key %s\n", keys[i]);
    }
    const cJSON* file = cJSON_GetObjectItemCaseSensitive(j, "file");
    CHECK(cJSON_IsString(file) && strcmp(file->valuestring, path) == 0);
    CHECK_EQ_INT(num(j, "particles"), 9);
    CHECK_EQ_INT(num(j, "triangles"), 8);
    CHECK_EQ_INT(num(j, "source_vertices"), 16);
    CHECK_EQ_INT(num(j, "welded_vertices"), 7);
    CHECK_EQ_INT(num(j, "unused_vertices"), 0);
    CHECK_EQ_INT(num(j, "points"), 0);
    CHECK_EQ_INT(num(j, "lines"), 0);
    const cJSON* polys = cJSON_GetObjectItemCaseSensitive(j, "polygons");
    CHECK(cJSON_IsObject(polys) && cJSON_GetArraySize(polys) == 1);
    CHECK_EQ_INT(num(polys, "4"), 4);
    CHECK_EQ_INT(num(j, "edges"), 16);   /* 12 quad sides + 4 triangulation diagonals */
    CHECK_EQ_INT(num(j, "boundary_edges"), 8);
    CHECK_EQ_INT(num(j, "non_manifold_edges"), 0);
    CHECK_EQ_INT(num(j, "degenerate_triangles"), 0);
    CHECK_EQ_INT(num(j, "duplicate_faces"), 0);
    CHECK_EQ_INT(num(j, "components"), 1);
    CHECK_EQ_INT(num(j, "boundary_loops"), 1);
    const cJSON* springs = cJSON_GetObjectItemCaseSensitive(j, "springs");
    CHECK_EQ_INT(num(springs, "stretch"), 12);
    CHECK_EQ_INT(num(springs, "shear"), 8);
    CHECK_EQ_INT(num(springs, "bend"), 6);
    for (int k = 0; k < 3; ++k) {
        CHECK_NEAR(vec(j, "bbox_min", k), 0.0, 1e-12);
        CHECK_NEAR(vec(j, "bbox_max", k), k < 2 ? 2.0 : 0.0, 1e-12);
    }
    CHECK_NEAR(num(j, "unit_scale"), 1.0, 0.0);
    CHECK(num(j, "weld_distance") > 0 && num(j, "weld_distance") < 1e-3);
    CHECK(cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(j, "warnings")));
    cJSON_Delete(j);
}

/* --scale and --weld-tolerance reach the importer and the model builder. */
static void test_grid_options(void) {
    static ts_cli_result r;
    cJSON* j = inspect_json(grid_obj(), "--scale 0.5 --weld-tolerance=0", &r);
    if (!j) return;
    CHECK_EQ_INT(num(j, "particles"), 16);
    CHECK_EQ_INT(num(j, "welded_vertices"), 0);
    CHECK_EQ_INT(num(j, "components"), 4);
    CHECK_EQ_INT(num(j, "boundary_loops"), 4);
    const cJSON* springs = cJSON_GetObjectItemCaseSensitive(j, "springs");
    CHECK_EQ_INT(num(springs, "stretch"), 16);
    CHECK_EQ_INT(num(springs, "shear"), 8);
    CHECK_EQ_INT(num(springs, "bend"), 0);
    CHECK_NEAR(vec(j, "bbox_max", 0), 1.0, 1e-12);
    CHECK_NEAR(num(j, "unit_scale"), 0.5, 0.0);
    CHECK_NEAR(num(j, "weld_distance"), 0.0, 0.0);
    cJSON_Delete(j);
}

static void test_grid_text(void) {
    static ts_cli_result r;
    char args[2048];
    snprintf(args, sizeof args, "inspect '%s'", grid_obj());
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "particles") != NULL);
    CHECK(strstr(r.out, "stretch") != NULL);
    CHECK(r.err[0] == '\0');
}

/* The bundled sample of the README's main job (see sample_scenes/README.md for the counts). */
static void test_sample_skirt(void) {
    static ts_cli_result r;
    const char* path = WEFT_SOURCE_DIR "/sample_scenes/skirt.obj";
    cJSON* j = inspect_json(path, "", &r);
    if (!j) return;
    CHECK_EQ_INT(num(j, "particles"), 544);
    CHECK_EQ_INT(num(j, "triangles"), 1024);
    CHECK_EQ_INT(num(j, "components"), 1);
    CHECK_EQ_INT(num(j, "boundary_loops"), 2);
    CHECK_EQ_INT(num(j, "boundary_edges"), 64);
    CHECK_EQ_INT(num(j, "non_manifold_edges"), 0);
    CHECK_EQ_INT(num(j, "flipped_faces"), 0);
    const cJSON* springs = cJSON_GetObjectItemCaseSensitive(j, "springs");
    CHECK_EQ_INT(num(springs, "stretch"), 1056);
    CHECK_EQ_INT(num(springs, "shear"), 1024);
    CHECK_EQ_INT(num(springs, "bend"), 1024);
    CHECK_NEAR(vec(j, "bbox_min", 1), 0.4, 1e-6);   /* assimp keeps floats */
    CHECK_NEAR(vec(j, "bbox_max", 1), 1.0, 1e-6);
    cJSON_Delete(j);

    j = inspect_json(path, "--select front", &r);
    if (!j) return;
    CHECK_EQ_INT(num(j, "particles"), 289);
    CHECK_EQ_INT(num(j, "components"), 1);
    cJSON_Delete(j);
}

/* A file that cannot be imported: exit 1, one "weft: ..." line on stderr, nothing on stdout. */
static void expect_import_failure(const char* path) {
    static ts_cli_result r;
    char args[2048];
    snprintf(args, sizeof args, "inspect '%s' --json", path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(r.out[0] == '\0');
    CHECK_EQ_INT(ts_count_lines(r.err), 1);
    CHECK(strncmp(r.err, "weft: ", 6) == 0);
    CHECK(r.err[0] && r.err[strlen(r.err) - 1] == '\n');
    if (ts_count_lines(r.err) != 1) fprintf(stderr, "stderr was: %s\n", r.err);
}

static void test_import_failures(void) {
    expect_import_failure(ts_tmp_path("no_such_file.obj"));
    expect_import_failure(ts_write_tmp("cli_not_a_mesh.obj", "this is not a mesh\n"));
    expect_import_failure(ts_write_tmp("cli_nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"));
}

/* Bad command lines: exit 2, usage on stderr, nothing on stdout. */
static void test_usage_errors(void) {
    static const char* const bad[] = {
        "",
        "frobnicate",
        "inspect",
        "inspect --json",
        "inspect a.obj b.obj",
        "inspect a.obj --bogus",
        "inspect a.obj --scale",
        "inspect a.obj --scale 0",
        "inspect a.obj --scale -1",
        "inspect a.obj --scale abc",
        "inspect a.obj --scale 1x",
        "inspect a.obj --scale nan",
        "inspect a.obj --scale inf",
        "inspect a.obj --scale 1e999",
        "inspect a.obj --weld-tolerance -1e-6",
        "inspect a.obj --weld-tolerance=",
        "inspect a.obj --select",
        "help frobnicate",
    };
    static ts_cli_result r;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        ts_run_cli(bad[i], &r);
        CHECK_EQ_INT(r.rc, 2);
        CHECK(r.out[0] == '\0');
        CHECK(strstr(r.err, "usage:") != NULL);
        if (r.rc != 2) fprintf(stderr, "  args: '%s'\n", bad[i]);
    }
}

static void test_help_and_version(void) {
    static ts_cli_result r;
    ts_run_cli("--help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "inspect") != NULL);
    ts_run_cli("inspect --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--weld-tolerance") != NULL);
    ts_run_cli("help inspect", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--weld-tolerance") != NULL);
    char expected[64];
    snprintf(expected, sizeof expected, "weft %d.%d.%d (ABI %d)\n", WEFT_VERSION_MAJOR,
             WEFT_VERSION_MINOR, WEFT_VERSION_PATCH, WEFT_ABI);
    ts_run_cli("--version", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strcmp(r.out, expected) == 0);
}

int main(void) {
    RUN_TEST(test_grid_json);
    RUN_TEST(test_grid_options);
    RUN_TEST(test_grid_text);
    RUN_TEST(test_sample_skirt);
    RUN_TEST(test_import_failures);
    RUN_TEST(test_usage_errors);
    RUN_TEST(test_help_and_version);
    return TEST_SUMMARY();
}
