/* Results of an FBX mesh come back in the file's control-point order. A 6 x 6 sheet whose
 * control points are shuffled, with its x = 3 column split into twin control points (a seam)
 * and one control point no polygon uses, is written by the test (fbx_writer.h) as binary FBX
 * 7.4 with raw and with deflated arrays, as binary 7.5 (64-bit records) and as ASCII:
 * weft_mesh_read's vertex i and the cloth's vertex i at every frame are the file's control
 * point i (node translation and cm applied), checked against the same mesh given as host arrays
 * in that order (an independent path); the twins report one position. Two geometries under
 * three models come back as three blocks, a geometry split by material as one. poncho.fbx maps
 * one to one onto its control points, and the poncho scene's pins sit where make_poncho.py puts
 * the shoulders. Corrupt files (truncated, bad offsets, counts past the end, a broken deflate
 * stream, an index past the control points, a polygon assimp did not import as the file has it)
 * are refused with IMPORT and a message. */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "fbx_geometry.h"
#include "fbx_writer.h"
#include "import_fbx_order.h"
#include "source_mesh.h"
#include "test_support.h"
#include "weft/weft.h"

#define N 6
#define NG (N * N)          /* grid points */
#define NT N                /* twins of the x = 3 column */
#define NP (NG + NT + 1)    /* control points: grid, twins, one unused */
#define NQ ((N - 1) * (N - 1))
#define CM 0.01

static double cp[NP][3];    /* control points in file order, cm */
static int quads[NQ][4];    /* each quad's control points */
static int sizes[NQ];
static const double shift[3] = {10.0, 50.0, -20.0};   /* the Model's Lcl Translation, cm */
static int twin_of[NP];     /* the other control point at the same position, or -1 */

/* Grid point g = (i, j) at (20 i, 0, 20 j) cm; the twins repeat the i = 3 column, and the quads
 * with i >= 3 use them; then every control point moves to a shuffled slot. */
static void make_sheet(void) {
    double pts[NP][3];
    for (int g = 0; g < NG; ++g) {
        pts[g][0] = 20.0 * (g % N);
        pts[g][1] = 0.0;
        pts[g][2] = 20.0 * (g / N);
    }
    for (int t = 0; t < NT; ++t) memcpy(pts[NG + t], pts[t * N + 3], sizeof pts[0]);
    pts[NP - 1][0] = 500.0;   /* unused */
    pts[NP - 1][1] = 7.0;
    pts[NP - 1][2] = -3.0;
    int perm[NP], where[NP];  /* file slot k holds point perm[k] */
    for (int i = 0; i < NP; ++i) perm[i] = i;
    unsigned s = 4242u;
    for (int i = NP - 1; i > 0; --i) {
        s = s * 1103515245u + 12345u;
        int j = (int)((s >> 8) % (unsigned)(i + 1)), t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    for (int k = 0; k < NP; ++k) {
        where[perm[k]] = k;
        memcpy(cp[k], pts[perm[k]], sizeof cp[k]);
    }
    for (int j = 0, q = 0; j + 1 < N; ++j)
        for (int i = 0; i + 1 < N; ++i, ++q) {
            int a = j * N + i, c[4] = {a, a + 1, a + N + 1, a + N};
            for (int k = 0; k < 4; ++k) {
                int g = c[k];
                if (i >= 3 && g % N == 3) g = NG + g / N;   /* this side of the seam */
                quads[q][k] = where[g];
            }
            sizes[q] = 4;
        }
    for (int k = 0; k < NP; ++k) twin_of[k] = -1;
    for (int t = 0; t < NT; ++t) {
        twin_of[where[t * N + 3]] = where[NG + t];
        twin_of[where[NG + t]] = where[t * N + 3];
    }
}

static fw_mesh sheet_mesh(int compress, int version) {
    fw_mesh m;
    memset(&m, 0, sizeof m);
    m.n_points = NP;
    m.points = &cp[0][0];
    m.n_polys = NQ;
    m.sizes = sizes;
    m.corners = &quads[0][0];
    memcpy(m.translation, shift, sizeof shift);
    m.compress = compress;
    m.version = version;
    return m;
}

static const char* write_file(const char* name, const void* data, size_t n) {
    const char* path = ts_tmp_path(name);
    FILE* f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f) return path;
    CHECK(fwrite(data, 1, n, f) == n);
    fclose(f);
    return path;
}

