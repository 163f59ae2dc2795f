/* `weft run`, run as a user would (WEFT_CLI is its path): the bundled hanging sheet for 10 frames
 * writes 10 OBJ frames (every host vertex, every quad) and a stats JSON with every key; the pinned
 * corners stay exactly at their rest positions, the free edge falls about g dt^2 in the first
 * frame, the stats bounding box matches the last frame; moving pins follow start + velocity t;
 * bad scenes exit 1 with one line naming the field (before creating any output); bad command
 * lines exit 2; a progress line only on a terminal; --render writes a PNG per frame; the summary
 * and the stats say which backend the cloth got and why (--backend auto). */
#define _XOPEN_SOURCE 700   /* posix_openpt */
#include <cjson/cJSON.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "cli_frames.h"
#include "test_support.h"

#define SHEET WEFT_SOURCE_DIR "/sample_scenes/hanging_sheet.json"

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
    const char* dir = cf_fresh_dir("run_sheet/frames");
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
        CHECK(cf_read_obj(path, o) == 0);
        CHECK_EQ_INT(o->n_v, 1024);
        CHECK_EQ_INT(o->n_f, 961);
        if (f == 1) continue;
        for (int i = 0; i < 3 * o->n_v; ++i) CHECK(isfinite(o->v[i]));
    }
    snprintf(path, sizeof path, "%s/frame_0011.obj", out_dir);
    CHECK(!cf_exists(path));

    /* The pinned corners, host vertices 992 = (0, 31) and 1023 = (31, 31) of the grid, sit exactly
     * at their rest positions (-0.5, 0, 0.5) and (0.5, 0, 0.5). */
    CHECK(frame_b.v[3 * 992 + 0] == -0.5 && frame_b.v[3 * 992 + 1] == 0.0 && frame_b.v[3 * 992 + 2] == 0.5);
    CHECK(frame_b.v[3 * 1023 + 0] == 0.5 && frame_b.v[3 * 1023 + 1] == 0.0 && frame_b.v[3 * 1023 + 2] == 0.5);
    /* The free edge (z = -0.5, far from the pins, springs at rest) falls freely in the first
     * frame: n backward-Euler pieces of dt / n (the step may halve the frame: the flat start
     * overstretches the pinned corners' springs) drop it by g dt^2 (1 + 1/n) / 2, between
     * g dt^2 / 2 and g dt^2 = 9.81 / 900 m (less a little for air drag). */
    for (int i = 0; i < 32; i += 31) {
        CHECK(frame_a.v[3 * i + 1] < -0.0109 * 0.5 * 0.95);
        CHECK(frame_a.v[3 * i + 1] > -0.0109 * 1.05);
    }
    /* ... and keeps falling. */
    CHECK(frame_b.v[3 * 0 + 1] < frame_a.v[3 * 0 + 1] - 0.05);

    cJSON* j = cf_read_json(stats);
    CHECK(cJSON_IsObject(j));
    if (!cJSON_IsObject(j)) return;
    static const char* const keys[] = {
        "frames", "particles", "triangles", "springs", "solver", "substeps", "threads", "ms_per_frame",
        "stage_ms", "iterations", "residual_max", "rollbacks", "halvings", "direct_fallbacks", "failures",
        "nonfinite_outputs", "max_strain", "final_kinetic_energy", "bbox_min", "bbox_max", "self_collision",
        "self_intersections", "max_penetration", "backend", "backend_reason"};
    static const char* const ms_keys[] = {"median", "p95", "mean", "max"};
    static const char* const stage_keys[] = {"forces", "assemble", "solve", "collide", "integrate", "total"};
    static const char* const it_keys[] = {"mean", "max"};
    check_keys(j, keys, (int)(sizeof keys / sizeof keys[0]), "stats");
    const cJSON* ms = cJSON_GetObjectItemCaseSensitive(j, "ms_per_frame");
    check_keys(ms, ms_keys, 4, "ms_per_frame");
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "stage_ms"), stage_keys, 6, "stage_ms");
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "stage_ms_max"), stage_keys, 6, "stage_ms_max");
    /* the self-collision stage and the stage means, which add up; the solves by kind (the hanging
       sheet: no contacts, so no friction pass; Newton steps at most one per substep and solve) */
    static const char* const more_stage_keys[] = {"self_collide", "total"};
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "stage_ms"), more_stage_keys, 2, "stage_ms");
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "stage_ms_mean"), stage_keys, 6, "stage_ms_mean");
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "stage_ms_mean"), more_stage_keys, 2, "stage_ms_mean");
    static const char* const kind_keys[] = {"newton_steps", "energy_steps", "friction_passes"};
    const cJSON* kinds = cJSON_GetObjectItemCaseSensitive(j, "solve_kinds");
    check_keys(kinds, kind_keys, 3, "solve_kinds");
    CHECK_EQ_INT(cf_num(kinds, "friction_passes"), 0);
    CHECK(cf_num(kinds, "energy_steps") <= cf_num(kinds, "newton_steps"));
    CHECK(cf_num(kinds, "newton_steps") < cf_num(j, "solves"));
    static const char* const contact_keys[] = {"max", "final"};
    check_keys(cJSON_GetObjectItemCaseSensitive(j, "contacts"), contact_keys, 2, "contacts");
    const cJSON* backend = cJSON_GetObjectItemCaseSensitive(j, "backend");
    CHECK(cJSON_IsString(backend) && strcmp(backend->valuestring, "cpu") == 0);
    const cJSON* smax = cJSON_GetObjectItemCaseSensitive(j, "stage_ms_max");
    const cJSON* smed = cJSON_GetObjectItemCaseSensitive(j, "stage_ms");
    for (int k = 0; k < 6; ++k) CHECK(cf_num(smax, stage_keys[k]) >= cf_num(smed, stage_keys[k]));
    CHECK(cf_num(ms, "max") >= cf_num(ms, "p95"));
    CHECK_EQ_INT(cf_num(cJSON_GetObjectItemCaseSensitive(j, "contacts"), "max"), 0);   /* no colliders */
    const cJSON* it = cJSON_GetObjectItemCaseSensitive(j, "iterations");
    check_keys(it, it_keys, 2, "iterations");
    CHECK_EQ_INT(cf_num(j, "frames"), 10);
    CHECK_EQ_INT(cf_num(j, "particles"), 1024);
    CHECK_EQ_INT(cf_num(j, "triangles"), 2 * 961);
    CHECK(cf_num(j, "springs") > 0);
    const cJSON* solver = cJSON_GetObjectItemCaseSensitive(j, "solver");
    CHECK(cJSON_IsString(solver) && strcmp(solver->valuestring, "pcg") == 0);
    CHECK_EQ_INT(cf_num(j, "substeps"), 1);
    CHECK(cf_num(j, "threads") >= 1);
    CHECK_EQ_INT(cf_num(j, "nonfinite_outputs"), 0);
    CHECK_EQ_INT(cf_num(j, "failures"), 0);
    /* self-collision off (the default), the last frame's check still made: a hanging sheet
       crosses nothing */
    const cJSON* self = cJSON_GetObjectItemCaseSensitive(j, "self_collision");
    CHECK(cJSON_IsFalse(cJSON_GetObjectItemCaseSensitive(self, "enabled")));
    CHECK(cf_num(self, "thickness") == 0.003);
    CHECK_EQ_INT(cf_num(self, "impacts"), 0);
    CHECK_EQ_INT(cf_num(j, "self_intersections"), 0);
    CHECK(cf_num(j, "max_penetration") == 0.0);
    CHECK(cf_num(ms, "median") > 0 && cf_num(ms, "p95") >= cf_num(ms, "median") && cf_num(ms, "mean") > 0);
    CHECK(cf_num(it, "max") >= 1 && cf_num(it, "mean") >= 1 && cf_num(it, "mean") <= cf_num(it, "max"));
    CHECK(cf_num(j, "final_kinetic_energy") > 0);
    CHECK(cf_num(j, "max_strain") >= 0);
    /* per-frame arrays, one value per frame; their maxima are the run's */
    const cJSON* pf = cJSON_GetObjectItemCaseSensitive(j, "per_frame");
    static const char* const pf_keys[] = {"ms", "rollbacks", "max_strain", "max_iterations", "not_converged",
                                          "self_impacts", "contacts", "self_intersections", "penetration"};
    for (int k = 0; k < 9; ++k) {
        const cJSON* a = cJSON_GetObjectItemCaseSensitive(pf, pf_keys[k]);
        CHECK(cJSON_IsArray(a) && cJSON_GetArraySize(a) == 10);
    }
    double pf_strain = 0, pf_it = 0;
    const cJSON* e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(pf, "max_strain")) pf_strain = fmax(pf_strain, e->valuedouble);
    cJSON_ArrayForEach(e, cJSON_GetObjectItemCaseSensitive(pf, "max_iterations")) pf_it = fmax(pf_it, e->valuedouble);
    CHECK(pf_strain == cf_num(j, "max_strain"));
    /* the last frame's check is the run's */
    const cJSON* pf_x = cJSON_GetObjectItemCaseSensitive(pf, "self_intersections");
    const cJSON* pf_p = cJSON_GetObjectItemCaseSensitive(pf, "penetration");
    CHECK(cJSON_GetArrayItem(pf_x, 9)->valuedouble == cf_num(j, "self_intersections"));
    CHECK(cJSON_GetArrayItem(pf_p, 9)->valuedouble == cf_num(j, "max_penetration"));
    CHECK(pf_it == cf_num(it, "max"));
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

