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

/* One body twice (the GPU's resident copy mg, core's mc) and a 24 x 24 sheet over it: the sheet's
 * positions x and velocities v (zero until the test sets them, before rig_device), their float
 * copies on the GPU, and each side's pair list and finder. */
typedef struct rig {
    const tmesh* bx;
    const double* to;   /* the body's frame end (NULL: at rest) */
    wc_mesh_collider *mg, *mc;
    const wc_mesh_collider* cg[1];
    const wc_mesh_collider* cc[1];
    wc_model m;
    int n;
    double *x, *v;
    wg_layout L;
    wg_runner run;
    wg_mesh g;
    wc_mesh_pairs *pg, *pc;
    wg_mesh_sharp* ms;
    wg_tex xt, vt;
} rig;

/* the body bx (moving to `to` over the frame; NULL: at rest) on both sides and the sheet */
static void rig_open(rig* r, const tmesh* bx, const double* to) {
    memset(r, 0, sizeof *r);
    r->bx = bx;
    r->to = to;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_mesh_collider_create(&r->mg, bx->x, bx->nv, bx->t, bx->nt, THICK, 0.3, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_create(&r->mc, bx->x, bx->nv, bx->t, bx->nt, THICK, 0.3, NULL, &d), WC_OK);
    if (to) CHECK_EQ_INT(wc_mesh_collider_set_target(r->mc, to, &d), WC_OK);
    CHECK(ts_sheet(&r->m, N, 1.0, 0.0, 0, 1.0));
    r->n = r->m.n_particles;
    r->x = calloc(3 * (size_t)r->n, sizeof(double));
    r->v = calloc(3 * (size_t)r->n, sizeof(double));
}

/* the GPU's side once x and v are set: mg resident (from bx to `to`, or at rest), both pair lists,
 * the finder, x and v as floats */
static void rig_device(rig* r) {
    const int n = r->n;
    float* x4 = calloc(4 * (size_t)n, sizeof(float));
    float* v4 = calloc(4 * (size_t)n, sizeof(float));
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) {
            x4[4 * i + c] = (float)r->x[3 * i + c];
            v4[4 * i + c] = (float)r->v[3 * i + c];
        }
    char err[512];
    CHECK(tg_runner_open(g_dev, &r->L, &r->run, err, sizeof err));
    CHECK(wg_mesh_init(&r->g, &r->run, &r->mg, 1, err, sizeof err));
    wg_mesh_body_set(&r->g, 0, r->bx->x, r->to ? r->to : r->bx->x);
    r->mg->on_device = 1;
    r->cg[0] = r->mg;
    r->cc[0] = r->mc;
    const int cap = 2 * (r->m.we.n_edges + r->m.n_tris) + 64;
    r->pg = wc_mesh_pairs_create(cap, n, r->cg, 1, NULL);
    r->pc = wc_mesh_pairs_create(cap, n, r->cc, 1, NULL);
    CHECK(r->pg && r->pc);
    CHECK(wg_mesh_sharp_create(&r->run, &r->g, r->pg, &r->m, &r->ms, err, sizeof err));
    if (!r->ms) printf("  wg_mesh_sharp_create: %s\n", err);
    CHECK(wg_array_create(&r->L, &r->xt, GL_RGBA32F, n, x4, err, sizeof err));
    CHECK(wg_array_create(&r->L, &r->vt, GL_RGBA32F, n, v4, err, sizeof err));
    free(x4), free(v4);
}

