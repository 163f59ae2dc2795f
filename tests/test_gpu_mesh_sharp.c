/* The sharp-feature pairs of a body resident on the GPU (gpu/solver/wg_mesh_sharp.c:
 * mesh_sharp.glsl, mesh_sharp_mask_groups.glsl, mesh_pairs_find_groups.glsl) against core's wc_mesh_pairs_find on the same
 * body and cloth (floats). A box (its 12 rim edges and 8 corners sharp, its face diagonals not)
 * with a smooth ball under it in the same mesh (no sharp feature: the pairs' walk prunes it, as
 * core's mask does) moves over the frame (shifted, grown); one copy is resident on the GPU (wg_mesh_body_set,
 * moved to the substep by the body's passes), the other core's (wc_mesh_collider_substep). A
 * 24 x 24 sheet lies 3 mm over the box's top and slopes down past its rim (1 in 7; up past one
 * rim, with a patch of particles inside the box there), jittered, moving down: its edges cross
 * the rims and its triangles lie over the corners. Two substeps
 * (the frame's first and second half). The GPU's pairs equal core's as sets (each pair's
 * particles; the weights, normal, off and k within float's reach: bounds below), the edge-edge
 * (or vertex-edge) and vertex-triangle pairs both present; the bytes read back are the counter
 * and 48 a pair. Compute passes only (fragment passes keep every body on the host). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "mesh_collider.h"
#include "mesh_pairs.h"
#include "test_meshes.h"
#include "test_support.h"
#include "wg_device.h"
#include "wg_mesh.h"
#include "wg_mesh_sharp.h"

static wg_gl_context* g_ctx;
static wg_device* g_dev;

#define N 24
#define THICK 0.004
#define H (1.0 / 120.0)
/* float's reach (measured on llvmpipe: weights 2.5e-6, normals 9.6e-4, gaps 3.0e-6 m, k 1.7e-6).
   A normal is the direction from the body point to the cloth point, which can be a few
   hundredths of a millimetre apart (a cloth edge over the rim): float's 6e-8 m in 6e-5 m turns it
   by 1e-3. The gap at the start, n . sum w x - off, moves by that turn times the few millimetres
   between the cloth point and the body point at the end. k goes with the weights squared. */
#define W_BOUND 2e-5
#define N_BOUND 3e-3
#define GAP_BOUND 1e-5
#define K_BOUND 1e-4

static double fr(double a) {
    volatile float f = (float)a;
    return (double)f;
}

static unsigned g_seed = 12345u;
static double jitter(void) {   /* in [-1, 1) */
    g_seed = g_seed * 1103515245u + 12345u;
    return ((g_seed >> 8) & 0xffff) / 32768.0 - 1.0;
}

typedef struct cmp {
    int matched, unmatched_core, unmatched_gpu, edge, tri;
    double w, n, gap, k;
    double n_gap;   /* core's gap at the start of the pair whose normals differ most */
} cmp;

/* pair j's gap at the cloth's positions x: n . sum w_a x_a - off */
static double gap(const wc_penalty_pairs* l, int j, const double* x) {
    const wc_coupling_term* t = &l->term[j];
    double g = -l->off[j];
    for (int a = 0; a < t->cnt; ++a)
        for (int c = 0; c < 3; ++c) g += t->w[a] * t->n[c] * x[3 * t->p[a] + c];
    return g;
}

/* core's list a against the GPU's b: each of a's pairs matched to one of b's with the same
   particles and the nearest normal */
static void compare(const wc_penalty_pairs* a, const wc_penalty_pairs* b, const double* x, cmp* c) {
    unsigned char* used = calloc((size_t)b->n + 1, 1);
    for (int i = 0; i < a->n; ++i) {
        const wc_coupling_term* ta = &a->term[i];
        int best = -1;
        double bd = HUGE_VAL;
        for (int j = 0; j < b->n; ++j) {
            const wc_coupling_term* tb = &b->term[j];
            if (used[j] || tb->cnt != ta->cnt) continue;
            int same = 1;
            for (int q = 0; q < ta->cnt; ++q) same &= ta->p[q] == tb->p[q];
            if (!same) continue;
            double d = 0.0;
            for (int q = 0; q < 3; ++q) d = fmax(d, fabs(ta->n[q] - tb->n[q]));
            if (d < bd) bd = d, best = j;
        }
        if (best < 0) {
            ++c->unmatched_core;
            continue;
        }
        used[best] = 1;
        ++c->matched;
        if (ta->cnt == 2) ++c->edge;
        else ++c->tri;
        const wc_coupling_term* tb = &b->term[best];
        for (int q = 0; q < ta->cnt; ++q) c->w = fmax(c->w, fabs(ta->w[q] - tb->w[q]));
        if (bd > c->n) c->n_gap = gap(a, i, x);
        c->n = fmax(c->n, bd);
        c->gap = fmax(c->gap, fabs(gap(a, i, x) - gap(b, best, x)));
        c->k = fmax(c->k, fabs(a->k[i] - b->k[best]) / a->k[i]);
    }
    for (int j = 0; j < b->n; ++j) c->unmatched_gpu += !used[j];
    free(used);
}

