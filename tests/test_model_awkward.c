/* Awkward and bad meshes through the model builder: every oddity is counted and warned about,
 * nothing crashes, and a mesh with nothing usable is refused with an intact (zeroed) output. */
#include <stdlib.h>
#include "check.h"
#include "model.h"
#include "test_support.h"
#include "weld.h"

static wc_status build_arrays(wc_model* m, const double* pos, int nv, const int* sizes, int np,
                                const int* idx, wc_diag* d) {
    wc_source_mesh src;
    wc_status st = wc_source_mesh_from_arrays(&src, NULL, pos, nv, sizes, np, idx, 1.0, d);
    if (st != WC_OK) return st;
    wc_model_def def = wc_default_model_def();
    st = wc_model_build(m, &src, &def, NULL, d);
    wc_source_mesh_free(&src);
    return st;
}

static int has_warning(const wc_model* m, const char* word) {
    for (int i = 0; i < m->report.n_warnings; ++i)
        if (strstr(m->report.warnings[i], word)) return 1;
    return 0;
}

/* Every manifold interior edge is traversed in opposite directions by its two faces. */
static int consistently_wound(const wc_model* m) {
    const wc_winged_edge* we = &m->we;
    for (int e = 0; e < we->n_edges; ++e) {
        const wc_we_edge* ed = &we->edges[e];
        if (ed->f[1] < 0) continue;
        int dir[2] = {0, 0};
        for (int s = 0; s < 2; ++s) {
            const wc_we_face* f = &we->faces[ed->f[s]];
            for (int k = 0; k < 3; ++k)
                if (f->e[k] == e) dir[s] = f->v[k] == ed->v[0];
        }
        if (dir[0] == dir[1]) return 0;
    }
    return 1;
}

static void test_non_manifold_edge(void) {
    /* three triangles on the edge 0-1 (a "book" of three pages) */
    double pos[] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1};
    int sizes[] = {3, 3, 3}, idx[] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 5, sizes, 3, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.non_manifold_edges, 1);
    CHECK_EQ_INT(m.report.edges, 8);           /* 6 outer edges + the shared edge + one copy */
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 7);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 0); /* none across a non-manifold edge */
    CHECK(has_warning(&m, "non-manifold"));
    int flagged = 0;
    for (int e = 0; e < m.we.n_edges; ++e) flagged += (m.we.edges[e].flags & WC_EDGE_NON_MANIFOLD) != 0;
    CHECK_EQ_INT(flagged, 2);
    wc_model_free(&m);
}

static void test_degenerate_and_duplicates(void) {
    /* a unit quad, a collinear triangle (zero area), a triangle repeating a vertex,
       the quad's first triangle again (reversed) and an unreferenced vertex */
    double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, /* quad */
                    2, 0, 0, 3, 0, 0, 4, 0, 0,          /* collinear */
                    9, 9, 9};                           /* unused */
    int sizes[] = {4, 3, 3, 3}, idx[] = {0, 1, 2, 3, 4, 5, 6, 0, 1, 1, 2, 1, 0};
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 8, sizes, 4, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.degenerate_triangles, 2);
    CHECK_EQ_INT(m.report.duplicate_faces, 1);
    CHECK_EQ_INT(m.report.triangles, 2);
    CHECK_EQ_INT(m.n_particles, 4);
    CHECK_EQ_INT(m.report.unused_vertices, 4); /* 3 of the collinear triangle + the loose one */
    CHECK_EQ_INT(m.host_to_particle[7], -1);
    CHECK_EQ_INT(m.host_to_particle[4], -1);
    CHECK(has_warning(&m, "degenerate"));
    CHECK(has_warning(&m, "duplicate"));
    CHECK(has_warning(&m, "no particle"));
    /* the model still has the quad's springs */
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 4);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 2);
    wc_model_free(&m);
}

static void test_inconsistent_winding(void) {
    /* 3x2 quads with the middle quad's corners listed clockwise */
    double pos[4 * 3 * 3];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) {
            double* p = pos + 3 * (j * 4 + i);
            p[0] = i; p[1] = j; p[2] = 0;
        }
    int sizes[6] = {4, 4, 4, 4, 4, 4}, idx[24], q = 0;
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i, ++q) {
            int c[4] = {j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i};
            for (int k = 0; k < 4; ++k) idx[4 * q + k] = (q == 1) ? c[3 - k] : c[k];
        }
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 12, sizes, 6, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.flipped_faces, 2); /* the minority: one quad's two triangles */
    CHECK_EQ_INT(m.report.non_orientable_components, 0);
    CHECK(consistently_wound(&m));
    CHECK(has_warning(&m, "winding"));
    /* the fix keeps the majority's orientation: normals along +z */
    int up = 0;
    for (int f = 0; f < m.n_tris; ++f) {
        const double* a = m.rest_pos + 3 * m.tris[3 * f];
        const double* b = m.rest_pos + 3 * m.tris[3 * f + 1];
        const double* c = m.rest_pos + 3 * m.tris[3 * f + 2];
        double z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        up += z > 0;
    }
    CHECK_EQ_INT(up, m.n_tris);
    wc_model_free(&m);
}

