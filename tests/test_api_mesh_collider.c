/* Triangle-mesh colliders through the public API: a sheet dropped on a box given as host arrays
 * (face_sizes NULL: triangles) never has a vertex inside the box (the box's own slabs, an
 * independent test) and rests on it; the same box from an OBJ file gives the same cloth; a box
 * moved by weft_frame.mesh_collider_transforms and one deformed by
 * weft_cloth_set_mesh_collider_vertices lift the sheet; bad inputs (NaN, wrong vertex count,
 * index out of range, bad collider index, negative thickness, no cookie, non-rigid transform)
 * are refused with a clear error and the state intact (the snapshot bytes unchanged); a snapshot
 * round trip with a deforming mesh collider is bit-exact. The GPU backend's mesh colliders:
 * test_api_gpu_mesh. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "api_grid.h"
#include "check.h"
#include "test_support.h"

#define N 12
#define DT (1.0 / 30.0)

static ag_mesh g_sheet;
static float g_box[8 * 3];
static int g_box_tris[12 * 3];
static const double LO[3] = {-0.3, 0.0, -0.3}, HI[3] = {0.3, 0.3, 0.3};

static void make_box(void) {
    for (int k = 0; k < 8; ++k) {
        g_box[3 * k] = (float)((k & 1) ? HI[0] : LO[0]);
        g_box[3 * k + 1] = (float)((k & 2) ? HI[1] : LO[1]);
        g_box[3 * k + 2] = (float)((k & 4) ? HI[2] : LO[2]);
    }
    int q[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int k = 0; k < 6; ++k) {
        int t[6] = {q[k][0], q[k][1], q[k][2], q[k][0], q[k][2], q[k][3]};
        memcpy(g_box_tris + 6 * k, t, sizeof t);
    }
}

static weft_context* make_ctx(weft_backend backend) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.backend = backend;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

static weft_mesh_collider_def box_def(void) {
    weft_mesh_collider_def m = weft_default_mesh_collider_def();
    m.mesh.positions = g_box;
    m.mesh.n_vertices = 8;
    m.mesh.indices = g_box_tris;
    m.mesh.n_faces = 12;
    m.friction = 0.5;
    return m;
}

static weft_cloth_def sheet_def(const weft_mesh_collider_def* m, int n) {
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&g_sheet);
    def.n_mesh_colliders = n;
    def.mesh_colliders = m;
    return def;
}

/* Vertices strictly inside the box (moved up by dy), deeper than tol. */
static int inside_box(weft_context* ctx, weft_cloth c, double dy, double tol) {
    float pos[3 * N * N];
    int count = 0, bad = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, pos, NULL, N * N, &count), WEFT_OK);
    for (int i = 0; i < count; ++i) {
        int in = 1;
        for (int k = 0; k < 3; ++k) {
            double lo = LO[k] + (k == 1 ? dy : 0.0), hi = HI[k] + (k == 1 ? dy : 0.0);
            if (!(pos[3 * i + k] > lo + tol && pos[3 * i + k] < hi - tol)) in = 0;
        }
        bad += in;
    }
    return bad;
}

static double max_y(weft_context* ctx, weft_cloth c) {
    float pos[3 * N * N];
    int count = 0;
    weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, pos, NULL, N * N, &count);
    double y = -HUGE_VAL;
    for (int i = 0; i < count; ++i) y = fmax(y, pos[3 * i + 1]);
    return y;
}

