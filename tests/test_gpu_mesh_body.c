/* The mesh colliders' bodies moved on the GPU (gpu/solver/wg_mesh_body.c: mesh_verts,
 * mesh_tris, mesh_refit_groups, mesh_measure) against core's wc_mesh_collider_substep on the
 * same frame positions (floats): two meshes share the textures, a box moved on the host (its
 * texels exactly core's, rounded to float) and an icosphere resident on the GPU that breathes,
 * shifts 6 cm and turns over the frame. Each substep (the first half, the second half, a
 * zero-length one) the resident body's vertex texels (start, end, velocity), triangle texels
 * (indices exact, unit normals at both ends), BVH nodes (children exact; every box holds core's
 * box and lies within float rounding of it) and its fastest vertex agree with core's. At the
 * frame's end the body comes back to core (wg_mesh_body_pull): from and to are the frame's end,
 * bit for bit. Compute passes only (the fragment passes move every body on the host). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "mesh_collider.h"
#include "test_meshes.h"
#include "wg_device.h"
#include "wg_mesh.h"

static wg_gl_context* g_ctx;
static wg_device* g_dev;
static tmesh g_box, g_ball;

#define THICK 0.004

/* a rounding to float; through a volatile: GCC 12 at -O3 drops the rounding of some of a
   vectorised loop's (double)(float) conversions */
static double fr(double a) {
    volatile float f = (float)a;
    return (double)f;
}

/* The ball's frame end: breathing +4 %, shifted (6, 3, -2) cm, turned 0.1 rad about y. */
static void ball_target(const double* x0, int n, double* out) {
    const double c = cos(0.1), s = sin(0.1);
    for (int i = 0; i < n; ++i) {
        const double* p = x0 + 3 * i;
        double q[3] = {1.04 * (c * p[0] + s * p[2]), 1.04 * p[1], 1.04 * (-s * p[0] + c * p[2])};
        out[3 * i] = fr(q[0] + 0.06);
        out[3 * i + 1] = fr(q[1] + 0.03);
        out[3 * i + 2] = fr(q[2] - 0.02);
    }
}

static double d3(const float* a, const double* b) {
    double e = 0.0;
    for (int c = 0; c < 3; ++c) e = fmax(e, fabs((double)a[c] - b[c]));
    return e;
}

typedef struct errs {
    double pos, vel, nrm, box;
    int host_exact, idx_exact, child_exact, contain;
} errs;

/* The GPU's textures against core's ref (mesh 1) and against host mesh 0 as core holds it. */
static void compare(const wg_mesh* g, const wc_mesh_collider* host, const wc_mesh_collider* ref, errs* e) {
    const wg_layout* L = g->run->layout;
    float* vt = malloc((size_t)g->n_vert * 3 * 16);
    float* tt = malloc((size_t)g->n_tri * 3 * 16);
    float* nt = malloc((size_t)g->n_node * 2 * 16);
    wg_array_read(L, &g->vert, 3 * g->n_vert, vt);
    wg_array_read(L, &g->tri, 3 * g->n_tri, tt);
    wg_array_read(L, &g->node, 2 * g->n_node, nt);
    for (int i = 0; i < host->n_verts; ++i)
        for (int c = 0; c < 3; ++c)
            e->host_exact &= vt[12 * i + c] == (float)host->xa[3 * i + c] &&
                             vt[12 * i + 4 + c] == (float)host->xb[3 * i + c] &&
                             vt[12 * i + 8 + c] == (float)host->vel[3 * i + c];
    const float* v1 = vt + 12 * (size_t)g->vert0[1];
    for (int i = 0; i < ref->n_verts; ++i) {
        e->pos = fmax(e->pos, fmax(d3(v1 + 12 * i, ref->xa + 3 * i), d3(v1 + 12 * i + 4, ref->xb + 3 * i)));
        e->vel = fmax(e->vel, d3(v1 + 12 * i + 8, ref->vel + 3 * i));
    }
    const float* t1 = tt + 12 * (size_t)g->tri0[1];
    for (int t = 0; t < ref->n_tris; ++t) {
        for (int c = 0; c < 3; ++c) e->idx_exact &= t1[12 * t + c] == (float)(g->vert0[1] + ref->tris[3 * t + c]);
        e->nrm = fmax(e->nrm, fmax(d3(t1 + 12 * t + 4, ref->nrm_a + 3 * t), d3(t1 + 12 * t + 8, ref->nrm_b + 3 * t)));
    }
    const float* n1 = nt + 8 * (size_t)g->node0[1];
    const wc_bvh* b = &ref->bvh;
    for (int j = 0; j < b->n_nodes; ++j) {
        const float* q = n1 + 8 * j;
        const double* bx = b->box + 6 * j;
        const int* ch = b->child + 2 * j;
        int leaf = ch[0] < 0;
        e->child_exact &= q[3] == (leaf ? -1.0f : (float)(g->node0[1] + ch[0])) &&
                          q[7] == (float)(leaf ? g->tri0[1] + ch[1] : g->node0[1] + ch[1]);
        for (int c = 0; c < 3; ++c) {
            e->contain &= (double)q[c] <= bx[c] && (double)q[4 + c] >= bx[3 + c];
            e->box = fmax(e->box, fmax(bx[c] - (double)q[c], (double)q[4 + c] - bx[3 + c]));
        }
    }
    free(vt), free(tt), free(nt);
}

