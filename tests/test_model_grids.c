/* Spring counts, welding and winged-edge invariants on generated grids, checked against closed
 * forms derived by hand from the grid geometry (not from the code under test). */
#include <stdlib.h>
#include "check.h"
#include "model.h"
#include "test_support.h"
#include "topology.h"

static wc_model build(const wc_source_mesh* src, double weld_tol) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = wc_default_model_def();
    def.weld_tolerance = weld_tol;
    wc_status st = wc_model_build(&m, src, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "build failed: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return m;
}

/* Each edge's faces contain it, wings are the neighbouring edges of the same face, every face's
 * edges point back to it, and V - E + F = 2 - 2g - b per component (g = 0 for these meshes). */
static void check_winged_edge(const wc_model* m, int genus) {
    const wc_winged_edge* we = &m->we;
    int bad = 0;
    for (int e = 0; e < we->n_edges; ++e) {
        const wc_we_edge* ed = &we->edges[e];
        if (!(ed->v[0] < ed->v[1])) ++bad;
        for (int s = 0; s < 2; ++s) {
            int f = ed->f[s];
            if (f < 0) {
                if (s == 0 || ed->prev[s] != -1 || ed->next[s] != -1) ++bad;
                continue;
            }
            const wc_we_face* fc = &we->faces[f];
            int k = -1;
            for (int q = 0; q < 3; ++q)
                if (fc->e[q] == e) k = q;
            if (k < 0) { ++bad; continue; }
            int a = fc->v[k], b = fc->v[(k + 1) % 3];
            if (!((a == ed->v[0] && b == ed->v[1]) || (a == ed->v[1] && b == ed->v[0]))) ++bad;
            if (ed->prev[s] != fc->e[(k + 2) % 3] || ed->next[s] != fc->e[(k + 1) % 3]) ++bad;
        }
    }
    for (int f = 0; f < we->n_faces; ++f)
        for (int k = 0; k < 3; ++k) {
            const wc_we_edge* ed = &we->edges[we->faces[f].e[k]];
            if (ed->f[0] != f && ed->f[1] != f) ++bad;
        }
    for (int v = 0; v < we->n_verts; ++v) {
        int e = we->vert_edge[v];
        if (e < 0 || (we->edges[e].v[0] != v && we->edges[e].v[1] != v)) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    /* Euler characteristic per component vs its boundary loops */
    int nc = m->n_components;
    int* chi = calloc((size_t)nc, sizeof(int));
    for (int v = 0; v < m->n_particles; ++v) chi[m->particle_component[v]] += 1;
    for (int e = 0; e < we->n_edges; ++e) chi[m->particle_component[we->edges[e].v[0]]] -= 1;
    for (int f = 0; f < we->n_faces; ++f) chi[m->particle_component[we->faces[f].v[0]]] += 1;
    int chi_sum = 0;
    for (int c = 0; c < nc; ++c) chi_sum += chi[c];
    CHECK_EQ_INT(chi_sum, nc * (2 - 2 * genus) - m->report.boundary_loops);
    free(chi);
}

static void test_quad_grid_counts(void) {
    for (int nx = 2; nx <= 9; ++nx)
        for (int ny = 2; ny <= 7; ++ny) {
            wc_source_mesh src;
            ts_quad_grid(&src, nx, ny, 1.0, 0.7, 0);
            wc_model m = build(&src, 1e-6);
            CHECK_EQ_INT(m.n_particles, nx * ny);
            CHECK_EQ_INT(m.n_tris, 2 * (nx - 1) * (ny - 1));
            CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], nx * (ny - 1) + ny * (nx - 1));
            CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 2 * (nx - 1) * (ny - 1));
            CHECK_EQ_INT(m.report.springs[WC_SPRING_BEND], nx * (ny - 2) + ny * (nx - 2));
            CHECK_EQ_INT(m.report.boundary_edges, 2 * (nx - 1) + 2 * (ny - 1));
            CHECK_EQ_INT(m.report.boundary_loops, 1);
            CHECK_EQ_INT(m.report.components, 1);
            CHECK_EQ_INT(m.report.polygons[4], (nx - 1) * (ny - 1));
            check_winged_edge(&m, 0);
            wc_model_free(&m);
            wc_source_mesh_free(&src);
        }
    /* the square form: 2N(N-1), 2(N-1)^2, 2N(N-2) */
    const int N = 20;
    wc_source_mesh src;
    ts_quad_grid(&src, N, N, 1.0, 1.0, 0);
    wc_model m = build(&src, 1e-6);
    CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 2 * N * (N - 1));
    CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], 2 * (N - 1) * (N - 1));
    CHECK_EQ_INT(m.report.springs[WC_SPRING_BEND], 2 * N * (N - 2));
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