static void test_drop_on_box(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_CPU);
    weft_mesh_collider_def m = box_def();
    weft_cloth_def def = sheet_def(&m, 1);
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    /* the same box from an OBJ file */
    char obj[2048];
    int at = 0;
    for (int k = 0; k < 8; ++k) at += snprintf(obj + at, sizeof obj - at, "v %g %g %g\n", g_box[3 * k], g_box[3 * k + 1], g_box[3 * k + 2]);
    for (int t = 0; t < 12; ++t)
        at += snprintf(obj + at, sizeof obj - at, "f %d %d %d\n", g_box_tris[3 * t] + 1, g_box_tris[3 * t + 1] + 1,
                       g_box_tris[3 * t + 2] + 1);
    weft_mesh_collider_def mf = weft_default_mesh_collider_def();
    mf.mesh.path = ts_write_tmp("mesh_collider_box.obj", obj);
    mf.friction = 0.5;
    weft_cloth_def deff = sheet_def(&mf, 1);
    weft_cloth cf;
    CHECK_EQ_INT(weft_cloth_create(ctx, &deff, &cf), WEFT_OK);
    int worst = 0, worst_f = 0;
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    weft_frame_stats st;
    for (int f = 0; f < 90; ++f) {
        CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, &st), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, cf, &fr, NULL), WEFT_OK);
        worst += inside_box(ctx, c, 0.0, 0.0);
        worst_f += inside_box(ctx, cf, 0.0, 0.0);
    }
    float a[3 * N * N], b[3 * N * N];
    int count;
    weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, a, NULL, N * N, &count);
    weft_cloth_get_vertices(ctx, cf, WEFT_SPACE_WORLD, b, NULL, N * N, &count);
    double diff = 0.0;
    for (int i = 0; i < 3 * count; ++i) diff = fmax(diff, fabs(a[i] - b[i]));
    printf("  sheet on a box (host arrays): %d vertex-frames inside; from the OBJ: %d; the two differ by %.3g m; "
           "top at %.4g m; %d in contact, %s at the end\n",
           worst, worst_f, diff, max_y(ctx, c), st.contacts, st.asleep ? "asleep" : "awake");
    CHECK_EQ_INT(worst, 0);
    CHECK_EQ_INT(worst_f, 0);
    CHECK(diff < 1e-3);
    /* the vertices over the top face rest on it, none below the thickness */
    double top_lo = HUGE_VAL, top_hi = -HUGE_VAL;
    for (int i = 0; i < count; ++i)
        if (fabs(a[3 * i]) < 0.2 && fabs(a[3 * i + 2]) < 0.2) {
            top_lo = fmin(top_lo, a[3 * i + 1]);
            top_hi = fmax(top_hi, a[3 * i + 1]);
        }
    printf("  vertices over the top face at y in [%.5g, %.5g] m (face 0.3 m + thickness 0.005 m)\n", top_lo, top_hi);
    /* (at 9 cm between vertices the bend over the box's sharp edges, resisted by the bending
       springs, lifts the middle of the top a little: 12-15 mm here, with or without friction) */
    CHECK(top_lo > 0.305 - 1e-4 && top_hi < 0.305 + 0.02);
    CHECK(st.contacts > 0);
    CHECK(st.kinetic_energy < 1e-4);
    weft_context_destroy(ctx);
}

/* The box rises 0.2 m over 20 frames, moved rigidly (transforms) or deformed (vertices). */
static void test_moving_box_lifts(void) {
    for (int mode = 0; mode < 2; ++mode) {
        weft_context* ctx = make_ctx(WEFT_BACKEND_CPU);
        weft_mesh_collider_def m = box_def();
        weft_cloth_def def = sheet_def(&m, 1);
        weft_cloth c;
        CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
        weft_frame fr = weft_default_frame();
        fr.dt = DT;
        int bad = 0;
        for (int f = 0; f < 30; ++f) CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
        for (int f = 0; f < 20; ++f) {
            double dy = 0.01 * (f + 1);
            float xf[16], verts[24];
            ag_transform(xf, 1, 0, 0, 0.0, 0.0, dy, 0.0);
            for (int k = 0; k < 24; ++k) verts[k] = g_box[k] + (k % 3 == 1 ? (float)dy : 0.0f);
            if (mode == 0) fr.mesh_collider_transforms = xf;
            else CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, verts, 8), WEFT_OK);
            CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
            bad += inside_box(ctx, c, dy, 0.0);
        }
        fr.mesh_collider_transforms = NULL;
        double top = max_y(ctx, c);
        printf("  box raised 0.2 m by %s: top of the sheet at %.4g m, %d vertex-frames inside\n",
               mode == 0 ? "transforms" : "vertices  ", top, bad);
        CHECK_EQ_INT(bad, 0);
        CHECK(top > 0.5 - 0.01 && top < 0.5 + 0.02);
        weft_context_destroy(ctx);
    }
}

