/* `weft run`, run as a user would (WEFT_CLI is its path): the bundled hanging sheet for 10 frames
 * writes 10 OBJ frames (every host vertex, every quad) and a stats JSON with every key; the pinned
 * corners stay exactly at their rest positions, the free edge falls about g dt^2 in the first
 * frame, the stats bounding box matches the last frame; moving pins follow start + velocity t;
 * bad scenes exit 1 with one line naming the field (before creating any output); bad command
 * lines exit 2. */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "check.h"
#include "test_support.h"

#define SHEET WEFT_SOURCE_DIR "/sample_scenes/hanging_sheet.json"

static int exists(const char* path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* A fresh, empty scratch folder (removed with its files first). */
static const char* fresh_dir(const char* name) {
    static char path[1024];
    snprintf(path, sizeof path, "%s", ts_tmp_path(name));
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", path);
    CHECK(system(cmd) == 0);
    return path;
}

/* An OBJ frame: its `v` positions and the number of `f` lines. */
typedef struct obj_frame {
    int n_v, n_f;
    double v[3 * 2048];
} obj_frame;

static int read_obj(const char* path, obj_frame* o) {
    o->n_v = o->n_f = 0;
    FILE* f = fopen(path, "r");
    if (!f) return -1;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        if (line[0] == 'v' && line[1] == ' ' && o->n_v < 2048) {
            double* p = o->v + 3 * o->n_v++;
            if (sscanf(line + 2, "%lf %lf %lf", &p[0], &p[1], &p[2]) != 3) p[0] = p[1] = p[2] = NAN;
        } else if (line[0] == 'f' && line[1] == ' ') {
            ++o->n_f;
        }
    }
    fclose(f);
    return 0;
}

static cJSON* read_json(const char* path) {
    static char text[65536];
    ts_read_text(path, text, sizeof text);
    return cJSON_Parse(text);
}

static double num(const cJSON* obj, const char* key) {
    const cJSON* item = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(item) ? item->valuedouble : NAN;
}

static double vec(const cJSON* obj, const char* key, int i) {
    const cJSON* arr = cJSON_GetObjectItemCaseSensitive(obj, key);
    const cJSON* item = cJSON_IsArray(arr) && cJSON_GetArraySize(arr) == 3 ? cJSON_GetArrayItem(arr, i) : NULL;
    return cJSON_IsNumber(item) ? item->valuedouble : NAN;
}

static void check_keys(const cJSON* obj, const char* const* keys, int n, const char* where) {
    for (int i = 0; i < n; ++i) {
        int has = cJSON_HasObjectItem(obj, keys[i]);
        CHECK(has);
        if (!has) fprintf(stderr, "  %s: missing key %s\n", where, keys[i]);
    }
}

static obj_frame frame_a, frame_b;