/* Without --quiet: the summary table on stdout (stage medians and maxima), and nothing on stderr:
 * no progress line when stderr is not a terminal; --solver and --frames override the scene;
 * --frames 0 leaves the rest shape. */
static void test_summary_and_overrides(void) {
    static ts_cli_result r;
    char args[4096], stats[1024];
    snprintf(stats, sizeof stats, "%s", ts_tmp_path("run_override_stats.json"));
    snprintf(args, sizeof args, "run '%s' --frames 2 --solver jacobi --threads 1 --stats '%s'", SHEET, stats);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "ms/frame") != NULL);
    CHECK(strstr(r.out, "1024 particles") != NULL);
    CHECK(strstr(r.out, "  median") != NULL && strstr(r.out, "  max") != NULL && strstr(r.out, "integrate") != NULL);
    CHECK(strstr(r.out, "contacts") != NULL && strstr(r.out, "direct fallbacks") != NULL);
    CHECK(ts_count_lines(r.out) < 16);
    CHECK(strstr(r.out, "\nbackend       cpu: asked for (weft_context_def.backend CPU)\n") != NULL);
    CHECK(r.err[0] == '\0');   /* stderr is a file here: no progress line */
    cJSON* j = cf_read_json(stats);
    const cJSON* solver = cJSON_GetObjectItemCaseSensitive(j, "solver");
    CHECK(cJSON_IsString(solver) && strcmp(solver->valuestring, "jacobi") == 0);
    CHECK_EQ_INT(cf_num(j, "frames"), 2);
    CHECK_EQ_INT(cf_num(j, "threads"), 1);
    cJSON_Delete(j);

    snprintf(args, sizeof args, "run '%s' --frames=0 --quiet --stats '%s'", SHEET, stats);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    j = cf_read_json(stats);
    CHECK_EQ_INT(cf_num(j, "frames"), 0);
    for (int k = 0; k < 3; ++k) {
        CHECK_NEAR(vec(j, "bbox_min", k), k == 1 ? 0.0 : -0.5, 0.0);
        CHECK_NEAR(vec(j, "bbox_max", k), k == 1 ? 0.0 : 0.5, 0.0);
    }
    CHECK_NEAR(cf_num(j, "final_kinetic_energy"), 0.0, 0.0);
    CHECK(cf_num(j, "newton_forcing") == 1e-2);   /* the 1,024-particle sheet's default */
    CHECK(cf_num(j, "tolerance") == 1e-3);        /* and its tolerance (backward Euler: 1e-3 at every size) */
    cJSON_Delete(j);
    /* --newton-forcing overrides the scene's, and the stats say what the library resolved */
    const char* given[] = {"0.25", "0", "default"};
    const double want[] = {0.25, 0.0, 1e-2};
    for (int k = 0; k < 3; ++k) {
        snprintf(args, sizeof args, "run '%s' --frames 1 --quiet --newton-forcing %s --stats '%s'", SHEET, given[k],
                 stats);
        ts_run_cli(args, &r);
        CHECK_EQ_INT(r.rc, 0);
        j = cf_read_json(stats);
        CHECK(cf_num(j, "newton_forcing") == want[k]);
        cJSON_Delete(j);
    }
}