static void test_bad_inputs(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_CPU);
    weft_cloth c;
    /* creation */
    float nan_box[24];
    memcpy(nan_box, g_box, sizeof nan_box);
    nan_box[7] = NAN;
    int bad_tris[36];
    memcpy(bad_tris, g_box_tris, sizeof bad_tris);
    bad_tris[20] = 8;
    struct {
        const char* what;
        weft_status want;
    } rows[] = {{"NaN position", WEFT_ERROR_NONFINITE},      {"index out of range", WEFT_ERROR_OUT_OF_RANGE},
                {"negative thickness", WEFT_ERROR_INVALID_ARGUMENT}, {"no cookie", WEFT_ERROR_INVALID_ARGUMENT},
                {"non-rigid transform", WEFT_ERROR_INVALID_ARGUMENT}, {"missing file", WEFT_ERROR_IO},
                {"NULL array, n = 1", WEFT_ERROR_INVALID_ARGUMENT}};
    for (int r = 0; r < (int)(sizeof rows / sizeof rows[0]); ++r) {
        weft_mesh_collider_def m = box_def();
        weft_cloth_def def = sheet_def(&m, 1);
        if (r == 0) m.mesh.positions = nan_box;
        if (r == 1) m.mesh.indices = bad_tris;
        if (r == 2) m.thickness = -0.001;
        if (r == 3) m.internal_cookie = 0;
        if (r == 4) m.transform[0] = 2.0f;
        if (r == 5) {
            m.mesh.positions = NULL;
            m.mesh.path = "/nonexistent/body.obj";
        }
        if (r == 6) def.mesh_colliders = NULL;
        weft_status st = weft_cloth_create(ctx, &def, &c);
        printf("  create, %-20s -> %s: %s\n", rows[r].what, weft_status_string(st), weft_context_last_error(ctx));
        CHECK_EQ_INT(st, rows[r].want);
        CHECK(c.id == 0);
    }
    /* per frame: refused, the state intact */
    weft_mesh_collider_def m = box_def();
    weft_cloth_def def = sheet_def(&m, 1);
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    for (int f = 0; f < 5; ++f) CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    size_t sz = info.snapshot_size;
    unsigned char* ref = malloc(sz);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, ref, sz), WEFT_OK);
    float v[24];
    memcpy(v, g_box, sizeof v);
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, NULL, 8), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, v, 7), WEFT_ERROR_OUT_OF_RANGE);
    printf("  wrong count: %s\n", weft_context_last_error(ctx));
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 1, v, 8), WEFT_ERROR_OUT_OF_RANGE);
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, -1, v, 8), WEFT_ERROR_OUT_OF_RANGE);
    v[5] = NAN;
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, v, 8), WEFT_ERROR_NONFINITE);
    printf("  NaN vertex: %s\n", weft_context_last_error(ctx));
    v[5] = INFINITY;
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, v, 8), WEFT_ERROR_NONFINITE);
    v[5] = 1e31f;
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, v, 8), WEFT_ERROR_OUT_OF_RANGE);
    CHECK(ag_same_snapshot(ctx, c, ref, sz));
    float xf[32];
    ag_identity(xf);
    xf[13] = NAN;
    fr.mesh_collider_transforms = xf;
    CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_ERROR_NONFINITE);
    printf("  NaN transform: %s\n", weft_context_last_error(ctx));
    ag_identity(xf);
    xf[0] = 3.0f;
    CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(ag_same_snapshot(ctx, c, ref, sz));
    /* a snapshot of a cloth with another collider mesh is refused */
    weft_mesh_collider_def m2 = box_def();
    m2.thickness = 0.01;
    weft_cloth_def def2 = sheet_def(&m2, 1);
    weft_cloth c2;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def2, &c2), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(ctx, c2, ref, sz), WEFT_ERROR_SNAPSHOT_MISMATCH);
    free(ref);
    weft_context_destroy(ctx);
}

/* Frame f's inputs: the box sways sideways and rises, given as vertices (deforming: its top
 * tilts) on even frames and as transforms on odd ones. */
static void frame_inputs(weft_context* ctx, weft_cloth c, int f) {
    double t = f * DT, dx = 0.1 * sin(3 * t), dy = 0.05 * t;
    float v[24], xf[16];
    for (int k = 0; k < 8; ++k) {
        v[3 * k] = g_box[3 * k] + (float)(dx * (g_box[3 * k + 1] > 0.1f ? 1.0 : 0.5));
        v[3 * k + 1] = g_box[3 * k + 1] + (float)dy;
        v[3 * k + 2] = g_box[3 * k + 2];
    }
    ag_transform(xf, 0, 1, 0, 0.2 * t, dx, dy, 0.0);
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    if (f % 2 == 0) CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, v, 8), WEFT_OK);
    else fr.mesh_collider_transforms = xf;
    CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
}

