/* What a host (and the `weft` tool) reads of a cloth through the public API besides its
 * vertices: the import report (weft_cloth_get_report), the state's energies and centre of mass
 * (weft_cloth_get_energy), a mesh file as host arrays (weft_mesh_read / weft_mesh_free), the
 * inexact-Newton forcing term of the def (resolved in weft_cloth_info), and the detailed counters
 * of weft_frame_stats. Every bad input is refused with a message naming it, writes nothing and
 * leaves the cloth as it was (its snapshot compared byte for byte). */
#include <stdio.h>
#include "api_grid.h"
#include "check.h"
#include "test_support.h"

static weft_context* new_context(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.backend = WEFT_BACKEND_CPU;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

/* A 2 x 2 quad grid whose quads have their own vertices: 16 host vertices welding to 9. */
static const char* split_grid_obj(void) {
    return ts_write_tmp("api_measure_grid.obj",
                        /* 2x2 quads, each with its own four v lines (split at every edge) */
                        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\n"
                        "v 0 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nv 1 1 0\nv 2 1 0\nv 2 2 0\nv 1 2 0\n"
                        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                        "f 1/1 2/2 3/3 4/4\nf 5/1 6/2 7/3 8/4\nf 9/1 10/2 11/3 12/4\nf 13/1 14/2 15/3 16/4\n"
                        "l 1 2\n");
}

static void test_report(void) {
    weft_context* ctx = new_context();
    weft_cloth_def d = weft_default_cloth_def();
    d.mesh.path = split_grid_obj();
    d.unit_scale = 0.5;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &cloth), WEFT_OK);
    weft_import_report r;
    memset(&r, 0x5a, sizeof r);
    CHECK_EQ_INT(weft_cloth_get_report(ctx, cloth, &r), WEFT_OK);
    CHECK_EQ_INT(r.source_vertices, 16);
    CHECK_EQ_INT(r.welded_vertices, 7);
    CHECK_EQ_INT(r.unused_vertices, 0);
    CHECK_EQ_INT(r.particles, 9);
    CHECK_EQ_INT(r.polygons[0], 0);
    CHECK_EQ_INT(r.polygons[4], 4);
    CHECK_EQ_INT(r.polygons[2], 1);   /* the line, ignored */
    CHECK_EQ_INT(r.triangles, 8);
    CHECK_EQ_INT(r.edges, 16);
    CHECK_EQ_INT(r.boundary_edges, 8);
    CHECK_EQ_INT(r.boundary_loops, 1);
    CHECK_EQ_INT(r.components, 1);
    CHECK_EQ_INT(r.springs[WEFT_SPRING_STRETCH], 12);
    CHECK_EQ_INT(r.springs[WEFT_SPRING_SHEAR], 8);
    CHECK_EQ_INT(r.springs[WEFT_SPRING_BEND], 6);
    CHECK_EQ_INT(r.springs[3], 0);
    CHECK_NEAR(r.unit_scale, 0.5, 0.0);
    CHECK_NEAR(r.bbox_max[0], 1.0, 1e-12);
    CHECK(r.weld_distance > 0 && r.weld_distance < 1e-3);
    CHECK(r.ms_total >= 0 && r.n_warnings >= 0 && r.n_warnings <= WEFT_REPORT_MAX_WARNINGS);
    for (int k = 0; k < r.n_warnings; ++k) CHECK(memchr(r.warnings[k], '\0', WEFT_REPORT_WARNING_LENGTH) != NULL);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_particles, r.particles);
    CHECK_EQ_INT(info.n_vertices, r.source_vertices);
    CHECK_EQ_INT(info.threads, 1);   /* the context's */

    /* bad calls: a message naming the problem, nothing written */
    CHECK_EQ_INT(weft_cloth_get_report(ctx, cloth, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(weft_context_last_error(ctx), "weft_cloth_get_report: out is NULL") != NULL);
    weft_cloth stale = cloth;
    CHECK_EQ_INT(weft_cloth_destroy(ctx, cloth), WEFT_OK);
    memset(&r, 0x5a, sizeof r);
    CHECK_EQ_INT(weft_cloth_get_report(ctx, stale, &r), WEFT_ERROR_INVALID_HANDLE);
    CHECK(strstr(weft_context_last_error(ctx), "weft_cloth_get_report") != NULL);
    CHECK(((unsigned char*)&r)[0] == 0x5a && ((unsigned char*)&r)[sizeof r - 1] == 0x5a);
    CHECK_EQ_INT(weft_cloth_get_report(NULL, stale, &r), WEFT_ERROR_INVALID_ARGUMENT);
    weft_context_destroy(ctx);
}