static void test_hanging_sheet(void) {
    static ts_cli_result r;
    const char* dir = fresh_dir("run_sheet/frames");
    char out_dir[1024], stats[1024], args[4096], path[1200];
    snprintf(out_dir, sizeof out_dir, "%s", dir);
    snprintf(stats, sizeof stats, "%s", ts_tmp_path("run_sheet_stats.json"));
    remove(stats);
    snprintf(args, sizeof args, "run '%s' --frames 10 --out '%s' --stats '%s' --quiet", SHEET, out_dir, stats);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(r.out[0] == '\0');
    CHECK(r.err[0] == '\0');
    if (r.rc != 0) fprintf(stderr, "  stderr: %s\n", r.err);

    /* 10 frames, each with the 32 x 32 host vertices and 31 x 31 quads; no 11th. */
    for (int f = 1; f <= 10; ++f) {
        snprintf(path, sizeof path, "%s/frame_%04d.obj", out_dir, f);
        obj_frame* o = f == 1 ? &frame_a : &frame_b;
        CHECK(read_obj(path, o) == 0);
        CHECK_EQ_INT(o->n_v, 1024);
        CHECK_EQ_INT(o->n_f, 961);
        if (f == 1) continue;
        for (int i = 0; i < 3 * o->n_v; ++i) CHECK(isfinite(o->v[i]));
    }
    snprintf(path, sizeof path, "%s/frame_0011.obj", out_dir);
    CHECK(!exists(path));

    /* The pinned corners, host vertices 992 = (0, 31) and 1023 = (31, 31) of the grid, sit exactly
     * at their rest positions (-0.5, 0, 0.5) and (0.5, 0, 0.5). */
    CHECK(frame_b.v[3 * 992 + 0] == -0.5 && frame_b.v[3 * 992 + 1] == 0.0 && frame_b.v[3 * 992 + 2] == 0.5);
    CHECK(frame_b.v[3 * 1023 + 0] == 0.5 && frame_b.v[3 * 1023 + 1] == 0.0 && frame_b.v[3 * 1023 + 2] == 0.5);
    /* The free edge (z = -0.5, far from the pins, springs at rest) falls by about g dt^2 =
     * 9.81 / 900 m in the first frame (less a little for air drag). */
    for (int i = 0; i < 32; i += 31) {
        CHECK(frame_a.v[3 * i + 1] < -0.0109 * 0.8);
        CHECK(frame_a.v[3 * i + 1] > -0.0109 * 1.05);
    }
    /* ... and keeps falling. */
    CHECK(frame_b.v[3 * 0 + 1] < frame_a.v[3 * 0 + 1] - 0.05);

    cJSON* j = read_json(stats);
    CHECK(cJSON_IsObject(j));
    if (!cJSON_IsObject(j)) return;
    static const char* const keys[] = {
        "frames", "particles", "triangles", "springs", "solver", "substeps", "threads", "ms_per_frame",
        "stage_ms", "iterations", "residual_max", "rollbacks", "halvings", "direct_fallbacks", "failures",
        "nonfinite_outputs", "max_strain", "final_kinetic_energy", "bbox_min", "bbox_max"};
    static const char* const ms_keys[] = {"median", "p95", "mean"};
    static const char* const stage_keys[] = {"forces", "assemble", "solve", "collide", "integrate", "total"};
    static const char* const it_keys[] = {"mean", "max"};
    check_keys(j, keys, (int)(sizeof keys / sizeof keys[0]), "stats");
    const cJSON* ms = cJSON_GetObjectItemCaseSensitive(j, "ms_per_frame");
    check_keys(ms, ms_keys, 3, "ms_per_frame");
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "stage_ms"), stage_keys, 6, "stage_ms");
    const cJSON* it = cJSON_GetObjectItemCaseSensitive(j, "iterations");
    check_keys(it, it_keys, 2, "iterations");
    CHECK_EQ_INT(num(j, "frames"), 10);
    CHECK_EQ_INT(num(j, "particles"), 1024);
    CHECK_EQ_INT(num(j, "triangles"), 2 * 961);
    CHECK(num(j, "springs") > 0);
    const cJSON* solver = cJSON_GetObjectItemCaseSensitive(j, "solver");
    CHECK(cJSON_IsString(solver) && strcmp(solver->valuestring, "pcg") == 0);
    CHECK_EQ_INT(num(j, "substeps"), 1);
    CHECK(num(j, "threads") >= 1);
    CHECK_EQ_INT(num(j, "nonfinite_outputs"), 0);
    CHECK_EQ_INT(num(j, "failures"), 0);
    CHECK(num(ms, "median") > 0 && num(ms, "p95") >= num(ms, "median") && num(ms, "mean") > 0);
    CHECK(num(it, "max") >= 1 && num(it, "mean") >= 1 && num(it, "mean") <= num(it, "max"));
    CHECK(num(j, "final_kinetic_energy") > 0);
    CHECK(num(j, "max_strain") >= 0);
    /* The bounding box of the final positions is that of the last frame's vertices: the same
     * floats (the API's outputs), written with as many digits as each file format needs. */
    for (int k = 0; k < 3; ++k) {
        double lo = INFINITY, hi = -INFINITY;
        for (int v = 0; v < frame_b.n_v; ++v) {
            lo = fmin(lo, frame_b.v[3 * v + k]);
            hi = fmax(hi, frame_b.v[3 * v + k]);
        }
        CHECK((float)vec(j, "bbox_min", k) == (float)lo);
        CHECK((float)vec(j, "bbox_max", k) == (float)hi);
    }
    cJSON_Delete(j);
}

