/* `weft run` driving the library the way a host does, checked against closed forms and
 * geometry: a pin whose motion spins, translates and oscillates puts its vertex on the closed
 * form at every frame; an object moving with inertia 0 carries the cloth rigidly (its motion's
 * closed form) while with inertia 1 the cloth does not feel it; a moving sphere pushes through a
 * sheet with no vertex ever inside its shell; colliders given in scene terms (tilted plane
 * normal/offset, capsule end points) keep every vertex outside them (so their placements in the
 * API's local conventions are right); a teleport moves everything by its offset and nothing
 * else; the bundled motion sample runs. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "cli_frames.h"
#include "test_support.h"

static const double PI = 3.14159265358979323846;
static obj_frame frame_a, frame_b;

/* Run `weft run SCENE --out DIR --quiet [extra]` for the scene text; returns the exit code. */
static int run_scene(const char* name, const char* text, const char* dir, const char* extra) {
    static ts_cli_result r;
    char sc[1024], args[4096];
    snprintf(sc, sizeof sc, "%s", ts_write_tmp(name, text));
    snprintf(args, sizeof args, "run '%s' --out '%s' --quiet %s", sc, dir, extra ? extra : "");
    ts_run_cli(args, &r);
    if (r.rc != 0) fprintf(stderr, "  %s: rc %d, stderr: %s\n", name, r.rc, r.err);
    return r.rc;
}