static void test_moebius_strip(void) {
    enum { SEG = 12 };
    double pos[SEG * 2 * 3];
    for (int i = 0; i < SEG; ++i) {
        double u = 2 * 3.14159265358979 * i / SEG;
        for (int s = 0; s < 2; ++s) {
            double w = s ? 0.2 : -0.2;
            double* p = pos + 3 * (2 * i + s);
            p[0] = (1 + w * cos(u / 2)) * cos(u);
            p[1] = (1 + w * cos(u / 2)) * sin(u);
            p[2] = w * sin(u / 2);
        }
    }
    int sizes[SEG], idx[4 * SEG];
    for (int i = 0; i < SEG; ++i) {
        int a = 2 * i, b = 2 * i + 1, c, dd;
        if (i + 1 < SEG) { c = 2 * (i + 1) + 1; dd = 2 * (i + 1); }
        else { c = 0; dd = 1; } /* the half twist: sides swap */
        sizes[i] = 4;
        int q[4] = {a, dd, c, b};
        memcpy(idx + 4 * i, q, sizeof q);
    }
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 2 * SEG, sizes, SEG, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.non_orientable_components, 1);
    CHECK_EQ_INT(m.report.components, 1);
    CHECK_EQ_INT(m.report.boundary_loops, 1); /* a Moebius strip has one boundary loop */
    CHECK(has_warning(&m, "non-orientable"));
    wc_model_free(&m);
}

static void test_points_lines_and_components(void) {
    /* two separate triangles, a line and a point */
    double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 6, 0, 0, 5, 1, 0};
    int sizes[] = {3, 2, 3, 1}, idx[] = {0, 1, 2, 0, 3, 3, 4, 5, 1};
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 6, sizes, 4, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.polygons[1], 1);
    CHECK_EQ_INT(m.report.polygons[2], 1);
    CHECK_EQ_INT(m.report.polygons[3], 2);
    CHECK_EQ_INT(m.report.components, 2);
    CHECK_EQ_INT(m.report.boundary_loops, 2);
    CHECK_EQ_INT(m.report.boundary_edges, 6);
    CHECK(has_warning(&m, "line"));
    CHECK(m.particle_component[m.host_to_particle[0]] != m.particle_component[m.host_to_particle[3]]);
    wc_model_free(&m);
}

/* An L-shaped hexagon (concave): ear clipping gives 4 triangles covering exactly its area, and
 * only its 6 sides are stretch springs. */
static void test_concave_polygon(void) {
    double pos[] = {0, 0, 0, 2, 0, 0, 2, 1, 0, 1, 1, 0, 1, 2, 0, 0, 2, 0};
    int sizes[] = {6}, idx[] = {0, 1, 2, 3, 4, 5};
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 6, sizes, 1, idx, &d), WC_OK);
    CHECK_EQ_INT(m.n_tris, 4);
    double area = 0;
    for (int t = 0; t < m.n_tris; ++t) area += m.tri_rest_area[t];
    CHECK_NEAR(area, 3.0, 1e-12);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 6);
    CHECK_EQ_INT(m.report.polygons[6], 1);
    CHECK(consistently_wound(&m));
    wc_model_free(&m);
}

/* A 5000-gon (a disc's cap): fanned instead of ear-clipped, exact area, a warning, and quick. */
static void test_huge_polygon(void) {
    enum { K = 5000 };
    double* pos = malloc(sizeof(double) * 3 * K);
    int* idx = malloc(sizeof(int) * K);
    int sizes[1] = {K};
    for (int i = 0; i < K; ++i) {
        double a = 2 * 3.14159265358979323846 * i / K;
        pos[3 * i] = cos(a);
        pos[3 * i + 1] = sin(a);
        pos[3 * i + 2] = 0;
        idx[i] = i;
    }
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, K, sizes, 1, idx, &d), WC_OK);
    CHECK_EQ_INT(m.n_tris, K - 2);
    double area = 0;
    for (int t = 0; t < m.n_tris; ++t) area += m.tri_rest_area[t];
    CHECK_NEAR(area, 0.5 * K * sin(2 * 3.14159265358979323846 / K), 1e-9);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], K);
    CHECK(has_warning(&m, "fanned"));
    wc_model_free(&m);
    free(pos);
    free(idx);
}

/* A quad next to a triangle: the quad's two diagonals plus one wing spring across the shared
 * edge (one of its faces is not from a quad). */
static void test_mixed_quad_triangle(void) {
    double pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 2, 0.5, 0};
    int sizes[] = {4, 3}, idx[] = {0, 1, 2, 3, 1, 4, 2};
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 5, sizes, 2, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 6);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 3);
    int wing = 0;
    for (int s = m.spring_type_start[WC_SPRING_SHEAR]; s < m.spring_type_start[WC_SPRING_SHEAR + 1]; ++s)
        wing += m.springs[s].b == 4 || m.springs[s].a == 4;
    CHECK_EQ_INT(wing, 1);
    wc_model_free(&m);
}