static const char* write_binary(const char* name, int compress, int version) {
    fw_mesh m = sheet_mesh(compress, version);
    fw_buf b = fw_binary(&m);
    const char* path = write_file(name, b.b, b.n);
    free(b.b);
    return path;
}

static const char* write_ascii(const char* name) {
    fw_mesh m = sheet_mesh(0, 0);
    char* t = fw_ascii(&m);
    const char* path = write_file(name, t, strlen(t));
    free(t);
    return path;
}

/* Control point k where the import puts it: (point + translation) x cm. */
static double placed(int k, int axis) { return CM * (cp[k][axis] + shift[axis]); }

static weft_context* new_context(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.backend = WEFT_BACKEND_CPU;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

/* The sheet from the file (path) or as host arrays in the file's order (NULL), pinned at the
 * file's control points of grid corners (0, 0) and (5, 0). */
static weft_cloth make_cloth(weft_context* ctx, const char* path, int pin_a, int pin_b) {
    static float host[NP][3];
    for (int k = 0; k < NP; ++k)
        for (int a = 0; a < 3; ++a) host[k][a] = (float)placed(k, a);
    weft_cloth_def d = weft_default_cloth_def();
    if (path) {
        d.mesh.path = path;
    } else {
        d.mesh.positions = &host[0][0];
        d.mesh.n_vertices = NP;
        d.mesh.face_sizes = sizes;
        d.mesh.n_faces = NQ;
        d.mesh.indices = &quads[0][0];
    }
    const int pinned[2] = {pin_a, pin_b};
    weft_attachment_def a = weft_default_attachment_def();
    a.vertices = pinned;
    a.n_vertices = 2;
    d.attachments = &a;
    d.n_attachments = 1;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &cloth), WEFT_OK);
    return cloth;
}

static void get(weft_context* ctx, weft_cloth cloth, float* pos) {
    int count = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, pos, NULL, NP, &count), WEFT_OK);
    CHECK_EQ_INT(count, NP);
}

/* The file at path reads as the sheet in control-point order and simulates as the host arrays. */
static void check_sheet_file(const char* path) {
    weft_context* ctx = new_context();
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, path, NULL, 1.0, &md), WEFT_OK);
    CHECK_EQ_INT(md.n_vertices, NP);
    CHECK_EQ_INT(md.n_faces, NQ);
    CHECK_NEAR(md.unit_scale, CM, 1e-15);
    for (int v = 0; v < md.n_vertices && v < NP; ++v)
        for (int a = 0; a < 3; ++a) CHECK_NEAR(md.positions[3 * v + a], placed(v, a), 1e-9);
    for (int c = 0; c < 4 * NQ && md.n_faces == NQ; ++c) CHECK_EQ_INT(md.indices[c], (&quads[0][0])[c]);
    weft_mesh_free(ctx, &md);

    int corner[2] = {-1, -1};   /* the control points of grid points (0, 0) and (5, 0) */
    for (int k = 0; k < NP; ++k)
        for (int s = 0; s < 2; ++s)
            if (cp[k][0] == 100.0 * s && cp[k][1] == 0.0 && cp[k][2] == 0.0) corner[s] = k;
    weft_cloth file = make_cloth(ctx, path, corner[0], corner[1]);
    weft_cloth arrays = make_cloth(ctx, NULL, corner[0], corner[1]);
    float a[NP * 3], b[NP * 3];
    get(ctx, file, a);
    for (int v = 0; v < NP; ++v)   /* frame 0: the file's control points, in file order */
        for (int k = 0; k < 3; ++k) CHECK_NEAR(a[3 * v + k], placed(v, k), 1e-6);
    for (int f = 1; f <= 4; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / 30.0;
        CHECK_EQ_INT(weft_cloth_step(ctx, file, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, arrays, &fr, NULL), WEFT_OK);
        get(ctx, file, a);
        get(ctx, arrays, b);
        double d = 0.0;
        for (int i = 0; i < 3 * NP; ++i) d = fmax(d, fabs(a[i] - b[i]));
        CHECK(d < 1e-6);
        for (int v = 0; v < NP; ++v)   /* seam twins: one particle, one position */
            if (twin_of[v] >= 0)
                for (int k = 0; k < 3; ++k) CHECK_NEAR(a[3 * v + k], a[3 * twin_of[v] + k], 0.0);
    }
    int fell = 0;
    for (int v = 0; v < NP; ++v) fell += a[3 * v + 1] < placed(v, 1) - 0.01;
    CHECK(fell > NP / 2);
    for (int s = 0; s < 2; ++s)
        for (int k = 0; k < 3; ++k) CHECK_NEAR(a[3 * corner[s] + k], placed(corner[s], k), 1e-6);
    weft_context_destroy(ctx);
}