/* Without --quiet: the summary table on stdout, nothing per frame; --solver and --frames override
 * the scene; --frames 0 leaves the rest shape. */
static void test_summary_and_overrides(void) {
    static ts_cli_result r;
    char args[4096], stats[1024];
    snprintf(stats, sizeof stats, "%s", ts_tmp_path("run_override_stats.json"));
    snprintf(args, sizeof args, "run '%s' --frames 2 --solver jacobi --threads 1 --stats '%s'", SHEET, stats);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "ms/frame") != NULL);
    CHECK(strstr(r.out, "1024 particles") != NULL);
    CHECK(ts_count_lines(r.out) < 16);
    CHECK(r.err[0] == '\0');
    cJSON* j = read_json(stats);
    const cJSON* solver = cJSON_GetObjectItemCaseSensitive(j, "solver");
    CHECK(cJSON_IsString(solver) && strcmp(solver->valuestring, "jacobi") == 0);
    CHECK_EQ_INT(num(j, "frames"), 2);
    CHECK_EQ_INT(num(j, "threads"), 1);
    cJSON_Delete(j);

    snprintf(args, sizeof args, "run '%s' --frames=0 --quiet --stats '%s'", SHEET, stats);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    j = read_json(stats);
    CHECK_EQ_INT(num(j, "frames"), 0);
    for (int k = 0; k < 3; ++k) {
        CHECK_NEAR(vec(j, "bbox_min", k), k == 1 ? 0.0 : -0.5, 0.0);
        CHECK_NEAR(vec(j, "bbox_max", k), k == 1 ? 0.0 : 0.5, 0.0);
    }
    CHECK_NEAR(num(j, "final_kinetic_energy"), 0.0, 0.0);
    cJSON_Delete(j);
}

/* A pin with a velocity: its vertex is at rest + velocity t at the end of every frame. A file
 * mesh found next to the scene, and a vertex pinned to a line. */
static void test_moving_pin(void) {
    static ts_cli_result r;
    ts_write_tmp("run_quad.obj", "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 2 0 0\nv 2 0 1\nf 1 2 3 4\nf 2 5 6 3\n");
    const char* scene = ts_write_tmp(
        "run_moving.json",
        "{\"mesh\": {\"file\": \"run_quad.obj\"}, \"gravity\": [0, 0, 0],"
        " \"pins\": [{\"vertices\": [0], \"velocity\": [0, 1, 0]}, {\"vertices\": [3]}],"
        " \"time\": {\"fps\": 10, \"frames\": 5}}");
    char sc[1024], args[4096], path[1200];
    snprintf(sc, sizeof sc, "%s", scene);
    const char* dir = fresh_dir("run_moving");
    snprintf(args, sizeof args, "run '%s' --out '%s' --quiet", sc, dir);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "  stderr: %s\n", r.err);
    for (int f = 1; f <= 5; ++f) {
        snprintf(path, sizeof path, "%s/frame_%04d.obj", dir, f);
        CHECK(read_obj(path, &frame_a) == 0);
        CHECK_EQ_INT(frame_a.n_v, 6);
        CHECK_EQ_INT(frame_a.n_f, 2);
        CHECK_NEAR(frame_a.v[0], 0.0, 1e-12);
        CHECK_NEAR(frame_a.v[1], 0.1 * f, 1e-12);
        CHECK_NEAR(frame_a.v[2], 0.0, 1e-12);
        CHECK(frame_a.v[9] == 0.0 && frame_a.v[10] == 0.0 && frame_a.v[11] == 1.0);
    }
}