static void test_body_against_core(void) {
    if (!g_dev->compute) {
        printf("  fragment passes: every body is moved on the host (nothing to compare)\n");
        return;
    }
    const double lo[3] = {-0.5, -0.6, -0.4}, hi[3] = {0.5, -0.45, 0.4}, c0[3] = {0.1, 0.2, 0.0};
    box(&g_box, lo, hi);
    icosphere(&g_ball, 3, 0.35, c0);
    for (int i = 0; i < 3 * g_box.nv; ++i) g_box.x[i] = fr(g_box.x[i]);
    for (int i = 0; i < 3 * g_ball.nv; ++i) g_ball.x[i] = fr(g_ball.x[i]);
    wc_diag d = {0};
    wc_mesh_collider *mc[2] = {NULL, NULL}, *ref = NULL;
    CHECK_EQ_INT(wc_mesh_collider_create(&mc[0], g_box.x, g_box.nv, g_box.t, g_box.nt, THICK, 0.3, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_create(&mc[1], g_ball.x, g_ball.nv, g_ball.t, g_ball.nt, THICK, 0.3, NULL, &d),
                 WC_OK);
    CHECK_EQ_INT(wc_mesh_collider_create(&ref, g_ball.x, g_ball.nv, g_ball.t, g_ball.nt, THICK, 0.3, NULL, &d), WC_OK);
    double* to = malloc(3 * (size_t)g_ball.nv * sizeof(double));
    ball_target(g_ball.x, g_ball.nv, to);
    CHECK_EQ_INT(wc_mesh_collider_set_target(ref, to, &d), WC_OK);
    double* box_to = malloc(3 * (size_t)g_box.nv * sizeof(double));
    for (int i = 0; i < 3 * g_box.nv; ++i) box_to[i] = fr(g_box.x[i] + (i % 3 == 1 ? 0.02 : 0.0));
    CHECK_EQ_INT(wc_mesh_collider_set_target(mc[0], box_to, &d), WC_OK);

    char err[512];
    wg_layout L;
    wg_runner run;
    CHECK(tg_runner_open(g_dev, &L, &run, err, sizeof err));
    wg_mesh g;
    int made = wg_mesh_init(&g, &run, mc, 2, err, sizeof err);
    CHECK(made);
    if (!made) printf("  wg_mesh_init: %s\n", err);
    CHECK(g.body);
    wg_mesh_body_set(&g, 1, g_ball.x, to);   /* the ball resident: from its creation shape to `to` */
    mc[1]->on_device = 1;
    CHECK_EQ_INT(g.n_resident, 1);
    CHECK_EQ_INT(g.order_first[g.n_heights], mc[1]->bvh.n_nodes);   /* every node of the ball refitted */

    const double h = 1.0 / 120.0;
    const double steps[3][3] = {{0.0, 0.5, h}, {0.5, 1.0, h}, {1.0, 1.0, 0.0}};
    double scale = 0.0, vmax = 0.0;
    for (int i = 0; i < 3 * g_ball.nv; ++i) scale = fmax(scale, fmax(fabs(g_ball.x[i]), fabs(to[i])));
    for (int s = 0; s < 3; ++s) {
        const double a0 = steps[s][0], a1 = steps[s][1], hs = steps[s][2];
        wg_mesh_substep(&g, a0, a1, hs);
        wc_mesh_collider_substep(ref, a0, a1, hs);
        errs e = {0, 0, 0, 0, 1, 1, 1, 1};
        compare(&g, mc[0], ref, &e);
        for (int i = 0; i < 3 * ref->n_verts; i += 3) vmax = fmax(vmax, sqrt(v3_dot(ref->vel + i, ref->vel + i)));
        double speed_err = fabs(mc[1]->max_speed - ref->max_speed);
        printf("  substep [%g, %g] h %.4g: position err %.2g m, velocity %.2g m/s (fastest %.3g), normal %.2g, box "
               "%.2g m beyond core's (holds it: %s), fastest vertex err %.2g m/s\n",
               a0, a1, hs, e.pos, e.vel, ref->max_speed, e.nrm, e.box, e.contain ? "yes" : "no", speed_err);
        /* float's reach: the interpolation rounds to a few ulps of the body's extent (~0.5 m,
           ulp 6e-8), the velocity divides two such by h; a normal of a ~4 cm triangle from float
           corners differs by ~ulp(0.5) / 4 cm; the boxes are widened by 8 ulps of their extent */
        CHECK(e.host_exact);
        CHECK(e.idx_exact);
        CHECK(e.child_exact);
        CHECK(e.contain);
        CHECK(e.pos <= 4.0 * 6e-8 * (scale / 0.5));
        CHECK(e.vel <= (hs > 0.0 ? 8.0 * 6e-8 / hs : 0.0) + 1e-6 * ref->max_speed);
        CHECK(e.nrm <= 2e-5);
        CHECK(e.box <= 2e-6);
        CHECK(speed_err <= (hs > 0.0 ? 8.0 * 6e-8 / hs : 0.0) + 1e-6 * ref->max_speed);
        CHECK(mc[1]->h == hs);
    }
    CHECK(vmax > 1.0);   /* the body moves: the velocities compared are not all zero */

    /* the frame's end, and the body back to core: from = to = the frame's end, bit for bit */
    wg_mesh_body_end_frame(&g);
    wc_mesh_collider_end_frame(ref);
    wg_mesh_body_pull(&g);
    CHECK_EQ_INT(g.n_resident, 0);
    CHECK_EQ_INT(mc[1]->on_device, 0);
    CHECK(memcmp(mc[1]->from, to, 3 * (size_t)g_ball.nv * sizeof(double)) == 0);
    CHECK(memcmp(mc[1]->to, to, 3 * (size_t)g_ball.nv * sizeof(double)) == 0);
    CHECK(memcmp(mc[1]->xb, to, 3 * (size_t)g_ball.nv * sizeof(double)) == 0);
    CHECK(glGetError() == GL_NO_ERROR);
    CHECK(run.fault[0] == '\0');

    wg_mesh_release(&g, 1);
    tg_runner_close(&run, &L);
    for (int k = 0; k < 2; ++k) wc_mesh_collider_destroy(mc[k]);
    wc_mesh_collider_destroy(ref);
    free(to), free(box_to);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_body_against_core);
    tg_gpu_close(g_ctx, g_dev);
    return TEST_SUMMARY();
}