static void test_snapshot_round_trip(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_CPU);
    weft_mesh_collider_def m = box_def();
    weft_cloth_def def = sheet_def(&m, 1);
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    size_t sz = info.snapshot_size;
    unsigned char *s10 = malloc(sz), *end1 = malloc(sz), *end2 = malloc(sz);
    for (int f = 0; f < 10; ++f) frame_inputs(ctx, c, f);
    /* saved with new vertices already set for the next frame: they are part of the state */
    float v[24];
    memcpy(v, g_box, sizeof v);
    for (int k = 0; k < 8; ++k) v[3 * k + 1] += 0.06f;
    CHECK_EQ_INT(weft_cloth_set_mesh_collider_vertices(ctx, c, 0, v, 8), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, s10, sz), WEFT_OK);
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
    for (int f = 11; f < 30; ++f) frame_inputs(ctx, c, f);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, end1, sz), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(ctx, c, s10, sz), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
    for (int f = 11; f < 30; ++f) frame_inputs(ctx, c, f);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, end2, sz), WEFT_OK);
    int same = memcmp(end1, end2, sz) == 0;
    printf("  snapshot at frame 10 (with pending vertices), restored, run to 30: %s (%zu bytes)\n",
           same ? "bit-identical" : "DIFFERENT", sz);
    CHECK(same);
    CHECK_EQ_INT(inside_box(ctx, c, 1e9, 0.0), 0);
    free(s10);
    free(end1);
    free(end2);
    weft_context_destroy(ctx);
}

/* weft_cloth_check_collisions' max_penetration against the box's slabs and a sphere's radius,
 * computed here from the cloth's vertices: a sheet created half inside the box (y = 0.2, the box's
 * top at 0.3), nothing stepped; then a sheet through an analytic sphere. */
static void test_check_penetration(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_CPU);
    ag_mesh low;
    ag_grid(&low, N, 1.0, 0.2, 0, 0);
    weft_mesh_collider_def m = box_def();
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&low);
    def.n_mesh_colliders = 1;
    def.mesh_colliders = &m;
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    int nv = low.nv, count = 0;
    float* v = malloc(sizeof(float) * 3 * (size_t)nv);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, v, NULL, nv, &count), WEFT_OK);
    double expect = 0.0;
    for (int i = 0; i < nv; ++i) {
        double depth = INFINITY;
        for (int k = 0; k < 3; ++k) {
            double lo = v[3 * i + k] - LO[k], hi = HI[k] - v[3 * i + k];
            depth = fmin(depth, fmin(lo, hi));
        }
        if (depth > expect) expect = depth;
    }
    weft_collision_check chk;
    CHECK_EQ_INT(weft_cloth_check_collisions(ctx, c, &chk), WEFT_OK);
    printf("  sheet created inside the box: max penetration %.6g m (slabs: %.6g m)\n", chk.max_penetration, expect);
    CHECK(expect > 0.05);
    CHECK_NEAR(chk.max_penetration, expect, 1e-6);
    /* an analytic sphere (radius 0.2 at the origin) through a sheet at y = 0.1 */
    weft_collider_def sph = weft_default_collider_def();
    sph.radius = 0.2;
    ag_mesh mid;
    ag_grid(&mid, N, 1.0, 0.1, 0, 0);
    weft_cloth_def d2 = weft_default_cloth_def();
    d2.mesh = ag_desc(&mid);
    d2.n_colliders = 1;
    d2.colliders = &sph;
    weft_cloth c2;
    CHECK_EQ_INT(weft_cloth_create(ctx, &d2, &c2), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c2, WEFT_SPACE_WORLD, v, NULL, nv, &count), WEFT_OK);
    expect = 0.0;
    for (int i = 0; i < nv; ++i) {
        double r = sqrt((double)v[3 * i] * v[3 * i] + (double)v[3 * i + 1] * v[3 * i + 1] + (double)v[3 * i + 2] * v[3 * i + 2]);
        if (0.2 - r > expect) expect = 0.2 - r;
    }
    CHECK_EQ_INT(weft_cloth_check_collisions(ctx, c2, &chk), WEFT_OK);
    printf("  sheet through a sphere: max penetration %.6g m (radius: %.6g m)\n", chk.max_penetration, expect);
    CHECK(expect > 0.05);
    CHECK_NEAR(chk.max_penetration, expect, 1e-6);
    free(v);
    ag_free(&low);
    ag_free(&mid);
    weft_context_destroy(ctx);
}

int main(void) {
    ag_grid(&g_sheet, N, 1.0, 0.5, 0, 0);
    make_box();
    RUN_TEST(test_drop_on_box);
    RUN_TEST(test_moving_box_lifts);
    RUN_TEST(test_bad_inputs);
    RUN_TEST(test_snapshot_round_trip);
    RUN_TEST(test_check_penetration);
    ag_free(&g_sheet);
    return TEST_SUMMARY();
}
