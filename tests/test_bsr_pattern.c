/* The block pattern and per-row lists against brute force over the springs, and the RCM
 * renumbering: a permutation that keeps the model identical up to numbering and shrinks the
 * bandwidth of a shuffled mesh. */
#include <stdlib.h>
#include "check.h"
#include "model.h"
#include "ordering.h"
#include "test_support.h"

static wc_model build(const wc_source_mesh* src, int reorder) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = wc_default_model_def();
    def.reorder = reorder;
    wc_status st = wc_model_build(&m, src, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "build failed: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return m;
}

static int bandwidth(const wc_model* m) {
    int bw = 0;
    for (int s = 0; s < m->n_springs; ++s) {
        int d = abs(m->springs[s].a - m->springs[s].b);
        if (d > bw) bw = d;
    }
    return bw;
}

static void check_pattern(const wc_model* m) {
    const wc_bsr_pattern* p = &m->pattern;
    int n = m->n_particles;
    CHECK_EQ_INT(p->n_rows, n);
    /* dense adjacency by brute force */
    unsigned char* adj = calloc((size_t)n * n, 1);
    for (int i = 0; i < n; ++i) adj[(size_t)i * n + i] = 1;
    for (int s = 0; s < m->n_springs; ++s) {
        adj[(size_t)m->springs[s].a * n + m->springs[s].b] = 1;
        adj[(size_t)m->springs[s].b * n + m->springs[s].a] = 1;
    }
    int expect = 0, bad = 0;
    for (size_t k = 0; k < (size_t)n * n; ++k) expect += adj[k];
    CHECK_EQ_INT(p->n_blocks, expect);
    for (int i = 0; i < n; ++i) {
        if (p->col[p->diag[i]] != i) ++bad;
        for (int b = p->row_start[i]; b < p->row_start[i + 1]; ++b) {
            if (b > p->row_start[i] && p->col[b] <= p->col[b - 1]) ++bad;
            if (!adj[(size_t)i * n + p->col[b]]) ++bad;
            int t = p->transpose[b];
            if (t < 0 || p->col[t] != i || !(t >= p->row_start[p->col[b]] && t < p->row_start[p->col[b] + 1])) ++bad;
        }
    }
    CHECK_EQ_INT(bad, 0);
    /* every spring appears once in each end's row, with the right block and sign */
    int* seen = calloc((size_t)m->n_springs, sizeof(int));
    for (int i = 0; i < n; ++i)
        for (int k = p->row_spring_start[i]; k < p->row_spring_start[i + 1]; ++k) {
            const wc_spring* s = &m->springs[p->row_spring[k]];
            int other = p->row_spring_sign[k] > 0 ? s->b : s->a;
            int self = p->row_spring_sign[k] > 0 ? s->a : s->b;
            if (self != i || p->col[p->row_spring_block[k]] != other) ++bad;
            ++seen[p->row_spring[k]];
        }
    for (int s = 0; s < m->n_springs; ++s)
        if (seen[s] != 2) ++bad;
    CHECK_EQ_INT(bad, 0);
    /* triangles per particle */
    int total = 0;
    for (int i = 0; i < n; ++i)
        for (int k = p->row_tri_start[i]; k < p->row_tri_start[i + 1]; ++k) {
            const int* t = m->tris + 3 * p->row_tri[k];
            if (t[0] != i && t[1] != i && t[2] != i) ++bad;
            ++total;
        }
    CHECK_EQ_INT(total, 3 * m->n_tris);
    CHECK_EQ_INT(bad, 0);
    free(seen);
    free(adj);
}

static void test_pattern_grids(void) {
    wc_source_mesh src;
    ts_quad_grid(&src, 9, 7, 1.0, 1.0, 0);
    wc_model a = build(&src, 1), b = build(&src, 0);
    check_pattern(&a);
    check_pattern(&b);
    wc_model_free(&a);
    wc_model_free(&b);
    wc_source_mesh_free(&src);
    ts_tri_grid(&src, 6, 11, 1.0, 2.0);
    a = build(&src, 1);
    check_pattern(&a);
    wc_model_free(&a);
    wc_source_mesh_free(&src);
}

/* A grid whose vertices are listed in random order: RCM brings the bandwidth down to about the
 * grid's width and the model is the same up to numbering (same springs, masses, positions). */
static void test_rcm_shuffled(void) {
    int nx = 30, ny = 20;
    wc_source_mesh grid;
    ts_quad_grid(&grid, nx, ny, 3.0, 2.0, 0);
    int nv = grid.n_verts;
    int* perm = malloc(sizeof(int) * nv);
    for (int i = 0; i < nv; ++i) perm[i] = i;
    srand(7);
    for (int i = nv - 1; i > 0; --i) {
        int j = rand() % (i + 1), t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    double* pos = malloc(sizeof(double) * 3 * nv);
    for (int v = 0; v < nv; ++v)
        for (int k = 0; k < 3; ++k) pos[3 * perm[v] + k] = grid.pos[3 * v + k];
    int* pv = malloc(sizeof(int) * grid.poly_start[grid.n_polys]);
    int* sizes = malloc(sizeof(int) * grid.n_polys);
    for (int k = 0; k < grid.poly_start[grid.n_polys]; ++k) pv[k] = perm[grid.poly_verts[k]];
    for (int k = 0; k < grid.n_polys; ++k) sizes[k] = grid.poly_start[k + 1] - grid.poly_start[k];
    wc_source_mesh shuffled;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&shuffled, NULL, pos, nv, sizes, grid.n_polys, pv, 1.0, &d), WC_OK);
    wc_model plain = build(&shuffled, 0), rcm = build(&shuffled, 1);
    printf("  bandwidth shuffled %d, rcm %d (grid %d x %d)\n", bandwidth(&plain), bandwidth(&rcm), nx, ny);
    CHECK(bandwidth(&plain) > 10 * nx);
    CHECK(bandwidth(&rcm) <= 3 * (nx < ny ? nx : ny));
    CHECK_EQ_INT(rcm.n_springs, plain.n_springs);
    /* same particle for each host vertex up to numbering: positions and masses agree */
    int bad = 0;
    for (int v = 0; v < nv; ++v) {
        int p = plain.host_to_particle[v], q = rcm.host_to_particle[v];
        for (int k = 0; k < 3; ++k)
            if (plain.rest_pos[3 * p + k] != rcm.rest_pos[3 * q + k]) ++bad;
        if (fabs(plain.mass[p] - rcm.mass[q]) > 1e-15) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    check_pattern(&rcm);
    wc_model_free(&plain);
    wc_model_free(&rcm);
    wc_source_mesh_free(&shuffled);
    wc_source_mesh_free(&grid);
    free(pos);
    free(pv);
    free(sizes);
    free(perm);
}

int main(void) {
    RUN_TEST(test_pattern_grids);
    RUN_TEST(test_rcm_shuffled);
    return TEST_SUMMARY();
}