static void test_binary_raw(void) { check_sheet_file(write_binary("fbx_order_raw.fbx", 0, 7400)); }
static void test_binary_deflated(void) { check_sheet_file(write_binary("fbx_order_zlib.fbx", 1, 7400)); }
static void test_binary_7500(void) { check_sheet_file(write_binary("fbx_order_7500.fbx", 1, 7500)); }
static void test_ascii(void) { check_sheet_file(write_ascii("fbx_order_ascii.fbx")); }

/* The unused control point keeps its own position (translated, cm) and has no particle. */
static void test_unused_point(void) {
    weft_context* ctx = new_context();
    int unused = -1;
    for (int k = 0; k < NP; ++k)
        if (cp[k][0] == 500.0) unused = k;
    weft_cloth cloth = make_cloth(ctx, ts_tmp_path("fbx_order_raw.fbx"), quads[0][0], quads[0][1]);
    weft_import_report r;
    CHECK_EQ_INT(weft_cloth_get_report(ctx, cloth, &r), WEFT_OK);
    CHECK_EQ_INT(r.source_vertices, NP);
    CHECK_EQ_INT(r.unused_vertices, 1);
    CHECK_EQ_INT(r.particles, NG);
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 30.0;
    CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_OK);
    float a[NP * 3];
    get(ctx, cloth, a);
    for (int k = 0; k < 3; ++k) CHECK_NEAR(a[3 * unused + k], placed(unused, k), 1e-6);
    weft_context_destroy(ctx);
}

/* The same from memory (wc_import_memory, hint "fbx"): the buffer is the file. */
static void test_memory(void) {
    fw_mesh m = sheet_mesh(1, 7400);
    fw_buf b = fw_binary(&m);
    wc_source_mesh src;
    wc_diag d;
    memset(&d, 0, sizeof d);
    CHECK_EQ_INT(wc_import_memory(&src, NULL, b.b, b.n, "fbx", NULL, &d), WC_OK);
    CHECK_EQ_INT(src.n_verts, NP);
    for (int v = 0; v < src.n_verts && v < NP; ++v)
        for (int a = 0; a < 3; ++a) CHECK_NEAR(src.pos[3 * v + a], placed(v, a), 1e-9);
    wc_source_mesh_free(&src);
    free(b.b);
}

/* Materials split a geometry: assimp 5.2 makes one mesh per material (in order of first use),
 * each with that material's polygons in file order; the node's meshes stay one block of the
 * geometry's control points, and the polygons come back grouped by mesh. */
static void test_material_split(void) {
    int mat[NQ];
    for (int q = 0; q < NQ; ++q) mat[q] = q % 3 == 0 ? 1 : 0;
    fw_mesh m = sheet_mesh(0, 7400);
    m.materials = mat;
    fw_buf b = fw_binary(&m);
    const char* path = write_file("fbx_order_materials.fbx", b.b, b.n);
    free(b.b);
    const struct aiScene* s = aiImportFile(path, 0);   /* what assimp makes of it */
    CHECK(s != NULL && s->mNumMeshes == 2);
    if (s) aiReleaseImport(s);
    weft_context* ctx = new_context();
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, path, NULL, 1.0, &md), WEFT_OK);
    CHECK_EQ_INT(md.n_vertices, NP);
    CHECK_EQ_INT(md.n_faces, NQ);
    for (int v = 0; v < md.n_vertices && v < NP; ++v)
        for (int a = 0; a < 3; ++a) CHECK_NEAR(md.positions[3 * v + a], placed(v, a), 1e-9);
    int c = 0;   /* material 1 first (polygon 0 has it), then material 0 */
    for (int pass = 0; pass < 2 && md.n_faces == NQ; ++pass)
        for (int q = 0; q < NQ; ++q)
            if (mat[q] == 1 - pass)
                for (int k = 0; k < 4; ++k, ++c) CHECK_EQ_INT(md.indices[c], quads[q][k]);
    weft_mesh_free(ctx, &md);
    weft_context_destroy(ctx);
}