/* An invalid scene: exit 1, exactly one "weft: ..." line naming the field, nothing on stdout,
 * and no output folder created (nothing ran). */
static void expect_bad_scene(const char* name, const char* text, const char* field) {
    static ts_cli_result r;
    char sc[1024], args[4096];
    snprintf(sc, sizeof sc, "%s", text ? ts_write_tmp(name, text) : ts_tmp_path(name));
    const char* dir = fresh_dir("run_bad_out");
    snprintf(args, sizeof args, "run '%s' --out '%s' --stats '%s/s.json'", sc, dir, dir);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(r.out[0] == '\0');
    CHECK_EQ_INT(ts_count_lines(r.err), 1);
    CHECK(strncmp(r.err, "weft: ", 6) == 0);
    CHECK(strstr(r.err, field) != NULL);
    CHECK(strstr(r.err, name) != NULL);
    CHECK(!exists(dir));
    if (r.rc != 1 || !strstr(r.err, field)) fprintf(stderr, "  %s: stderr: %s\n", name, r.err);
}

static void test_bad_scenes(void) {
    expect_bad_scene("run_bad_k.json",
                     "{\"mesh\": {\"grid\": {\"n\": [8, 8], \"size\": [1, 1]}},\n"
                     " \"material\": {\"k\": {\"stretch\": -1}}}",
                     "material.k.stretch");
    expect_bad_scene("run_bad_pin.json",
                     "{\"mesh\": {\"grid\": {\"n\": [8, 8], \"size\": [1, 1]}}, \"pins\": [{\"vertices\": [64]}]}",
                     "pins[0].vertices[0]: 64 is out of range (mesh has 64 vertices)");
    expect_bad_scene("run_bad_key.json", "{\"mesh\": {\"grid\": {\"n\": [8, 8], \"size\": [1, 1]}}, \"fps\": 30}",
                     "fps: unknown key");
    expect_bad_scene("run_bad_json.json", "{\"mesh\": ", "invalid JSON");
    expect_bad_scene("run_no_such_scene.json", NULL, "cannot open");
}

/* Bad command lines: exit 2, usage on stderr, nothing on stdout. */
static void test_usage_errors(void) {
    static const char* const bad[] = {
        "run",
        "run --quiet",
        "run a.json b.json",
        "run a.json --solver bogus",
        "run a.json --solver",
        "run a.json --frames -1",
        "run a.json --frames 1.5",
        "run a.json --frames x",
        "run a.json --threads -2",
        "run a.json --out",
        "run a.json --stats=",
        "run a.json --bogus",
    };
    static ts_cli_result r;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        ts_run_cli(bad[i], &r);
        CHECK_EQ_INT(r.rc, 2);
        CHECK(r.out[0] == '\0');
        CHECK(strstr(r.err, "usage: weft run") != NULL);
        if (r.rc != 2) fprintf(stderr, "  args: '%s'\n", bad[i]);
    }
    char args[2048];
    snprintf(args, sizeof args, "run '%s' --solver bogus", SHEET);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bogus") != NULL);
}

static void test_help(void) {
    static ts_cli_result r;
    ts_run_cli("--help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "  run ") != NULL);
    ts_run_cli("run --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--solver") != NULL && strstr(r.out, "--stats") != NULL);
    ts_run_cli("help run", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--frames") != NULL);
}

int main(void) {
    RUN_TEST(test_hanging_sheet);
    RUN_TEST(test_summary_and_overrides);
    RUN_TEST(test_moving_pin);
    RUN_TEST(test_bad_scenes);
    RUN_TEST(test_usage_errors);
    RUN_TEST(test_help);
    return TEST_SUMMARY();
}