/* A falling sheet: the energies add up to the total a free fall keeps (no drag, no springs
 * stretched), the kinetic term is the frame stats', the centre of mass falls as g t^2 / 2. */
static void test_energy(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 5, 1.0, 2.0, 0, 0);
    weft_cloth_def d = weft_default_cloth_def();
    d.mesh = ag_desc(&m);
    d.air_drag_normal = d.air_drag_tangent = 0.0;
    d.sleep_speed = 0.0;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &cloth), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    weft_cloth_energy e0, e1;
    CHECK_EQ_INT(weft_cloth_get_energy(ctx, cloth, &e0), WEFT_OK);
    CHECK_NEAR(e0.mass, info.total_mass, 1e-15);
    CHECK_NEAR(e0.kinetic, 0.0, 0.0);
    CHECK_NEAR(e0.elastic, 0.0, 1e-12);
    CHECK_NEAR(e0.center_of_mass[1], 2.0, 1e-6);
    CHECK_NEAR(e0.gravity, e0.mass * 9.81 * e0.center_of_mass[1], 1e-9);
    weft_frame fr = weft_default_frame();
    fr.dt = 0.1;
    weft_frame_stats fs;
    CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, &fs), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_energy(ctx, cloth, &e1), WEFT_OK);
    CHECK_NEAR(e1.kinetic, fs.kinetic_energy, 1e-12 * (1 + fs.kinetic_energy));
    CHECK(e1.kinetic > 0);
    /* backward Euler's free fall: v = g dt, x = x0 + v dt; it loses what it gains in kinetic energy */
    CHECK_NEAR(e1.center_of_mass[1], 2.0 - 9.81 * 0.1 * 0.1, 1e-5);
    CHECK_NEAR(e1.kinetic, 0.5 * e1.mass * (9.81 * 0.1) * (9.81 * 0.1), 1e-3 * e1.kinetic);
    const double total0 = e0.kinetic + e0.elastic + e0.gravity, total1 = e1.kinetic + e1.elastic + e1.gravity;
    CHECK_NEAR(total1, total0 - e1.kinetic, 1e-3 * e1.kinetic);

    unsigned char *a = malloc(info.snapshot_size), *b = malloc(info.snapshot_size);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, a, info.snapshot_size), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_energy(ctx, cloth, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(weft_context_last_error(ctx), "weft_cloth_get_energy: out is NULL") != NULL);
    weft_cloth forged = {cloth.id ^ 0x1234};
    memset(&e1, 0x5a, sizeof e1);
    CHECK_EQ_INT(weft_cloth_get_energy(ctx, forged, &e1), WEFT_ERROR_INVALID_HANDLE);
    CHECK(((unsigned char*)&e1)[0] == 0x5a);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, b, info.snapshot_size), WEFT_OK);
    CHECK(memcmp(a, b, info.snapshot_size) == 0);
    free(a);
    free(b);
    ag_free(&m);
    weft_context_destroy(ctx);
}

