/* `weft run` with "colliders" of type "mesh": a sheet dropped on a box read from an OBJ file
 * ends on it (no vertex inside the box's slabs, the top at the thickness); the same box raised
 * by a scripted motion and by a vertex animation from a sequence of OBJ files (10 file frames
 * per second, the scene at 30: interpolated) lifts it; a frame file with another vertex count and
 * a pattern without an integer conversion are refused before anything runs, naming the field. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_support.h"

static const double LO[3] = {-0.3, 0.0, -0.3}, HI[3] = {0.3, 0.3, 0.3};

static void write_box(const char* name, double dy, int extra_vertex) {
    char text[2048];
    int at = 0;
    for (int k = 0; k < 8; ++k)
        at += snprintf(text + at, sizeof text - at, "v %g %g %g\n", (k & 1) ? HI[0] : LO[0],
                       ((k & 2) ? HI[1] : LO[1]) + dy, (k & 4) ? HI[2] : LO[2]);
    if (extra_vertex) at += snprintf(text + at, sizeof text - at, "v 0 5 0\n");
    int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int k = 0; k < 6; ++k)
        at += snprintf(text + at, sizeof text - at, "f %d %d %d %d\n", q[k][0] + 1, q[k][1] + 1, q[k][2] + 1,
                       q[k][3] + 1);
    if (extra_vertex) at += snprintf(text + at, sizeof text - at, "f 9 1 2\n");
    ts_write_tmp(name, text);
}

/* Vertices of an OBJ file ("v x y z" lines) into v (capacity cap); returns the count. */
static int read_obj_vertices(const char* path, double* v, int cap) {
    FILE* f = fopen(path, "r");
    if (!f) return -1;
    char line[256];
    int n = 0;
    while (fgets(line, sizeof line, f))
        if (line[0] == 'v' && line[1] == ' ' && n < cap &&
            sscanf(line + 2, "%lf %lf %lf", &v[3 * n], &v[3 * n + 1], &v[3 * n + 2]) == 3)
            ++n;
    fclose(f);
    return n;
}

/* Runs scene text; returns rc; the last frame's cloth vertices into v, their count into *n. */
static int run_scene(const char* name, const char* text, int frames, double* v, int* n, ts_cli_result* r) {
    char json[64], dir[64], args[4096], path[1200];
    snprintf(json, sizeof json, "%s.json", name);
    const char* sc = ts_write_tmp(json, text);
    char scene_path[1024];
    snprintf(scene_path, sizeof scene_path, "%s", sc);
    snprintf(dir, sizeof dir, "%s_out", name);
    char out_dir[1024];
    snprintf(out_dir, sizeof out_dir, "%s", ts_tmp_path(dir));
    snprintf(args, sizeof args, "run '%s' --out '%s' --quiet", scene_path, out_dir);
    ts_run_cli(args, r);
    if (r->rc != 0) return r->rc;
    snprintf(path, sizeof path, "%s/frame_%04d.obj", out_dir, frames);
    *n = read_obj_vertices(path, v, 400);
    return 0;
}

/* Vertices strictly inside the box raised by dy; the lowest and highest y over its top face. */
static int inside(const double* v, int n, double dy, double* top_lo, double* top_hi) {
    int bad = 0;
    *top_lo = HUGE_VAL;
    *top_hi = -HUGE_VAL;
    for (int i = 0; i < n; ++i) {
        const double* p = v + 3 * i;
        bad += p[0] > LO[0] && p[0] < HI[0] && p[1] > LO[1] + dy && p[1] < HI[1] + dy && p[2] > LO[2] && p[2] < HI[2];
        if (fabs(p[0]) < 0.2 && fabs(p[2]) < 0.2) {
            *top_lo = fmin(*top_lo, p[1]);
            *top_hi = fmax(*top_hi, p[1]);
        }
    }
    return bad;
}

static const char* SHEET = "\"mesh\": {\"grid\": {\"n\": [12, 12], \"size\": [1, 1]}},"
                           " \"transform\": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0.5, 0, 1],";