static void rig_close(rig* r) {
    wg_tex_destroy(&r->xt);
    wg_tex_destroy(&r->vt);
    wg_mesh_sharp_destroy(r->ms, 1);
    wg_mesh_release(&r->g, 1);
    tg_runner_close(&r->run, &r->L);
    wc_mesh_pairs_destroy(r->pg, NULL);
    wc_mesh_pairs_destroy(r->pc, NULL);
    wc_mesh_collider_destroy(r->mg);
    wc_mesh_collider_destroy(r->mc);
    wc_model_free(&r->m);
    free(r->x), free(r->v);
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
    rig r;
    rig_open(&r, &bx, to);
    const int n = r.n;
    double *x = r.x, *v = r.v;
    for (int i = 0; i < n; ++i) {
        double px = r.m.rest_pos[3 * i] + 0.004 * jitter(), pz = r.m.rest_pos[3 * i + 2] + 0.004 * jitter();
        double out = fmax(fabs(px), fabs(pz)) - 0.3;
        /* past the rim x = -0.3 the sheet rises (its pairs' normals past the top's, turned to it),
           and a patch lies 1 mm under the top inside that rim (behind the body: no pair of it) */
        double y = 0.003 - (px < -0.3 && fabs(pz) < 0.3 ? -0.12 : 0.15) * fmax(out, 0.0) + 0.0005 * jitter();
        if (px > -0.3 && px < -0.26 && fabs(pz) < 0.15) y = -0.001;
        x[3 * i] = fr(px);
        x[3 * i + 1] = fr(y);
        x[3 * i + 2] = fr(pz);
        for (int c = 0; c < 3; ++c) v[3 * i + c] = fr(0.05 * jitter() - (c == 1 ? 0.2 : 0.0));
    }
    rig_device(&r);

    for (int s = 0; r.ms && s < 2; ++s) {
        const double a0 = 0.5 * s, a1 = 0.5 * (s + 1);
        wg_mesh_substep(&r.g, a0, a1, H);
        wc_mesh_collider_substep(r.mc, a0, a1, H);
        int found_core = wc_mesh_pairs_find(r.pc, r.cc, 1, &r.m, NULL, NULL, x, v, H, H);
        /* core skips a body on the device */
        CHECK_EQ_INT(wc_mesh_pairs_find(r.pg, r.cg, 1, &r.m, NULL, NULL, x, v, H, H), 0);
        size_t bytes = 0;
        int found = wg_mesh_sharp_find(r.ms, r.pg, &r.m, NULL, NULL, &r.xt, &r.vt, H, H, &bytes);
        cmp c = {0};
        compare(&r.pc->list, &r.pg->list, x, &c);
        printf("  substep [%g, %g]: core %d pairs, GPU %d (kept %d); matched %d (%d with 2 particles, %d with 3), "
               "unmatched core %d GPU %d; weights %.2g, normals %.2g (that pair's gap %.2g m), gaps at the start "
               "%.2g m, k %.2g (relative); %zu bytes read back\n",
               a0, a1, found_core, found, r.pg->list.n, c.matched, c.edge, c.tri, c.unmatched_core, c.unmatched_gpu,
               c.w, c.n, c.n_gap, c.gap, c.k, bytes);
        CHECK(found_core > 20);
        CHECK_EQ_INT(found, r.pg->list.n);
        CHECK_EQ_INT(c.unmatched_core, 0);
        CHECK_EQ_INT(c.unmatched_gpu, 0);
        CHECK(c.edge > 0 && c.tri > 0);
        CHECK(c.w <= W_BOUND);
        CHECK(c.n <= N_BOUND);
        CHECK(c.gap <= GAP_BOUND);
        CHECK(c.k <= K_BOUND);
        CHECK(bytes == 4 + 48 * (size_t)found);
        CHECK_EQ_INT(r.pg->list.overflow, 0);
    }
    CHECK(glGetError() == GL_NO_ERROR);
    CHECK(r.run.fault[0] == '\0');
    rig_close(&r);
    free(to);
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
    rig r;
    rig_open(&r, &bx, NULL);
    for (int i = 0; i < r.n; ++i) {
        r.x[3 * i] = fr(r.m.rest_pos[3 * i]);
        r.x[3 * i + 1] = 0.0;
        r.x[3 * i + 2] = fr(r.m.rest_pos[3 * i + 2]);
    }
    rig_device(&r);
    if (r.ms) {
        wg_mesh_substep(&r.g, 0.0, 1.0, H);
        wc_mesh_collider_substep(r.mc, 0.0, 1.0, H);
        int found_core = wc_mesh_pairs_find(r.pc, r.cc, 1, &r.m, NULL, NULL, r.x, r.v, H, H);
        int found = wg_mesh_sharp_find(r.ms, r.pg, &r.m, NULL, NULL, &r.xt, &r.vt, H, H, NULL);
        cmp c = {0};
        compare(&r.pc->list, &r.pg->list, r.x, &c);
        printf("  level sheet over the rim: core %d pairs, GPU %d; matched %d, unmatched core %d GPU %d; normals %.2g, "
               "gaps %.2g m\n", found_core, found, c.matched, c.unmatched_core, c.unmatched_gpu, c.n, c.gap);
        CHECK(found_core > 0);
        CHECK_EQ_INT(c.unmatched_core, 0);
        CHECK_EQ_INT(c.unmatched_gpu, 0);
        CHECK(c.n <= N_BOUND);
        CHECK(c.gap <= GAP_BOUND);
    }
    rig_close(&r);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_pairs_against_core);
    RUN_TEST(test_tie_level_rim);
    tg_gpu_close(g_ctx, g_dev);
    return TEST_SUMMARY();
}