/* Rotation of p about the unit axis k by angle a (Rodrigues, vector form). */
static void rodrigues(const double* k, double a, const double* p, double* out) {
    const double kxp[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
    const double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
    for (int c = 0; c < 3; ++c) out[c] = p[c] * cos(a) + kxp[c] * sin(a) + k[c] * kp * (1 - cos(a));
}

/* Pinned vertex 0 of a 3 x 3 grid (rest (-0.5, 0, -0.5)) with a motion starting at 0.2 s:
 * spin 90 deg/s about Y through the origin, rise 0.1 m/s, oscillate 0.05 m along Z at 1 Hz. */
static void test_spinning_pin(void) {
    const char* dir = cf_fresh_dir("motion_spin");
    CHECK_EQ_INT(run_scene("motion_spin.json",
                           "{\"mesh\": {\"grid\": {\"n\": [3, 3], \"size\": [1, 1]}}, \"gravity\": [0, 0, 0],"
                           " \"pins\": [{\"vertices\": [0], \"motion\": {\"pivot\": [0, 0, 0], \"spin_axis\": [0, 1, 0],"
                           "   \"spin_deg_per_s\": 90, \"velocity\": [0, 0.1, 0],"
                           "   \"oscillate\": {\"amplitude\": [0, 0, 0.05], \"hz\": 1}, \"start\": 0.2}}],"
                           " \"time\": {\"fps\": 10, \"frames\": 25}}",
                           dir, NULL),
                 0);
    const double y_axis[3] = {0, 1, 0}, rest[3] = {-0.5, 0, -0.5};
    double farthest = 0;
    for (int f = 1; f <= 25; ++f) {
        CHECK(cf_read_frame(dir, f, &frame_a) == 0);
        CHECK_EQ_INT(frame_a.n_v, 9);
        const double t = 0.1 * f, tau = t > 0.2 ? t - 0.2 : 0.0;
        double want[3];
        rodrigues(y_axis, 0.5 * PI * tau, rest, want);
        want[1] += 0.1 * tau;
        want[2] += 0.05 * sin(2 * PI * tau);
        for (int k = 0; k < 3; ++k) CHECK_NEAR(frame_a.v[k], want[k], 2e-6);
        /* on the circle of radius sqrt(0.5) about the (moving) axis */
        CHECK_NEAR(hypot(frame_a.v[0], frame_a.v[2] - 0.05 * sin(2 * PI * tau)), sqrt(0.5), 2e-6);
        farthest = fmax(farthest, fabs(frame_a.v[0] - rest[0]));
    }
    CHECK(farthest > 0.5);   /* it went a long way round: 2.3 s x 90 deg/s = 207 deg */
}

/* The object moves from 0.2 s on: 0.3 m/s along X and 60 deg/s about Y through (0.2, 0, 0).
 * No gravity, no air, no pins. Inertia 0: the cloth is carried, every vertex at M(t) rest.
 * Inertia 1 (physical): the object's motion is not felt at all, every vertex stays at rest. */
static void test_object_motion(void) {
    static const char* const scene =
        "{\"mesh\": {\"grid\": {\"n\": [4, 4], \"size\": [0.6, 0.6]}}, \"gravity\": [0, 0, 0],"
        " \"wind\": {\"normal_drag\": 0, \"tangent_drag\": 0},"
        " \"object\": {\"motion\": {\"velocity\": [0.3, 0, 0], \"spin_axis\": [0, 1, 0], \"spin_deg_per_s\": 60,"
        "   \"pivot\": [0.2, 0, 0], \"start\": 0.2}, \"linear_inertia\": %s, \"angular_inertia\": %s},"
        " \"time\": {\"fps\": 10, \"frames\": 12}}";
    char text[1024];
    const double y_axis[3] = {0, 1, 0};
    for (int inertia = 0; inertia <= 1; ++inertia) {
        snprintf(text, sizeof text, scene, inertia ? "1" : "0", inertia ? "1" : "0");
        const char* dir = cf_fresh_dir(inertia ? "motion_object_1" : "motion_object_0");
        CHECK_EQ_INT(run_scene(inertia ? "motion_object_1.json" : "motion_object_0.json", text, dir, NULL), 0);
        double moved = 0;
        for (int f = 1; f <= 12; ++f) {
            CHECK(cf_read_frame(dir, f, &frame_a) == 0);
            CHECK_EQ_INT(frame_a.n_v, 16);
            const double t = 0.1 * f, tau = t > 0.2 ? t - 0.2 : 0.0;
            for (int v = 0; v < 16 && v < frame_a.n_v; ++v) {
                const double rest[3] = {-0.3 + 0.2 * (v % 4), 0, -0.3 + 0.2 * (v / 4)};
                double want[3];
                if (inertia) {
                    memcpy(want, rest, sizeof want);
                } else {
                    const double r[3] = {rest[0] - 0.2, rest[1], rest[2]};
                    rodrigues(y_axis, PI / 3 * tau, r, want);
                    want[0] += 0.2 + 0.3 * tau;
                }
                for (int k = 0; k < 3; ++k) CHECK_NEAR(frame_a.v[3 * v + k], want[k], 2e-5);
                moved = fmax(moved, fabs(frame_a.v[3 * v] - rest[0]));
            }
        }
        if (!inertia) CHECK(moved > 0.25);
    }
}

/* A sheet pinned at its four corners; a sphere (radius 0.15, shell 0.005) rises through it from
 * below at 0.5 m/s. At the end of every frame no vertex is inside the shell, and the sheet has
 * been lifted over the sphere's top. */
static void test_moving_sphere(void) {
    const char* dir = cf_fresh_dir("motion_sphere");
    CHECK_EQ_INT(run_scene("motion_sphere.json",
                           "{\"mesh\": {\"grid\": {\"n\": [16, 16], \"size\": [1, 1]}}, \"gravity\": [0, -9.81, 0],"
                           " \"pins\": [{\"vertices\": [0, 15, 240, 255]}],"
                           " \"colliders\": [{\"type\": \"sphere\", \"center\": [0.03, -0.3, -0.02], \"radius\": 0.15,"
                           "   \"thickness\": 0.005, \"motion\": {\"velocity\": [0, 0.5, 0]}}],"
                           " \"time\": {\"fps\": 30, \"frames\": 30}}",
                           dir, NULL),
                 0);
    double top = -1;
    for (int f = 1; f <= 30; ++f) {
        CHECK(cf_read_frame(dir, f, &frame_a) == 0);
        CHECK_EQ_INT(frame_a.n_v, 256);
        const double c[3] = {0.03, -0.3 + 0.5 * f / 30.0, -0.02};
        double closest = INFINITY;
        for (int v = 0; v < frame_a.n_v; ++v) {
            const double* p = frame_a.v + 3 * v;
            closest = fmin(closest, sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                                         (p[2] - c[2]) * (p[2] - c[2])));
            if (f == 30) top = fmax(top, p[1]);
        }
        CHECK(closest >= 0.155 - 1e-5);
        if (closest < 0.155 - 1e-5) fprintf(stderr, "  frame %d: a vertex %.6f m from the centre\n", f, closest);
    }
    CHECK(top > 0.2 + 0.15);   /* the sphere's top is at y = 0.35 after 1 s */
}

/* A sheet dropped onto a capsule bar (scene end points a, b) above a tilted plane (scene normal
 * and offset): at the end of every frame every vertex is outside both shells, and both were
 * touched. */