static void test_mesh_read(void) {
    ag_alloc_counter count = {0, 0, 0};
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.allocator.alloc = ag_count_alloc;
    cd.allocator.free = ag_count_free;
    cd.allocator.user = &count;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    const long live0 = count.live;
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, split_grid_obj(), NULL, 0.5, &md), WEFT_OK);
    CHECK_EQ_INT(md.n_vertices, 16);
    CHECK_EQ_INT(md.n_faces, 4);   /* the line is dropped */
    CHECK_NEAR(md.unit_scale, 0.5, 0.0);
    for (int f = 0; f < md.n_faces; ++f) CHECK_EQ_INT(md.face_sizes[f], 4);
    /* the first quad, 1/1 2/2 3/3 4/4: its own four vertices at (0 0) (1 0) (1 1) (0 1) x 0.5 */
    static const double q0[4][2] = {{0, 0}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
    for (int k = 0; k < 4; ++k) {
        const double* p = md.positions + 3 * md.indices[k];
        CHECK_NEAR(p[0], q0[k][0], 1e-15);
        CHECK_NEAR(p[1], q0[k][1], 1e-15);
        CHECK_NEAR(p[2], 0.0, 0.0);
    }
    CHECK(count.live > live0);   /* from the context's allocator ... */
    weft_mesh_free(ctx, &md);
    CHECK_EQ_INT(count.live, live0);   /* ... and back */
    CHECK(md.positions == NULL && md.n_vertices == 0);
    weft_mesh_free(ctx, &md);   /* a zeroed mesh: nothing */
    weft_mesh_free(ctx, NULL);

    /* the skirt's front panel by name, as weft_cloth_create would select it */
    CHECK_EQ_INT(weft_mesh_read(ctx, WEFT_SOURCE_DIR "/sample_scenes/skirt.obj", "front", 1.0, &md), WEFT_OK);
    CHECK(md.n_vertices > 0 && md.n_faces > 0);
    weft_mesh_free(ctx, &md);

    struct {
        const char* path;
        double scale;
        weft_status want;
        const char* text;
    } bad[] = {
        {NULL, 1.0, WEFT_ERROR_INVALID_ARGUMENT, "weft_mesh_read: path is NULL"},
        {"", 1.0, WEFT_ERROR_INVALID_ARGUMENT, "weft_mesh_read: path is empty"},
        {"api_measure_grid.obj", 0.0, WEFT_ERROR_INVALID_ARGUMENT, "unit_scale = 0"},
        {"api_measure_grid.obj", -1.0, WEFT_ERROR_INVALID_ARGUMENT, "unit_scale = -1"},
        {"api_measure_grid.obj", NAN, WEFT_ERROR_NONFINITE, "unit_scale is not finite"},
        {"no_such_mesh.obj", 1.0, WEFT_ERROR_IO, "no_such_mesh.obj"},
        {"not_a_mesh.obj", 1.0, WEFT_ERROR_IMPORT, "not_a_mesh.obj"},
        {"nan_mesh.obj", 1.0, WEFT_ERROR_NONFINITE, "nan_mesh.obj"},
    };
    ts_write_tmp("not_a_mesh.obj", "this is not a mesh\n");
    ts_write_tmp("nan_mesh.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        char path[512];
        const char* p = bad[k].path;
        if (p && p[0]) {
            snprintf(path, sizeof path, "%s", !strcmp(p, "api_measure_grid.obj") ? split_grid_obj() : ts_tmp_path(p));
            p = path;
        }
        memset(&md, 0x5a, sizeof md);
        const weft_status st = weft_mesh_read(ctx, p, NULL, bad[k].scale, &md);
        CHECK(st == bad[k].want || (bad[k].want == WEFT_ERROR_IMPORT && st == WEFT_ERROR_EMPTY_MESH));
        CHECK(strstr(weft_context_last_error(ctx), bad[k].text) != NULL);
        CHECK(md.n_vertices == 0 && md.positions == NULL && md.face_sizes == NULL && md.indices == NULL);
        printf("bad %zu: %s (%s)\n", k, weft_context_last_error(ctx), weft_status_string(st));
    }
    CHECK(weft_mesh_read(ctx, split_grid_obj(), "no_such_node", 1.0, &md) != WEFT_OK);
    CHECK(md.positions == NULL);
    CHECK(strstr(weft_context_last_error(ctx), "no_such_node") != NULL);
    CHECK_EQ_INT(weft_mesh_read(ctx, split_grid_obj(), NULL, 1.0, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(weft_context_last_error(ctx), "out is NULL") != NULL);
    CHECK_EQ_INT(weft_mesh_read(NULL, split_grid_obj(), NULL, 1.0, &md), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(count.live, live0);   /* no failure leaks */
    weft_context_destroy(ctx);
    CHECK_EQ_INT(count.live, 0);
}

/* newton_forcing: -1 (default) resolves to the backend's (this 25-particle cloth on the CPU: 0,
 * with IC(0); test_api_precond_default.c), a value in [0, 1) is kept, anything else is refused
 * naming the field. */
static void test_newton_forcing(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 5, 1.0, 1.0, 0, 0);
    weft_cloth_def d = weft_default_cloth_def();
    CHECK(d.newton_forcing == -1.0);
    d.mesh = ag_desc(&m);
    const double given[] = {-1.0, 0.0, 0.25};
    const double want[] = {0.0, 0.0, 0.25};
    for (int k = 0; k < 3; ++k) {
        d.newton_forcing = given[k];
        weft_cloth c = {0};
        CHECK_EQ_INT(weft_cloth_create(ctx, &d, &c), WEFT_OK);
        weft_cloth_info info;
        CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
        CHECK(info.newton_forcing == want[k]);
        CHECK_EQ_INT(weft_cloth_destroy(ctx, c), WEFT_OK);
    }
    const double bad[] = {-0.5, 1.0, 2.0, NAN, INFINITY};
    for (int k = 0; k < 5; ++k) {
        d.newton_forcing = bad[k];
        weft_cloth c = {777};
        const weft_status st = weft_cloth_create(ctx, &d, &c);
        CHECK_EQ_INT(st, isfinite(bad[k]) ? WEFT_ERROR_INVALID_ARGUMENT : WEFT_ERROR_NONFINITE);
        CHECK(c.id == 0);
        CHECK(strstr(weft_context_last_error(ctx), "def->newton_forcing") != NULL);
    }
    ag_free(&m);
    weft_context_destroy(ctx);
}

/* tolerance: -1 (default) resolves to the backend's (this 25-particle cloth on the CPU: 1e-3,
 * with IC(0); test_api_precond_default.c), a value in [0, 1) is kept, anything else is refused
 * naming the field, and a cloth made before still steps. */
static void test_tolerance(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 5, 1.0, 1.0, 0, 0);
    weft_cloth_def d = weft_default_cloth_def();
    CHECK(d.tolerance == -1.0);
    d.mesh = ag_desc(&m);
    weft_cloth keep = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &keep), WEFT_OK);
    const double given[] = {-1.0, 1e-4, 0.0, 0.5};
    const double want[] = {1e-3, 1e-4, 0.0, 0.5};
    for (int k = 0; k < 4; ++k) {
        d.tolerance = given[k];
        weft_cloth c = {0};
        CHECK_EQ_INT(weft_cloth_create(ctx, &d, &c), WEFT_OK);
        weft_cloth_info info;
        CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
        CHECK(info.tolerance == want[k]);
        CHECK_EQ_INT(weft_cloth_destroy(ctx, c), WEFT_OK);
    }
    const double bad[] = {-0.5, -1e-4, -2.0, 1.0, NAN, INFINITY, -INFINITY};
    for (int k = 0; k < 7; ++k) {
        d.tolerance = bad[k];
        weft_cloth c = {777};
        const weft_status st = weft_cloth_create(ctx, &d, &c);
        CHECK_EQ_INT(st, isfinite(bad[k]) ? WEFT_ERROR_INVALID_ARGUMENT : WEFT_ERROR_NONFINITE);
        CHECK(c.id == 0);
        CHECK(strstr(weft_context_last_error(ctx), "def->tolerance") != NULL);
    }
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 30.0;
    weft_frame_stats fs;
    CHECK_EQ_INT(weft_cloth_step(ctx, keep, &fr, &fs), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, keep, &info), WEFT_OK);
    CHECK(info.tolerance == 1e-3);
    CHECK_EQ_INT(weft_cloth_destroy(ctx, keep), WEFT_OK);
    ag_free(&m);
    weft_context_destroy(ctx);
}