static void test_pairs_against_core(void) {
    if (!g_dev->compute) {
        printf("  fragment passes: every body is moved on the host (nothing to compare)\n");
        return;
    }
    static tmesh bx, ball;
    const double lo[3] = {-0.3, -0.3, -0.3}, hi[3] = {0.3, 0.0, 0.3}, below[3] = {0.0, -0.6, 0.0};
    box(&bx, lo, hi);
    icosphere(&ball, 2, 0.15, below);   /* the same mesh: its smooth part, which the walk's mask prunes */
    const int v0 = bx.nv;
    for (int i = 0; i < ball.nv; ++i) tm_vert(&bx, ball.x[3 * i], ball.x[3 * i + 1], ball.x[3 * i + 2]);
    for (int t = 0; t < ball.nt; ++t) tm_tri(&bx, v0 + ball.t[3 * t], v0 + ball.t[3 * t + 1], v0 + ball.t[3 * t + 2]);
    for (int i = 0; i < 3 * bx.nv; ++i) bx.x[i] = fr(bx.x[i]);
    double* to = malloc(3 * (size_t)bx.nv * sizeof(double));
    for (int i = 0; i < 3 * bx.nv; ++i) to[i] = fr(1.01 * bx.x[i] + (i % 3 == 0 ? 0.004 : i % 3 == 1 ? 0.002 : 0.0));
    wc_diag d = {0};
    wc_mesh_collider *mg = NULL, *mc = NULL;
    CHECK_EQ_INT(wc_mesh_collider_create(&mg, bx.x, bx.nv, bx.t, bx.nt, THICK, 0.3, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, bx.x, bx.nv, bx.t, bx.nt, THICK, 0.3, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_set_target(mc, to, &d), WC_OK);

    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 0, 1.0));
    const int n = m.n_particles;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    double* v = malloc(3 * (size_t)n * sizeof(double));
    float* x4 = calloc(4 * (size_t)n, sizeof(float));
    float* v4 = calloc(4 * (size_t)n, sizeof(float));
    for (int i = 0; i < n; ++i) {
        double px = m.rest_pos[3 * i] + 0.004 * jitter(), pz = m.rest_pos[3 * i + 2] + 0.004 * jitter();
        double out = fmax(fabs(px), fabs(pz)) - 0.3;
        /* past the rim x = -0.3 the sheet rises (its pairs' normals past the top's, turned to it),
           and a patch lies 1 mm under the top inside that rim (behind the body: no pair of it) */
        double y = 0.003 - (px < -0.3 && fabs(pz) < 0.3 ? -0.12 : 0.15) * fmax(out, 0.0) + 0.0005 * jitter();
        if (px > -0.3 && px < -0.26 && fabs(pz) < 0.15) y = -0.001;
        x[3 * i] = fr(px);
        x[3 * i + 1] = fr(y);
        x[3 * i + 2] = fr(pz);
        for (int c = 0; c < 3; ++c) v[3 * i + c] = fr(0.05 * jitter() - (c == 1 ? 0.2 : 0.0));
        for (int c = 0; c < 3; ++c) {
            x4[4 * i + c] = (float)x[3 * i + c];
            v4[4 * i + c] = (float)v[3 * i + c];
        }
    }

    char err[512];
    wg_layout L;
    CHECK(wg_layout_init(&L, 10, g_dev->max_texture_size, (wc_allocator){0}, err, sizeof err));
    wg_runner run;
    wg_runner_init(&run, g_dev, &L);
    wg_mesh g;
    CHECK(wg_mesh_init(&g, &run, &mg, 1, err, sizeof err));
    wg_mesh_body_set(&g, 0, bx.x, to);
    mg->on_device = 1;
    const wc_mesh_collider* const cg[1] = {mg};
    const wc_mesh_collider* const cc[1] = {mc};
    const int cap = 2 * (m.we.n_edges + m.n_tris) + 64;
    wc_mesh_pairs* pg = wc_mesh_pairs_create(cap, n, cg, 1, NULL);
    wc_mesh_pairs* pc = wc_mesh_pairs_create(cap, n, cc, 1, NULL);
    CHECK(pg && pc);
    wg_mesh_sharp* ms = NULL;
    CHECK(wg_mesh_sharp_create(&run, &g, pg, &m, &ms, err, sizeof err));
    if (!ms) printf("  wg_mesh_sharp_create: %s\n", err);
    wg_tex xt = {0}, vt = {0};
    CHECK(wg_array_create(&L, &xt, GL_RGBA32F, n, x4, err, sizeof err));
    CHECK(wg_array_create(&L, &vt, GL_RGBA32F, n, v4, err, sizeof err));

    for (int s = 0; ms && s < 2; ++s) {
        const double a0 = 0.5 * s, a1 = 0.5 * (s + 1);
        wg_mesh_substep(&g, a0, a1, H);
        wc_mesh_collider_substep(mc, a0, a1, H);
        int found_core = wc_mesh_pairs_find(pc, cc, 1, &m, NULL, NULL, x, v, H, H);
        /* core skips a body on the device */
        CHECK_EQ_INT(wc_mesh_pairs_find(pg, cg, 1, &m, NULL, NULL, x, v, H, H), 0);
        size_t bytes = 0;
        int found = wg_mesh_sharp_find(ms, pg, &m, NULL, NULL, &xt, &vt, H, H, &bytes);
        cmp c = {0};
        compare(&pc->list, &pg->list, x, &c);
        printf("  substep [%g, %g]: core %d pairs, GPU %d (kept %d); matched %d (%d with 2 particles, %d with 3), "
               "unmatched core %d GPU %d; weights %.2g, normals %.2g (that pair's gap %.2g m), gaps at the start "
               "%.2g m, k %.2g (relative); %zu bytes read back\n",
               a0, a1, found_core, found, pg->list.n, c.matched, c.edge, c.tri, c.unmatched_core, c.unmatched_gpu, c.w,
               c.n, c.n_gap, c.gap, c.k, bytes);
        CHECK(found_core > 20);
        CHECK_EQ_INT(found, pg->list.n);
        CHECK_EQ_INT(c.unmatched_core, 0);
        CHECK_EQ_INT(c.unmatched_gpu, 0);
        CHECK(c.edge > 0 && c.tri > 0);
        CHECK(c.w <= W_BOUND);
        CHECK(c.n <= N_BOUND);
        CHECK(c.gap <= GAP_BOUND);
        CHECK(c.k <= K_BOUND);
        CHECK(bytes == 4 + 48 * (size_t)found);
        CHECK_EQ_INT(pg->list.overflow, 0);
    }
    CHECK(glGetError() == GL_NO_ERROR);
    CHECK(run.fault[0] == '\0');
    wg_tex_destroy(&xt);
    wg_tex_destroy(&vt);
    wg_mesh_sharp_destroy(ms, 1);
    wg_mesh_release(&g, 1);
    wg_runner_destroy(&run);
    wg_layout_destroy(&L);
    wc_mesh_pairs_destroy(pg, NULL);
    wc_mesh_pairs_destroy(pc, NULL);
    wc_mesh_collider_destroy(mg);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
    free(x), free(v), free(x4), free(v4), free(to);
}