/* Two geometries and three models, the first geometry shown twice: one block of host vertices
 * per model in the node order, each its geometry's control points at the model's translation;
 * the polygons of each block index into it. */
static void test_several_geometries(void) {
    static const double tri_pts[5][3] = {{0, 0, 300}, {40, 0, 300}, {0, 40, 300}, {40, 40, 300}, {9, 9, 9}};
    static const int tri_sizes[2] = {3, 3}, tri_corners[6] = {0, 1, 2, 2, 1, 3};
    fw_mesh geo[2] = {sheet_mesh(1, 7400), sheet_mesh(0, 7400)};
    geo[1].n_points = 5;   /* the last one unused */
    geo[1].points = &tri_pts[0][0];
    geo[1].n_polys = 2;
    geo[1].sizes = tri_sizes;
    geo[1].corners = tri_corners;
    static const int model_geo[3] = {0, 1, 0};
    static const double model_t[3][3] = {{10, 50, -20}, {0, 0, 0}, {-300, 10, 0}};
    fw_buf b = fw_binary_scene(geo, 2, model_geo, model_t, 3);
    const char* path = write_file("fbx_order_three_models.fbx", b.b, b.n);
    free(b.b);
    weft_context* ctx = new_context();
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, path, NULL, 1.0, &md), WEFT_OK);
    CHECK_EQ_INT(md.n_vertices, 2 * NP + 5);
    CHECK_EQ_INT(md.n_faces, 2 * NQ + 2);
    if (md.n_vertices == 2 * NP + 5 && md.n_faces == 2 * NQ + 2) {
        int base = 0, c = 0;
        for (int k = 0; k < 3; ++k) {
            const fw_mesh* g = &geo[model_geo[k]];
            for (int v = 0; v < g->n_points; ++v)
                for (int a = 0; a < 3; ++a)
                    CHECK_NEAR(md.positions[3 * (base + v) + a], CM * (g->points[3 * v + a] + model_t[k][a]), 1e-9);
            int n_idx = 0;
            for (int q = 0; q < g->n_polys; ++q) n_idx += g->sizes[q];
            for (int i = 0; i < n_idx; ++i, ++c) CHECK_EQ_INT(md.indices[c], base + g->corners[i]);
            base += g->n_points;
        }
    }
    weft_mesh_free(ctx, &md);
    CHECK_EQ_INT(weft_mesh_read(ctx, path, "sheet2", 1.0, &md), WEFT_OK);   /* one node */
    CHECK_EQ_INT(md.n_vertices, NG + NT);   /* the selected polygons' control points */
    for (int v = 0, k = 0; v < NP && md.n_vertices == NG + NT; ++v) {
        if (cp[v][0] == 500.0) continue;    /* the unused one is left out */
        for (int a = 0; a < 3; ++a) CHECK_NEAR(md.positions[3 * k + a], CM * (cp[v][a] + model_t[2][a]), 1e-9);
        ++k;
    }
    weft_mesh_free(ctx, &md);
    weft_context_destroy(ctx);
}

/* ---- poncho.fbx ------------------------------------------------------------------------- */

/* The Vertices array of an ASCII FBX read with strtod, independently of fbx_geometry.c. */
static double* ascii_vertices(const char* text, int* n) {
    const char* p = strstr(text, "Vertices: *");
    *n = p ? atoi(p + 11) : 0;
    p = p ? strstr(p, "a:") : NULL;
    if (!p || *n <= 0) return NULL;
    double* v = malloc(sizeof(double) * (size_t)*n);
    p += 2;
    for (int i = 0; i < *n; ++i) {
        char* end;
        v[i] = strtod(p, &end);
        p = end;
        while (*p == ',' || *p == ' ' || *p == '\n' || *p == '\r' || *p == '\t') ++p;
    }
    return v;
}