/* Rest lengths: stretch h, shear h*sqrt(2) for a square grid, bend 2h; bend pairs at (+-2,0),(0,+-2). */
static void test_quad_grid_geometry(void) {
    const int N = 6;
    const double h = 0.2;
    wc_source_mesh src;
    ts_quad_grid(&src, N, N, h * (N - 1), h * (N - 1), 0);
    wc_model m = build(&src, 1e-6);
    int bad = 0;
    for (int i = 0; i < m.n_springs; ++i) {
        const wc_spring* s = &m.springs[i];
        double want = s->type == WC_SPRING_STRETCH ? h : s->type == WC_SPRING_SHEAR ? h * sqrt(2.0) : 2 * h;
        if (fabs(s->rest - want) > 1e-12) ++bad;
        if (!(s->a < s->b)) ++bad;
        if (i > 0 && m.springs[i - 1].type > s->type) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    /* lumped mass: total = area x density */
    double total = 0;
    for (int p = 0; p < m.n_particles; ++p) total += m.mass[p];
    CHECK_NEAR(total, (h * (N - 1)) * (h * (N - 1)) * m.material.density, 1e-12);
    wc_model_free(&m);
    wc_source_mesh_free(&src);
}

/* Triangle grid (cells cut along (i,j)-(i+1,j+1)), derived by hand with M = N - 1:
 *   stretch = 2NM + M^2 (the diagonals are real edges);
 *   shear   = M^2 (anti-diagonal across each diagonal) + 2M(M-1) (offsets (1,2), (2,1) across
 *             interior horizontal and vertical edges);
 *   bend    = 2N(N-2) + (N-2)^2 (offsets (2,0), (0,2) and (2,2)). */
static void test_tri_grid_counts(void) {
    for (int N = 3; N <= 12; ++N) {
        int M = N - 1;
        wc_source_mesh src;
        ts_tri_grid(&src, N, N, 1.0, 1.0);
        wc_model m = build(&src, 1e-6);
        CHECK_EQ_INT(m.report.springs[WC_SPRING_STRETCH], 2 * N * M + M * M);
        CHECK_EQ_INT(m.report.springs[WC_SPRING_SHEAR], M * M + 2 * M * (M - 1));
        CHECK_EQ_INT(m.report.springs[WC_SPRING_BEND], 2 * N * (N - 2) + (N - 2) * (N - 2));
        CHECK_EQ_INT(m.report.polygons[3], 2 * M * M);
        check_winged_edge(&m, 0);
        wc_model_free(&m);
        wc_source_mesh_free(&src);
    }
}

/* Every quad with its own four vertices (per-quad UVs): welding recovers the shared grid and the
 * host map sends each host vertex to the particle at its position. */
static void test_split_uv_weld(void) {
    const int N = 7;
    wc_source_mesh split, plain;
    ts_quad_grid(&split, N, N, 1.0, 1.0, 1);
    ts_quad_grid(&plain, N, N, 1.0, 1.0, 0);
    CHECK_EQ_INT(split.n_verts, 4 * (N - 1) * (N - 1));
    wc_model a = build(&split, 1e-6), b = build(&plain, 1e-6);
    CHECK_EQ_INT(a.n_particles, N * N);
    CHECK_EQ_INT(a.report.welded_vertices, 4 * (N - 1) * (N - 1) - N * N);
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) CHECK_EQ_INT(a.report.springs[t], b.report.springs[t]);
    int bad = 0;
    for (int v = 0; v < split.n_verts; ++v) {
        int p = a.host_to_particle[v];
        if (p < 0) { ++bad; continue; }
        for (int k = 0; k < 3; ++k)
            if (a.rest_pos[3 * p + k] != split.pos[3 * v + k]) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    check_winged_edge(&a, 0);
    wc_model_free(&a);
    /* tolerance 0 disables welding: every quad is its own island */
    wc_model c = build(&split, 0.0);
    CHECK_EQ_INT(c.n_particles, 4 * (N - 1) * (N - 1));
    CHECK_EQ_INT(c.report.components, (N - 1) * (N - 1));
    CHECK_EQ_INT(c.report.springs[WC_SPRING_STRETCH], 4 * (N - 1) * (N - 1));
    check_winged_edge(&c, 0);
    wc_model_free(&c);
    wc_model_free(&b);
    wc_source_mesh_free(&split);
    wc_source_mesh_free(&plain);
}

/* Near-coincident vertices weld within the tolerance and stay apart beyond it. */
static void test_weld_tolerance(void) {
    /* two triangles whose shared edge vertices are offset by 1e-4 (bbox diagonal ~1.414) */
    double pos[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, /* tri 1 */
                    1 + 1e-4, 0, 0, 1, 1, 0, 0, 1 + 1e-4, 0 /* tri 2 */};
    int sizes[] = {3, 3}, idx[] = {0, 1, 2, 3, 4, 5};
    wc_source_mesh src;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, 6, sizes, 2, idx, 1.0, &d), WC_OK);
    wc_model loose = build(&src, 1e-3), tight = build(&src, 1e-6);
    CHECK_EQ_INT(loose.n_particles, 4);
    CHECK_EQ_INT(loose.report.components, 1);
    CHECK_EQ_INT(tight.n_particles, 6);
    CHECK_EQ_INT(tight.report.components, 2);
    CHECK_EQ_INT(loose.host_to_particle[3], loose.host_to_particle[1]);
    CHECK_EQ_INT(loose.host_to_particle[5], loose.host_to_particle[2]);
    wc_model_free(&loose);
    wc_model_free(&tight);
    wc_source_mesh_free(&src);
}

int main(void) {
    RUN_TEST(test_quad_grid_counts);
    RUN_TEST(test_quad_grid_geometry);
    RUN_TEST(test_tri_grid_counts);
    RUN_TEST(test_split_uv_weld);
    RUN_TEST(test_weld_tolerance);
    return TEST_SUMMARY();
}