/* --backend auto: the summary's backend line and the stats' "backend" and "backend_reason" say
 * which backend the sheet got and why: the CPU by the table on any device (1,024 particles, below
 * every crossover, or no device that wins); with WEFT_AUTO_CROSSOVER=0 the GPU where it is built. */
static void test_backend_auto(void) {
    static ts_cli_result r;
    char args[4096], stats[1024];
    snprintf(stats, sizeof stats, "%s", ts_tmp_path("run_auto_stats.json"));
    for (int forced = 0; forced < 2; ++forced) {
        if (forced) setenv("WEFT_AUTO_CROSSOVER", "0", 1);
        snprintf(args, sizeof args, "run '%s' --frames 1 --backend auto --stats '%s'", SHEET, stats);
        ts_run_cli(args, &r);
        if (forced) unsetenv("WEFT_AUTO_CROSSOVER");
        CHECK_EQ_INT(r.rc, 0);
        cJSON* j = cf_read_json(stats);
        const cJSON* backend = cJSON_GetObjectItemCaseSensitive(j, "backend");
        const cJSON* reason = cJSON_GetObjectItemCaseSensitive(j, "backend_reason");
        CHECK(cJSON_IsString(backend) && cJSON_IsString(reason));
        if (cJSON_IsString(backend) && cJSON_IsString(reason)) {
            printf("  %s: %s\n", backend->valuestring, reason->valuestring);
#ifdef WEFT_TEST_HAVE_GPU
            const char* want = forced ? "gpu" : "cpu";
#else
            const char* want = "cpu";
#endif
            CHECK(strcmp(backend->valuestring, want) == 0);
            CHECK(strncmp(reason->valuestring, "AUTO: ", 6) == 0);
            if (forced) CHECK(strstr(reason->valuestring, "WEFT_AUTO_CROSSOVER") || strstr(reason->valuestring, "no GPU"));
            char line[400];
            snprintf(line, sizeof line, "\nbackend       %s: %s\n", backend->valuestring, reason->valuestring);
            CHECK(strstr(r.out, line) != NULL);
        }
        cJSON_Delete(j);
    }
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
    const char* dir = cf_fresh_dir("run_moving");
    snprintf(args, sizeof args, "run '%s' --out '%s' --quiet", sc, dir);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "  stderr: %s\n", r.err);
    for (int f = 1; f <= 5; ++f) {
        snprintf(path, sizeof path, "%s/frame_%04d.obj", dir, f);
        CHECK(cf_read_obj(path, &frame_a) == 0);
        CHECK_EQ_INT(frame_a.n_v, 6);
        CHECK_EQ_INT(frame_a.n_f, 2);
        CHECK_NEAR(frame_a.v[0], 0.0, 1e-12);
        CHECK_NEAR(frame_a.v[1], 0.1 * f, 1e-12);
        CHECK_NEAR(frame_a.v[2], 0.0, 1e-12);
        CHECK(frame_a.v[9] == 0.0 && frame_a.v[10] == 0.0 && frame_a.v[11] == 1.0);
    }
}

