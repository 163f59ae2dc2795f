/* The same cloth through real files: a quad grid written as OBJ with per-quad UVs (assimp keeps
 * the UV-split vertices apart) and as ASCII FBX (written by assimp's exporter) must give the
 * model built from host arrays: same particles, springs and rest shape, in metres. */
#include <assimp/cexport.h>
#include <assimp/cimport.h>
#include <assimp/scene.h>
#include <stdlib.h>
#include "check.h"
#include "model.h"
#include "test_support.h"

enum { N = 6 };

/* Every quad with its own four `v` lines and UVs (as exporters write UV seams): the file's
 * vertices are split at every quad edge, and welding joins them. */
static const char* write_uv_split_obj(void) {
    static char text[1 << 16];
    size_t len = 0;
    len += (size_t)snprintf(text + len, sizeof text - len, "# %dx%d quad grid, every quad with its own vertices and UVs\n", N, N);
    int q = 0;
    for (int j = 0; j + 1 < N; ++j)
        for (int i = 0; i + 1 < N; ++i, ++q) {
            static const int corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
            for (int k = 0; k < 4; ++k)
                len += (size_t)snprintf(text + len, sizeof text - len, "v %g %g 0\nvt %d %d\n",
                                        0.2 * (i + corner[k][0]), 0.2 * (j + corner[k][1]), corner[k][0],
                                        corner[k][1]);
            len += (size_t)snprintf(text + len, sizeof text - len, "f %d/%d %d/%d %d/%d %d/%d\n", 4 * q + 1,
                                    4 * q + 1, 4 * q + 2, 4 * q + 2, 4 * q + 3, 4 * q + 3, 4 * q + 4, 4 * q + 4);
        }
    return ts_write_tmp("uv_split_grid.obj", text);
}

static void check_grid_model(const wc_model* m, double scale) {
    CHECK_EQ_INT(m->n_particles, N * N);
    CHECK_EQ_INT(m->report.springs[WC_SPRING_STRETCH], 2 * N * (N - 1));
    CHECK_EQ_INT(m->report.springs[WC_SPRING_SHEAR], 2 * (N - 1) * (N - 1));
    CHECK_EQ_INT(m->report.springs[WC_SPRING_BEND], 2 * N * (N - 2));
    CHECK_EQ_INT(m->report.polygons[4], (N - 1) * (N - 1));
    CHECK_NEAR(m->report.bbox_max[0] - m->report.bbox_min[0], 0.2 * (N - 1) * scale, 1e-6 * scale);
    CHECK_NEAR(m->report.bbox_max[1] - m->report.bbox_min[1], 0.2 * (N - 1) * scale, 1e-6 * scale);
    int bad = 0;
    for (int s = m->spring_type_start[WC_SPRING_STRETCH]; s < m->spring_type_start[WC_SPRING_STRETCH + 1]; ++s)
        if (fabs(m->springs[s].rest - 0.2 * scale) > 1e-6 * scale) ++bad;
    CHECK_EQ_INT(bad, 0);
}

static void build_file(wc_model* m, const char* path, double user_scale) {
    wc_source_mesh src;
    wc_diag d = {0};
    wc_import_opts o = wc_default_import_opts();
    o.scale = user_scale;
    wc_status st = wc_import_file(&src, NULL, path, &o, &d);
    if (st != WC_OK) fprintf(stderr, "%s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    wc_model_def def = wc_default_model_def();
    st = wc_model_build(m, &src, &def, NULL, &d);
    CHECK_EQ_INT(st, WC_OK);
    /* the host map: every file vertex goes to the particle at its (welded) position */
    int bad = 0;
    for (int v = 0; v < src.n_verts; ++v) {
        int p = m->host_to_particle[v];
        if (p < 0) { ++bad; continue; }
        for (int k = 0; k < 3; ++k)
            if (fabs(m->rest_pos[3 * p + k] - src.pos[3 * v + k]) > m->report.weld_distance) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    wc_source_mesh_free(&src);
}

static void test_obj_with_uv_seams(void) {
    const char* path = write_uv_split_obj();
    CHECK(path != NULL);
    wc_model m;
    build_file(&m, path, 1.0);
    /* one host vertex per `v` line: 4 per quad; welding joins them */
    CHECK_EQ_INT(m.n_host_verts, 4 * (N - 1) * (N - 1));
    CHECK_EQ_INT(m.report.welded_vertices, 4 * (N - 1) * (N - 1) - N * N);
    check_grid_model(&m, 1.0);
    wc_model_free(&m);
    build_file(&m, path, 0.5); /* a user scale for a unit-less format */
    check_grid_model(&m, 0.5);
    CHECK_NEAR(m.report.unit_scale, 0.5, 0);
    wc_model_free(&m);
}

static void test_ascii_fbx_round_trip(void) {
    const char* obj = write_uv_split_obj();
    const struct aiScene* scene = aiImportFile(obj, 0);
    CHECK(scene != NULL);
    if (!scene) return;
    const char* fbx = ts_tmp_path("uv_split_grid.fbx");
    CHECK_EQ_INT(aiExportScene(scene, "fbxa", fbx, 0), aiReturn_SUCCESS);
    aiReleaseImport(scene);
    wc_model m;
    build_file(&m, fbx, 1.0);
    /* assimp's FBX writer declares UnitScaleFactor 1 (centimetres): 0.2 units are 2 mm */
    CHECK_NEAR(m.report.unit_scale, 0.01, 1e-12);
    check_grid_model(&m, 0.01);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_obj_with_uv_seams);
    RUN_TEST(test_ascii_fbx_round_trip);
    return TEST_SUMMARY();
}