static void test_poncho(void) {
    char path[1024];
    snprintf(path, sizeof path, "%s/sample_scenes/poncho.fbx", WEFT_SOURCE_DIR);
    static char text[400000];
    ts_read_text(path, text, sizeof text);
    int n = 0;
    double* v = ascii_vertices(text, &n);
    CHECK(v != NULL && n % 3 == 0);
    if (!v) return;
    const int np = n / 3;
    wc_source_mesh m;
    wc_diag d;
    memset(&d, 0, sizeof d);
    CHECK_EQ_INT(wc_import_file(&m, NULL, path, NULL, &d), WC_OK);
    CHECK_EQ_INT(m.n_verts, np);
    int* hits = calloc((size_t)np + 1, sizeof(int));
    const int nc = m.poly_start[m.n_polys];
    for (int c = 0; c < nc; ++c)
        if (m.poly_verts[c] >= 0 && m.poly_verts[c] < np) ++hits[m.poly_verts[c]];
    int once = 0;
    for (int k = 0; k < np; ++k) once += hits[k] == 1;
    CHECK_EQ_INT(nc, np);     /* assimp's exporter: one control point per corner */
    CHECK_EQ_INT(once, np);   /* so the corners map one to one onto them */
    double worst = 0.0;
    for (int k = 0; k < 3 * np; ++k) worst = fmax(worst, fabs(m.pos[k] - CM * v[k]));
    CHECK(worst < 1e-6);
    free(hits);
    free(v);

    /* The scene's pins: the top of the fold (y 154 cm, z 0) either side of the neck hole, at
     * x = +-10, 12.5, 15, 17.5, 20 cm (make_poncho.py). */
    char scene[1024];
    static char json[8192];
    snprintf(scene, sizeof scene, "%s/sample_scenes/poncho_shoulders.json", WEFT_SOURCE_DIR);
    ts_read_text(scene, json, sizeof json);
    cJSON* root = cJSON_Parse(json);
    const cJSON* pins = cJSON_GetObjectItem(root, "pins");
    CHECK_EQ_INT(cJSON_GetArraySize(pins), 2);
    for (int s = 0; s < 2; ++s) {
        const cJSON* idx = cJSON_GetObjectItem(cJSON_GetArrayItem(pins, s), "vertices");
        int seen[5] = {0};
        CHECK_EQ_INT(cJSON_GetArraySize(idx), 5);
        for (int i = 0; i < cJSON_GetArraySize(idx); ++i) {
            const int k = cJSON_GetArrayItem(idx, i)->valueint;
            CHECK(k >= 0 && k < m.n_verts);
            if (k < 0 || k >= m.n_verts) continue;
            const double* p = m.pos + 3 * k, x = (s ? 1.0 : -1.0) * p[0] / CM;
            CHECK_NEAR(p[1], 1.54, 1e-6);
            CHECK_NEAR(p[2], 0.0, 1e-6);
            const int step = (int)lround((x - 10.0) / 2.5);
            CHECK(step >= 0 && step < 5 && fabs(x - (10.0 + 2.5 * step)) < 1e-4);
            if (step >= 0 && step < 5) ++seen[step];
        }
        for (int i = 0; i < 5; ++i) CHECK_EQ_INT(seen[i], 1);
    }
    cJSON_Delete(root);
    wc_source_mesh_free(&m);
}

/* ---- refused files ---------------------------------------------------------------------- */

static void expect_reader_fail(const unsigned char* data, size_t n, const char* needle) {
    wc_fbx_geometries g;
    wc_diag d;
    memset(&d, 0, sizeof d);
    wc_status st = wc_fbx_geometry_read(&g, NULL, data, n, "bad.fbx", &d);
    CHECK_EQ_INT(st, WC_ERROR_IMPORT);
    CHECK(g.n == 0 && g.g == NULL);
    CHECK(strstr(d.message, "bad.fbx") != NULL);
    if (needle && !strstr(d.message, needle)) {
        fprintf(stderr, "message without '%s': %s\n", needle, d.message);
        CHECK(0);
    }
    if (st == WC_OK) wc_fbx_geometry_free(&g);
}