static void test_static_moving_animated(void) {
    static ts_cli_result r;
    static double v[1200];
    write_box("mc_body.obj", 0.0, 0);
    for (int k = 0; k <= 10; ++k) {
        char name[64];
        snprintf(name, sizeof name, "mc_body_%04d.obj", k);
        write_box(name, 0.03 * k, 0);
    }
    const char* colliders[3] = {
        "{\"type\": \"mesh\", \"file\": \"mc_body.obj\", \"friction\": 0.5}",
        "{\"type\": \"mesh\", \"file\": \"mc_body.obj\", \"friction\": 0.5,"
        " \"motion\": {\"velocity\": [0, 0.3, 0], \"start\": 1}}",
        "{\"type\": \"mesh\", \"friction\": 0.5,"
        " \"frames\": {\"pattern\": \"mc_body_%04d.obj\", \"first\": 0, \"count\": 11, \"fps\": 5}}"};
    /* the box's rise at the end (2 s): none; 0.3 m/s from 1 s; file frame 10 (0.3 m) at 2 s */
    const double rise[3] = {0.0, 0.3, 0.3};
    const char* what[3] = {"static", "motion", "frames"};
    for (int k = 0; k < 3; ++k) {
        char text[2048], name[32];
        snprintf(text, sizeof text, "{%s \"colliders\": [%s], \"time\": {\"fps\": 30, \"frames\": 60}}", SHEET,
                 colliders[k]);
        snprintf(name, sizeof name, "mc_%s", what[k]);
        int n = 0;
        int rc = run_scene(name, text, 60, v, &n, &r);
        CHECK_EQ_INT(rc, 0);
        if (rc != 0) {
            fprintf(stderr, "  stderr: %s\n", r.err);
            continue;
        }
        double lo, hi;
        int bad = inside(v, n, rise[k], &lo, &hi);
        printf("  %-6s: %d vertices, %d inside the box, the top of the sheet over the box at y in [%.4g, %.4g] "
               "(box top %.3g + thickness 0.005)\n",
               what[k], n, bad, lo, hi, 0.3 + rise[k]);
        CHECK_EQ_INT(n, 144);
        CHECK_EQ_INT(bad, 0);
        CHECK(lo > 0.305 + rise[k] - 1e-4 && hi < 0.305 + rise[k] + 0.03);
    }
}

static void test_refused(void) {
    static ts_cli_result r;
    static double v[1200];
    write_box("mc_bad_0000.obj", 0.0, 0);
    write_box("mc_bad_0001.obj", 0.0, 1);
    char text[2048];
    int n;
    snprintf(text, sizeof text,
             "{%s \"colliders\": [{\"type\": \"mesh\", \"frames\": {\"pattern\": \"mc_bad_%%04d.obj\", \"count\": 2,"
             " \"fps\": 25}}]}", SHEET);
    CHECK(run_scene("mc_bad_count", text, 1, v, &n, &r) != 0);
    printf("  %s", r.err);
    CHECK(strstr(r.err, "colliders[0].frames.pattern") != NULL && strstr(r.err, "vertices") != NULL);
    snprintf(text, sizeof text,
             "{%s \"colliders\": [{\"type\": \"mesh\", \"frames\": {\"pattern\": \"mc_bad.obj\", \"count\": 2,"
             " \"fps\": 25}}]}", SHEET);
    CHECK(run_scene("mc_bad_pattern", text, 1, v, &n, &r) != 0);
    printf("  %s", r.err);
    CHECK(strstr(r.err, "integer conversion") != NULL);
    snprintf(text, sizeof text, "{%s \"colliders\": [{\"type\": \"mesh\", \"file\": \"mc_body.obj\", \"thickness\": -1}]}",
             SHEET);
    CHECK(run_scene("mc_bad_thickness", text, 1, v, &n, &r) != 0);
    printf("  %s", r.err);
    CHECK(strstr(r.err, "colliders[0].thickness") != NULL);
}

int main(void) {
    RUN_TEST(test_static_moving_animated);
    RUN_TEST(test_refused);
    return TEST_SUMMARY();
}