static void test_scene_colliders(void) {
    const char* dir = cf_fresh_dir("motion_colliders");
    CHECK_EQ_INT(run_scene("motion_colliders.json",
                           "{\"mesh\": {\"grid\": {\"n\": [12, 12], \"size\": [0.6, 0.6]}},"
                           " \"transform\": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.45, 0, 1],"
                           " \"colliders\": [{\"type\": \"plane\", \"normal\": [0.3, 1, 0.2], \"offset\": 0.1,"
                           "   \"thickness\": 0.004},"
                           "  {\"type\": \"capsule\", \"a\": [-0.4, 0.3, 0.1], \"b\": [0.4, 0.25, -0.05],"
                           "   \"radius\": 0.04, \"thickness\": 0.004}],"
                           " \"time\": {\"fps\": 30, \"frames\": 45}}",
                           dir, NULL),
                 0);
    const double len = sqrt(0.3 * 0.3 + 1 + 0.2 * 0.2), n[3] = {0.3 / len, 1 / len, 0.2 / len};
    const double a[3] = {-0.4, 0.3, 0.1}, b[3] = {0.4, 0.25, -0.05};
    double plane_min = INFINITY, capsule_min = INFINITY;
    for (int f = 1; f <= 45; ++f) {
        CHECK(cf_read_frame(dir, f, &frame_a) == 0);
        CHECK_EQ_INT(frame_a.n_v, 144);
        for (int v = 0; v < frame_a.n_v; ++v) {
            const double* p = frame_a.v + 3 * v;
            plane_min = fmin(plane_min, n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - 0.1);
            double ab[3], ap[3], s = 0, ab2 = 0;
            for (int k = 0; k < 3; ++k) {
                ab[k] = b[k] - a[k];
                ap[k] = p[k] - a[k];
                s += ab[k] * ap[k];
                ab2 += ab[k] * ab[k];
            }
            s = fmin(1, fmax(0, s / ab2));
            double d2 = 0;
            for (int k = 0; k < 3; ++k) d2 += (ap[k] - s * ab[k]) * (ap[k] - s * ab[k]);
            capsule_min = fmin(capsule_min, sqrt(d2) - 0.04);
        }
    }
    CHECK(plane_min >= 0.004 - 1e-5);
    CHECK(plane_min < 0.004 + 2e-3);     /* it lay on the plane */
    CHECK(capsule_min >= 0.004 - 1e-5);
    CHECK(capsule_min < 0.004 + 2e-3);   /* and on the bar */
    if (!(plane_min >= 0.004 - 1e-5) || !(capsule_min >= 0.004 - 1e-5))
        fprintf(stderr, "  closest: plane %.6f, capsule %.6f\n", plane_min, capsule_min);
}

/* The hanging sheet with and without a teleport of the object by (1, 0, -0.5) in frame 4: the
 * frames before are identical, every later frame is the other run's moved by the offset (pins
 * jump with the object). */
static void test_teleport(void) {
    static const char* const scene =
        "{\"mesh\": {\"grid\": {\"n\": [8, 8], \"size\": [1, 1]}}, \"pins\": [{\"vertices\": [56, 63]}],"
        " \"time\": {\"fps\": 30, \"frames\": 10}%s}";
    char text[1024];
    snprintf(text, sizeof text, scene, "");
    char plain[1024];
    snprintf(plain, sizeof plain, "%s", cf_fresh_dir("motion_plain"));
    CHECK_EQ_INT(run_scene("motion_plain.json", text, plain, NULL), 0);
    snprintf(text, sizeof text, scene,
             ", \"object\": {\"teleport\": [{\"frame\": 4, \"translate\": [1, 0, -0.5]}]}");
    const char* jumped = cf_fresh_dir("motion_teleport");
    CHECK_EQ_INT(run_scene("motion_teleport.json", text, jumped, NULL), 0);
    const double d[3] = {1, 0, -0.5};
    double moved = 0;
    for (int f = 1; f <= 10; ++f) {
        CHECK(cf_read_frame(plain, f, &frame_a) == 0);
        CHECK(cf_read_frame(jumped, f, &frame_b) == 0);
        CHECK_EQ_INT(frame_a.n_v, 64);
        CHECK_EQ_INT(frame_b.n_v, 64);
        for (int v = 0; v < 64; ++v)
            for (int k = 0; k < 3; ++k) {
                const double want = frame_a.v[3 * v + k] + (f >= 4 ? d[k] : 0.0);
                CHECK_NEAR(frame_b.v[3 * v + k], want, f >= 4 ? 2e-5 : 0.0);
            }
        moved = fmax(moved, fabs(frame_a.v[1]));
    }
    CHECK(moved > 0.01);   /* the sheet was swinging, not at rest */
}

/* The bundled motion sample runs cleanly (a smoke test of the shipped scene). */
static void test_sample_scene(void) {
    static ts_cli_result r;
    char args[2048], stats[1024];
    snprintf(stats, sizeof stats, "%s", ts_tmp_path("motion_sample.json"));
    snprintf(args, sizeof args, "run '%s/sample_scenes/sweeping_sphere.json' --frames 20 --quiet --stats '%s'",
             WEFT_SOURCE_DIR, stats);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(r.out[0] == '\0' && r.err[0] == '\0');
    cJSON* j = cf_read_json(stats);
    CHECK_EQ_INT(cf_num(j, "frames"), 20);
    CHECK_EQ_INT(cf_num(j, "failures"), 0);
    CHECK_EQ_INT(cf_num(j, "nonfinite_outputs"), 0);
    cJSON_Delete(j);
}

int main(void) {
    RUN_TEST(test_spinning_pin);
    RUN_TEST(test_object_motion);
    RUN_TEST(test_moving_sphere);
    RUN_TEST(test_scene_colliders);
    RUN_TEST(test_teleport);
    RUN_TEST(test_sample_scene);
    return TEST_SUMMARY();
}