/* The detailed counters: Newton steps with two Newton iterations, BDF2 substeps with BDF2, no
 * pairs without mesh colliders or self-collision (test_api_self_collide's fold has them). */
static void test_stats_detail(void) {
    weft_context* ctx = new_context();
    ag_mesh m;
    ag_grid(&m, 8, 1.0, 1.0, 0, 0);
    weft_cloth_def d = weft_default_cloth_def();
    d.mesh = ag_desc(&m);
    d.sleep_speed = 0.0;
    d.newton_iterations = 2;
    d.line_search = 1;
    d.integrator = WEFT_INTEGRATOR_BDF2;
    d.substeps = 2;
    int pin[1] = {0};
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = pin;
    att.n_vertices = 1;
    d.attachments = &att;
    d.n_attachments = 1;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &cloth), WEFT_OK);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 30.0;
    int newton = 0, bdf2 = 0;
    for (int f = 0; f < 4; ++f) {
        weft_frame_stats fs;
        memset(&fs, 0x5a, sizeof fs);
        CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, &fs), WEFT_OK);
        CHECK(fs.newton_steps >= 0 && fs.line_search_backtracks >= 0 && fs.energy_steps >= 0);
        CHECK(fs.mesh_pairs == 0 && fs.self_pairs == 0);   /* neither mesh colliders nor self-collision */
        CHECK(fs.bdf2_substeps <= fs.substeps);
        newton += fs.newton_steps;
        bdf2 += fs.bdf2_substeps;
    }
    CHECK(newton > 0);
    CHECK(bdf2 > 0);   /* the first substep has no history: backward Euler; then BDF2 */
    CHECK_EQ_INT(weft_cloth_destroy(ctx, cloth), WEFT_OK);
    ag_free(&m);
    weft_context_destroy(ctx);
}

int main(void) {
    RUN_TEST(test_report);
    RUN_TEST(test_energy);
    RUN_TEST(test_mesh_read);
    RUN_TEST(test_newton_forcing);
    RUN_TEST(test_tolerance);
    RUN_TEST(test_stats_detail);
    return TEST_SUMMARY();
}