/* Every prefix of a binary file, raw and deflated: refused or read, never past the data. */
static void test_truncated(void) {
    for (int z = 0; z < 3; ++z) {   /* raw 7400, deflated 7400, deflated 7500 */
        fw_mesh m = sheet_mesh(z > 0, z == 2 ? 7500 : 7400);
        fw_buf b = fw_binary(&m);
        int refused = 0;
        for (size_t n = 0; n < b.n; ++n) {
            unsigned char* copy = malloc(n + 1);   /* exactly n bytes for ASan */
            memcpy(copy, b.b, n);
            wc_fbx_geometries g;
            wc_diag d;
            memset(&d, 0, sizeof d);
            wc_status st = wc_fbx_geometry_read(&g, NULL, copy, n, "cut.fbx", &d);
            if (st == WC_OK) {   /* cut between top-level records */
                CHECK(g.n <= 1);
                wc_fbx_geometry_free(&g);
            } else {
                CHECK_EQ_INT(st, WC_ERROR_IMPORT);
                CHECK(d.message[0] != '\0');
                ++refused;
            }
            free(copy);
        }
        CHECK(refused > (int)b.n / 2);   /* cut inside a record: refused */
        /* and the whole file reads as the sheet */
        wc_fbx_geometries g;
        wc_diag d;
        memset(&d, 0, sizeof d);
        CHECK_EQ_INT(wc_fbx_geometry_read(&g, NULL, b.b, b.n, "whole.fbx", &d), WC_OK);
        CHECK_EQ_INT(g.n, 1);
        if (g.n == 1) {
            CHECK_EQ_INT(g.g[0].n_points, NP);
            CHECK_EQ_INT(g.g[0].n_polys, NQ);
            for (int k = 0; k < 3 * NP && g.g[0].n_points == NP; ++k)
                CHECK_NEAR(g.g[0].points[k], (&cp[0][0])[k], 0.0);
            for (int c = 0; c < 4 * NQ && g.g[0].n_polys == NQ; ++c)
                CHECK_EQ_INT(g.g[0].poly_points[c], (&quads[0][0])[c]);
        }
        wc_fbx_geometry_free(&g);
        free(b.b);
    }
}

static void test_corrupt_binary(void) {
    fw_mesh m = sheet_mesh(0, 7400);
    fw_buf b = fw_binary(&m);
    unsigned char* c = malloc(b.n);

    memcpy(c, b.b, b.n);   /* the Geometry's end offset past the file */
    fw_buf w = {c, b.n, b.n, 0, 0, 0, 0};
    fw_patch32(&w, b.geometry_record, (uint32_t)b.n + 100);
    expect_reader_fail(c, b.n, "end offset");
    fw_patch32(&w, b.geometry_record, (uint32_t)b.geometry_record);   /* before its own header */
    expect_reader_fail(c, b.n, "end offset");

    memcpy(c, b.b, b.n);   /* Vertices' count past its bytes */
    fw_patch32(&w, b.vertices_array + 1, 3 * NP + 5);
    expect_reader_fail(c, b.n, "Vertices");
    memcpy(c, b.b, b.n);   /* its byte length past the record */
    fw_patch32(&w, b.vertices_array + 9, 1u << 30);
    expect_reader_fail(c, b.n, "property");

    memcpy(c, b.b, b.n);   /* an index past the control points */
    fw_patch32(&w, b.index_array + 13, NP + 7);
    expect_reader_fail(c, b.n, "control point");
    const char* path = write_file("fbx_order_bad_index.fbx", c, b.n);
    weft_context* ctx = new_context();   /* through the API: refused, the context still works */
    weft_mesh_data md;
    CHECK_EQ_INT(weft_mesh_read(ctx, path, NULL, 1.0, &md), WEFT_ERROR_IMPORT);
    CHECK(md.n_vertices == 0 && md.positions == NULL);
    CHECK(strstr(weft_context_last_error(ctx), "fbx_order_bad_index.fbx") != NULL);
    CHECK_EQ_INT(weft_mesh_read(ctx, ts_tmp_path("fbx_order_raw.fbx"), NULL, 1.0, &md), WEFT_OK);
    weft_mesh_free(ctx, &md);
    weft_context_destroy(ctx);
    free(b.b);

    m = sheet_mesh(1, 7400);   /* a broken deflate stream */
    b = fw_binary(&m);
    c = realloc(c, b.n);
    memcpy(c, b.b, b.n);
    w.b = c;
    for (int k = 0; k < 8; ++k) c[b.vertices_array + 13 + 2 + (size_t)k] ^= 0x5A;
    expect_reader_fail(c, b.n, "inflate");
    memcpy(c, b.b, b.n);   /* a count the compressed bytes cannot hold */
    fw_patch32(&w, b.vertices_array + 1, 0x7ffffff0u);
    expect_reader_fail(c, b.n, "compressed");
    memcpy(c, b.b, b.n);   /* an unknown encoding */
    fw_patch32(&w, b.vertices_array + 5, 7);
    expect_reader_fail(c, b.n, "encoding");
    free(c);
    free(b.b);
}