/* The tie: an axis-aligned sheet exactly level with a box's top (y = 0, floats), its edges along
 * X and Z through the top's rim edges (the rim lines x, z = +-0.3 cut them between particles), at
 * rest. Each cloth edge across a rim meets the rim line: its closest points coincide (the gap is
 * zero up to rounding), the pair's normal is the visited face's (core: at most 1e-9 thickness
 * apart). The GPU's pairs must be core's: each matched by its particles with a normal within
 * N_BOUND, none left over. */
static void test_tie_level_rim(void) {
    if (!g_dev->compute) return;
    static tmesh bx;
    const double lo[3] = {-0.3, -0.3, -0.3}, hi[3] = {0.3, 0.0, 0.3};
    box(&bx, lo, hi);
    wc_diag d = {0};
    wc_mesh_collider *mg = NULL, *mc = NULL;
    CHECK_EQ_INT(wc_mesh_collider_create(&mg, bx.x, bx.nv, bx.t, bx.nt, THICK, 0.3, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, bx.x, bx.nv, bx.t, bx.nt, THICK, 0.3, NULL, &d), WC_OK);
    wc_model m;
    CHECK(ts_sheet(&m, N, 1.0, 0.0, 0, 1.0));
    const int n = m.n_particles;
    double* x = malloc(3 * (size_t)n * sizeof(double));
    double* v = calloc(3 * (size_t)n, sizeof(double));
    float* x4 = calloc(4 * (size_t)n, sizeof(float));
    float* v4 = calloc(4 * (size_t)n, sizeof(float));
    for (int i = 0; i < n; ++i) {
        x[3 * i] = fr(m.rest_pos[3 * i]);
        x[3 * i + 1] = 0.0;
        x[3 * i + 2] = fr(m.rest_pos[3 * i + 2]);
        for (int c = 0; c < 3; ++c) x4[4 * i + c] = (float)x[3 * i + c];
    }
    char err[512];
    wg_layout L;
    CHECK(wg_layout_init(&L, 10, g_dev->max_texture_size, (wc_allocator){0}, err, sizeof err));
    wg_runner run;
    wg_runner_init(&run, g_dev, &L);
    wg_mesh g;
    CHECK(wg_mesh_init(&g, &run, &mg, 1, err, sizeof err));
    wg_mesh_body_set(&g, 0, bx.x, bx.x);
    mg->on_device = 1;
    const wc_mesh_collider* const cg[1] = {mg};
    const wc_mesh_collider* const cc[1] = {mc};
    const int cap = 2 * (m.we.n_edges + m.n_tris) + 64;
    wc_mesh_pairs* pg = wc_mesh_pairs_create(cap, n, cg, 1, NULL);
    wc_mesh_pairs* pc = wc_mesh_pairs_create(cap, n, cc, 1, NULL);
    CHECK(pg && pc);
    wg_mesh_sharp* ms = NULL;
    CHECK(wg_mesh_sharp_create(&run, &g, pg, &m, &ms, err, sizeof err));
    wg_tex xt = {0}, vt = {0};
    CHECK(wg_array_create(&L, &xt, GL_RGBA32F, n, x4, err, sizeof err));
    CHECK(wg_array_create(&L, &vt, GL_RGBA32F, n, v4, err, sizeof err));
    if (ms) {
        wg_mesh_substep(&g, 0.0, 1.0, H);
        wc_mesh_collider_substep(mc, 0.0, 1.0, H);
        int found_core = wc_mesh_pairs_find(pc, cc, 1, &m, NULL, NULL, x, v, H, H);
        int found = wg_mesh_sharp_find(ms, pg, &m, NULL, NULL, &xt, &vt, H, H, NULL);
        cmp c = {0};
        compare(&pc->list, &pg->list, x, &c);
        printf("  level sheet over the rim: core %d pairs, GPU %d; matched %d, unmatched core %d GPU %d; normals %.2g, "
               "gaps %.2g m\n", found_core, found, c.matched, c.unmatched_core, c.unmatched_gpu, c.n, c.gap);
        CHECK(found_core > 0);
        CHECK_EQ_INT(c.unmatched_core, 0);
        CHECK_EQ_INT(c.unmatched_gpu, 0);
        CHECK(c.n <= N_BOUND);
        CHECK(c.gap <= GAP_BOUND);
    }
    wg_tex_destroy(&xt);
    wg_tex_destroy(&vt);
    wg_mesh_sharp_destroy(ms, 1);
    wg_mesh_release(&g, 1);
    wg_runner_destroy(&run);
    wg_layout_destroy(&L);
    wc_mesh_pairs_destroy(pg, NULL);
    wc_mesh_pairs_destroy(pc, NULL);
    wc_mesh_collider_destroy(mg);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
    free(x), free(v), free(x4), free(v4);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_pairs_against_core);
    RUN_TEST(test_tie_level_rim);
    tg_gpu_close(g_ctx, g_dev);
    return TEST_SUMMARY();
}