/* Closed quad surfaces: a cube (chi = 2) and a torus (chi = 0); no boundary. */
static void test_closed_surfaces(void) {
    double cube[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    int sizes[] = {4, 4, 4, 4, 4, 4};
    int idx[] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    wc_model m;
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, cube, 8, sizes, 6, idx, &d), WC_OK);
    CHECK_EQ_INT(m.report.boundary_edges, 0);
    CHECK_EQ_INT(m.report.boundary_loops, 0);
    CHECK_EQ_INT(m.n_particles - m.we.n_edges + m.n_tris, 2);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 12);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 12);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_BEND], 0);
    CHECK_EQ_INT(m.report.flipped_faces, 0);
    wc_model_free(&m);

    enum { U = 12, V = 16 }; /* regular 12- and 16-gons: interior angles 150 and 157.5 deg */
    double tor[U * V * 3];
    int ts[U * V], ti[4 * U * V];
    for (int i = 0; i < U; ++i)
        for (int j = 0; j < V; ++j) {
            double a = 2 * 3.14159265358979 * i / U, b = 2 * 3.14159265358979 * j / V;
            double* p = tor + 3 * (i * V + j);
            p[0] = (1 + 0.3 * cos(b)) * cos(a);
            p[1] = (1 + 0.3 * cos(b)) * sin(a);
            p[2] = 0.3 * sin(b);
            int q[4] = {i * V + j, ((i + 1) % U) * V + j, ((i + 1) % U) * V + (j + 1) % V, i * V + (j + 1) % V};
            ts[i * V + j] = 4;
            memcpy(ti + 4 * (i * V + j), q, sizeof q);
        }
    CHECK_EQ_INT(build_arrays(&m, tor, U * V, ts, U * V, ti, &d), WC_OK);
    CHECK_EQ_INT(m.n_particles - m.we.n_edges + m.n_tris, 0);
    CHECK_EQ_INT(m.report.boundary_loops, 0);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 2 * U * V);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 2 * U * V);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_BEND], 2 * U * V);
    CHECK(consistently_wound(&m));
    wc_model_free(&m);
}

static void test_nothing_usable(void) {
    double pos[] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    int sizes[] = {3, 2}, idx[] = {0, 1, 2, 0, 1};
    wc_model m;
    memset(&m, 0x5a, sizeof m);
    wc_diag d = {0};
    CHECK_EQ_INT(build_arrays(&m, pos, 3, sizes, 2, idx, &d), WC_ERROR_EMPTY_MESH);
    CHECK(strstr(d.message, "no usable triangles") != NULL);
    CHECK(m.n_particles == 0 && m.rest_pos == NULL && m.springs == NULL);
    wc_model_free(&m); /* freeing a zeroed model is harmless */

    int only_lines[] = {2}, li[] = {0, 1};
    CHECK_EQ_INT(build_arrays(&m, pos, 3, only_lines, 1, li, &d), WC_ERROR_EMPTY_MESH);

    /* bad definition values are refused before any work */
    wc_source_mesh src;
    ts_quad_grid(&src, 3, 3, 1, 1, 0);
    wc_model_def def = wc_default_model_def();
    def.weld_tolerance = NAN;
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(d.message, "weld_tolerance") != NULL);
    def = wc_default_model_def();
    def.material.density = -1;
    CHECK_EQ_INT(wc_model_build(&m, &src, &def, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(d.message, "density") != NULL);
    CHECK_EQ_INT(wc_model_build(&m, NULL, &def, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    wc_source_mesh_free(&src);
}

/* Coordinates far beyond any cell index (a fuzzed host array had 1e42 m): the cells clamp, the
 * exact distance still decides (fuzz/regressions/cloth_arrays/weld_huge_coordinate_cell_overflow
 * is the input that found it; the sanitizer build failed on the conversion). */
static void test_weld_far_coordinates(void) {
    const double pos[] = {1e42, -1e42, 1e300,  1e42, -1e42, 1e300,  1.001e42, -1e42, 1e300,
                          0.0, 0.0, 0.0,      0.0005, 0.0, 0.0,     -1e42, 5e41, -1e300};
    const unsigned char used[] = {1, 1, 1, 1, 1, 1};
    int to[6];
    int count = wc_weld(pos, used, 6, 0.001, to, NULL);
    CHECK_EQ_INT(count, 4);
    CHECK_EQ_INT(to[0], to[1]);  /* coincident far away: one particle */
    CHECK(to[2] != to[0]);       /* 1e39 m from them */
    CHECK_EQ_INT(to[3], to[4]);  /* 0.5 mm apart near the origin */
    CHECK(to[5] != to[0] && to[5] != to[3]);
}

int main(void) {
    RUN_TEST(test_non_manifold_edge);
    RUN_TEST(test_degenerate_and_duplicates);
    RUN_TEST(test_inconsistent_winding);
    RUN_TEST(test_moebius_strip);
    RUN_TEST(test_points_lines_and_components);
    RUN_TEST(test_concave_polygon);
    RUN_TEST(test_huge_polygon);
    RUN_TEST(test_mixed_quad_triangle);
    RUN_TEST(test_closed_surfaces);
    RUN_TEST(test_nothing_usable);
    RUN_TEST(test_weld_far_coordinates);
    return TEST_SUMMARY();
}