static void test_corrupt_ascii(void) {
    fw_mesh m = sheet_mesh(0, 0);
    char* t = fw_ascii(&m);
    char* star = strstr(t, "Vertices: *");
    CHECK(star != NULL);
    if (!star) return;
    char* copy = malloc(strlen(t) + 1);
    strcpy(copy, t);   /* a count that says more than the numbers */
    copy[star - t + 11] = '9';
    expect_reader_fail((const unsigned char*)copy, strlen(copy), "Vertices");
    strcpy(copy, t);   /* no `*N { a: }` form */
    memcpy(copy + (star - t) + 10, "   ", 3);
    expect_reader_fail((const unsigned char*)copy, strlen(copy), "*N");
    strcpy(copy, t);   /* cut inside the array: no closing brace */
    expect_reader_fail((const unsigned char*)copy, (size_t)(star - t) + 40, "Vertices");
    strcpy(copy, t);   /* a number that does not parse */
    char* a = strstr(copy, "a: ");
    a[3] = 'x';
    expect_reader_fail((const unsigned char*)copy, strlen(copy), "parse");
    free(copy);
    free(t);
}

/* assimp's mesh against a file whose geometry says otherwise (a control point moved): the
 * matcher names the mesh and face instead of reporting a wrong order. */
static void test_unmatched_polygon(void) {
    const char* path = ts_tmp_path("fbx_order_raw.fbx");
    const struct aiScene* s = aiImportFile(path, aiProcess_JoinIdenticalVertices);
    CHECK(s != NULL && s->mNumMeshes == 1);
    if (!s) return;
    fw_mesh m = sheet_mesh(0, 7400);
    fw_buf b = fw_binary(&m);
    wc_fbx_geometries g;
    wc_diag d;
    memset(&d, 0, sizeof d);
    CHECK_EQ_INT(wc_fbx_geometry_read(&g, NULL, b.b, b.n, path, &d), WC_OK);
    wc_import_instance inst;
    memset(&inst, 0, sizeof inst);
    inst.mesh = 0;
    inst.node = s->mRootNode;
    inst.m[0] = inst.m[5] = inst.m[10] = 1.0;
    wc_file_order o;
    CHECK_EQ_INT(wc_fbx_file_order(s, &inst, 1, &g, &o, NULL, path, &d), WC_OK);
    CHECK_EQ_INT(o.n_v, NP);
    wc_file_order_free(&o);
    g.g[0].points[3 * quads[7][2] + 1] += 3.0;   /* the third corner of quad 7 */
    CHECK_EQ_INT(wc_fbx_file_order(s, &inst, 1, &g, &o, NULL, path, &d), WC_ERROR_IMPORT);
    CHECK(o.corner_v == NULL && o.n_v == 0);
    CHECK(strstr(d.message, "face 7 of mesh 'sheet'") != NULL);
    if (!strstr(d.message, "face 7 of mesh 'sheet'")) fprintf(stderr, "%s\n", d.message);
    wc_fbx_geometry_free(&g);
    free(b.b);
    aiReleaseImport(s);
}

int main(void) {
    make_sheet();
    RUN_TEST(test_binary_raw);
    RUN_TEST(test_binary_deflated);
    RUN_TEST(test_binary_7500);
    RUN_TEST(test_ascii);
    RUN_TEST(test_unused_point);
    RUN_TEST(test_memory);
    RUN_TEST(test_several_geometries);
    RUN_TEST(test_material_split);
    RUN_TEST(test_poncho);
    RUN_TEST(test_truncated);
    RUN_TEST(test_corrupt_binary);
    RUN_TEST(test_corrupt_ascii);
    RUN_TEST(test_unmatched_polygon);
    return TEST_SUMMARY();
}
