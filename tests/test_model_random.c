/* Random soups of polygons (repeated indices, coincident and collinear points, points, lines,
 * n-gons, non-manifold fans): the builder never crashes, either refuses with EMPTY_MESH or
 * returns a model whose invariants hold. Deterministic (fixed LCG seed); run under ASan in CI. */
#include <stdint.h>
#include <stdlib.h>
#include "check.h"
#include "model.h"

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static unsigned next_u(void) {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return (unsigned)(rng >> 33);
}
static int rand_int(int n) { return (int)(next_u() % (unsigned)n); }

static int model_invariants_hold(const wc_model* m, int n_host) {
    int bad = 0;
    for (int t = 0; t < m->n_tris; ++t) {
        const int* v = m->tris + 3 * t;
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) ++bad;
        for (int k = 0; k < 3; ++k)
            if (v[k] < 0 || v[k] >= m->n_particles) ++bad;
        if (!(m->tri_rest_area[t] > 0)) ++bad;
    }
    for (int v = 0; v < n_host; ++v)
        if (m->host_to_particle[v] < -1 || m->host_to_particle[v] >= m->n_particles) ++bad;
    for (int p = 0; p < m->n_particles; ++p) {
        int h = m->particle_to_host[p];
        if (h < 0 || h >= n_host || m->host_to_particle[h] != p) ++bad;
        if (!(m->mass[p] > 0) || !isfinite(m->inv_mass[p])) ++bad;
    }
    for (int s = 0; s < m->n_springs; ++s) {
        const wc_spring* sp = &m->springs[s];
        if (!(sp->a < sp->b) || sp->b >= m->n_particles || !isfinite(sp->rest)) ++bad;
        if (s < m->spring_type_start[sp->type] || s >= m->spring_type_start[sp->type + 1]) ++bad;
        /* one spring per pair (sorted by (a, b) within a type; across types checked below) */
        if (s > 0 && m->springs[s - 1].type == sp->type &&
            !(m->springs[s - 1].a < sp->a || (m->springs[s - 1].a == sp->a && m->springs[s - 1].b < sp->b)))
            ++bad;
    }
    for (int s = 0; s < m->n_springs; ++s) /* across types: O(n^2) is fine at these sizes */
        for (int q = s + 1; q < m->n_springs; ++q)
            if (m->springs[s].a == m->springs[q].a && m->springs[s].b == m->springs[q].b) ++bad;
    const wc_winged_edge* we = &m->we;
    for (int e = 0; e < we->n_edges; ++e)
        for (int s = 0; s < 2; ++s) {
            int f = we->edges[e].f[s];
            if (f < 0) continue;
            int found = 0;
            for (int k = 0; k < 3; ++k) found += we->faces[f].e[k] == e;
            if (found != 1) ++bad;
        }
    for (int f = 0; f < we->n_faces; ++f)
        for (int k = 0; k < 3; ++k) {
            const wc_we_edge* ed = &we->edges[we->faces[f].e[k]];
            if (ed->f[0] != f && ed->f[1] != f) ++bad;
        }
    int comps_seen = 0;
    for (int p = 0; p < m->n_particles; ++p)
        if (m->particle_component[p] + 1 > comps_seen) comps_seen = m->particle_component[p] + 1;
    if (comps_seen != m->n_components) ++bad;
    return bad == 0;
}

static void test_random_soups(void) {
    int built = 0, refused = 0, broken = 0;
    for (int iter = 0; iter < 400; ++iter) {
        int nv = 1 + rand_int(40), np = 1 + rand_int(30);
        double* pos = malloc(sizeof(double) * 3 * (size_t)nv);
        for (int v = 0; v < nv; ++v)
            for (int k = 0; k < 3; ++k) {
                int mode = rand_int(10);
                /* coarse lattice -> coincident and collinear points; sometimes all z = 0 */
                pos[3 * v + k] = mode < 6 ? rand_int(4) * 0.5 : mode < 9 ? (double)rand_int(1000) / 997.0 : 0.0;
            }
        if (rand_int(4) == 0 && nv > 1) memcpy(pos + 3, pos, 3 * sizeof(double)); /* exact duplicate */
        int* sizes = malloc(sizeof(int) * (size_t)np);
        int total = 0;
        for (int p = 0; p < np; ++p) {
            int r = rand_int(20);
            sizes[p] = r < 1 ? 1 : r < 2 ? 2 : r < 10 ? 3 : r < 16 ? 4 : 5 + rand_int(4);
            total += sizes[p];
        }
        int* idx = malloc(sizeof(int) * (size_t)total);
        for (int i = 0; i < total; ++i) idx[i] = rand_int(nv);
        wc_source_mesh src;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, nv, sizes, np, idx, 1.0, &d), WC_OK);
        wc_model_def def = wc_default_model_def();
        def.weld_tolerance = rand_int(3) == 0 ? 0.0 : 1e-6;
        wc_model m;
        wc_status st = wc_model_build(&m, &src, &def, NULL, &d);
        if (st == WC_OK) {
            ++built;
            if (!model_invariants_hold(&m, nv)) {
                ++broken;
                fprintf(stderr, "invariants broken at iteration %d\n", iter);
            }
            wc_model_free(&m);
        } else {
            ++refused;
            CHECK(st == WC_ERROR_EMPTY_MESH);
            CHECK(m.n_particles == 0 && m.springs == NULL);
        }
        wc_source_mesh_free(&src);
        free(pos);
        free(sizes);
        free(idx);
    }
    printf("  %d built, %d refused as empty, %d with broken invariants\n", built, refused, broken);
    CHECK_EQ_INT(broken, 0);
    CHECK(built > 100);
}

int main(void) {
    RUN_TEST(test_random_soups);
    return TEST_SUMMARY();
}