/* A file mesh under a scene transform: rigid x uniform scale (the mesh goes to the library by
 * path, with unit_scale and a rigid object transform) and with a non-uniform scale (as host
 * arrays already placed). Without gravity or air the cloth stays at its rest shape, which must
 * be the transform applied to the file's positions, in the file's vertex order. */
static void test_file_mesh_transform(void) {
    static ts_cli_result r;
    ts_write_tmp("run_tri.obj", "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nf 1 2 3 4\n");
    /* columns: rotate +90 deg about X (y' = -z, z' = y), then scale; translation (1, 2, 3) */
    static const char* const transforms[] = {"[2, 0, 0, 0,  0, 0, 2, 0,  0, -2, 0, 0,  1, 2, 3, 1]",
                                             "[2, 0, 0, 0,  0, 0, 3, 0,  0, -0.5, 0, 0,  1, 2, 3, 1]"};
    static const double scale[2][3] = {{2, 2, 2}, {2, 0.5, 3}};   /* x, the y' (from z), the z' (from y) factors */
    static const double file[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
    for (int t = 0; t < 2; ++t) {
        char text[1024], sc[1024], args[4096];
        snprintf(text, sizeof text,
                 "{\"mesh\": {\"file\": \"run_tri.obj\", \"scale\": 0.5}, \"transform\": %s,"
                 " \"gravity\": [0, 0, 0], \"wind\": {\"normal_drag\": 0, \"tangent_drag\": 0},"
                 " \"time\": {\"frames\": 2}}",
                 transforms[t]);
        snprintf(sc, sizeof sc, "%s", ts_write_tmp("run_file_transform.json", text));
        const char* dir = cf_fresh_dir("run_file_transform");
        snprintf(args, sizeof args, "run '%s' --out '%s' --quiet", sc, dir);
        ts_run_cli(args, &r);
        CHECK_EQ_INT(r.rc, 0);
        if (r.rc != 0) fprintf(stderr, "  stderr: %s\n", r.err);
        char path[1200];
        snprintf(path, sizeof path, "%s/frame_0002.obj", dir);
        CHECK(cf_read_obj(path, &frame_a) == 0);
        CHECK_EQ_INT(frame_a.n_v, 4);
        for (int v = 0; v < 4 && v < frame_a.n_v; ++v) {
            const double* p = file[v];   /* x 0.5 (mesh.scale), then the transform */
            const double want[3] = {1 + scale[t][0] * 0.5 * p[0], 2 - scale[t][1] * 0.5 * p[2],
                                    3 + scale[t][2] * 0.5 * p[1]};
            for (int k = 0; k < 3; ++k) CHECK_NEAR(frame_a.v[3 * v + k], want[k], 1e-6);
        }
    }
}

/* An invalid scene: exit 1, exactly one "weft: ..." line naming the field, nothing on stdout,
 * and no output folder created (nothing ran). */
static void expect_bad_scene(const char* name, const char* text, const char* field) {
    static ts_cli_result r;
    char sc[1024], args[4096];
    snprintf(sc, sizeof sc, "%s", text ? ts_write_tmp(name, text) : ts_tmp_path(name));
    const char* dir = cf_fresh_dir("run_bad_out");
    snprintf(args, sizeof args, "run '%s' --out '%s' --stats '%s/s.json'", sc, dir, dir);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(r.out[0] == '\0');
    CHECK_EQ_INT(ts_count_lines(r.err), 1);
    CHECK(strncmp(r.err, "weft: ", 6) == 0);
    CHECK(strstr(r.err, field) != NULL);
    CHECK(strstr(r.err, name) != NULL);
    CHECK(!cf_exists(dir));
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
    /* welded twins (vertices 1 and 4 share a position, split by their UVs) pinned with different
     * motions: refused by the library, the message naming the pins entry */
    ts_write_tmp("run_twins.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 0 1\nv 1 0 0\nv 1 0 1\n"
                                  "vt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\nf 1/1 2/2 3/3\nf 4/4 5/4 6/4\n");
    expect_bad_scene("run_bad_twins.json",
                     "{\"mesh\": {\"file\": \"run_twins.obj\"},"
                     " \"pins\": [{\"vertices\": [1]}, {\"vertices\": [4], \"velocity\": [0, 1, 0]}]}",
                     "already pinned by attachments[0] (attachments[1] are the pins with the free_axis and motion "
                     "of pins[1])");
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
        "run a.json --render",
        "run a.json --render=",
        "run a.json --backend metal",
        "run a.json --integrator rk4",
        "run a.json --precond ilu",
        "run a.json --newton 0",
        "run a.json --newton 101",
        "run a.json --line-search yes",
        "run a.json --newton-forcing 1",
        "run a.json --newton-forcing -1",
        "run a.json --newton-forcing x",
        "run a.json --newton-forcing",
        "run a.json --line-search",
        "run a.json --backend",
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
    snprintf(args, sizeof args, "run '%s' --newton-forcing 1.5", SHEET);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--newton-forcing must be a number in [0, 1) or default, not '1.5'") != NULL);
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

/* Run the tool with stderr on a pseudo-terminal (stdout to /dev/null) and collect what it wrote
 * there. Returns the exit code, -1 when the terminal could not be set up. */
static int run_on_terminal(char* const argv[], char* out, size_t cap) {
    out[0] = '\0';
    int master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return -1;
    const char* slave_name = ptsname(master);
    if (!slave_name) return -1;
    pid_t pid = fork();
    if (pid < 0) return -1;
    if (pid == 0) {
        int slave = open(slave_name, O_RDWR);
        int null = open("/dev/null", O_WRONLY);
        if (slave < 0 || null < 0 || dup2(slave, 2) < 0 || dup2(null, 1) < 0) _exit(126);
        close(master);
        execv(WEFT_CLI, argv);
        _exit(127);
    }
    size_t len = 0;
    for (;;) {   /* until the child closed the terminal (EIO) */
        ssize_t got = read(master, out + len, cap - 1 - len);
        if (got > 0) {
            len += (size_t)got;
            if (len + 1 >= cap) break;
        } else if (got < 0 && errno == EINTR) {
            continue;
        } else {
            break;
        }
    }
    out[len] = '\0';
    close(master);
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/* On a terminal: one progress line redrawn in place (carriage returns, no newline), ending at
 * frame N/N and 100 %, erased at the end; --quiet draws nothing. */
static void test_progress_on_terminal(void) {
    static char text[65536];
    char* argv[] = {"weft", "run", (char*)SHEET, "--frames", "12", "--threads", "1", NULL};
    int rc = run_on_terminal(argv, text, sizeof text);
    CHECK_EQ_INT(rc, 0);
    CHECK(strstr(text, "frame 12/12 100%") != NULL);
    CHECK(strstr(text, "ms/frame") != NULL && strstr(text, "ETA 0:00:00") != NULL);
    CHECK(strchr(text, '\r') != NULL);
    CHECK(strchr(text, '\n') == NULL);   /* never scrolls */
    const size_t n = strlen(text);
    CHECK(n >= 4 && strcmp(text + n - 4, "\r\033[K") == 0);   /* erased at the end */
    if (rc != 0 || !strstr(text, "frame 12/12")) fprintf(stderr, "  terminal: '%s'\n", text);

    char* quiet[] = {"weft", "run", (char*)SHEET, "--frames", "3", "--quiet", NULL};
    CHECK_EQ_INT(run_on_terminal(quiet, text, sizeof text), 0);
    CHECK(text[0] == '\0');
}

/* --render: a PNG per frame (real EGL: llvmpipe without a GPU); built without WEFT_GPU, a one-line
 * error naming the renderer after the first frame's OBJ. */
static void test_render_option(void) {
    static ts_cli_result r;
    char images[1024], objs[1024], args[4096], path[1200];
    snprintf(images, sizeof images, "%s", cf_fresh_dir("run_render_png"));
    snprintf(objs, sizeof objs, "%s", cf_fresh_dir("run_render_obj"));
    snprintf(args, sizeof args, "run '%s' --frames 2 --render '%s' --out '%s' --quiet", SHEET, images, objs);
    ts_run_cli(args, &r);
#ifndef WEFT_TEST_HAVE_GPU
    CHECK_EQ_INT(r.rc, 1);
    CHECK_EQ_INT(ts_count_lines(r.err), 1);
    CHECK(strstr(r.err, "render") != NULL && strstr(r.err, "WEFT_GPU") != NULL);
    return;
#endif
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "%s", r.err);
    for (int f = 1; f <= 2; ++f) {
        snprintf(path, sizeof path, "%s/frame_%04d.png", images, f);
        unsigned char sig[8] = {0};
        FILE* png = fopen(path, "rb");
        CHECK(png != NULL);
        if (png) {
            CHECK(fread(sig, 1, 8, png) == 8);
            fclose(png);
        }
        CHECK(memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
    }
}

int main(void) {
    RUN_TEST(test_hanging_sheet);
    RUN_TEST(test_summary_and_overrides);
    RUN_TEST(test_backend_auto);
    RUN_TEST(test_moving_pin);
    RUN_TEST(test_file_mesh_transform);
    RUN_TEST(test_bad_scenes);
    RUN_TEST(test_usage_errors);
    RUN_TEST(test_help);
    RUN_TEST(test_progress_on_terminal);
    RUN_TEST(test_render_option);
    return TEST_SUMMARY();
}
