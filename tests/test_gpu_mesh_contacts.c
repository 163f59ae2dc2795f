/* The GPU contact passes against a triangle-mesh collider (gpu/solver/wg_mesh.c,
 * contact_query.glsl, contact_ccd.glsl) step by step against core/collide.c on the same
 * (float-rounded) input: particles scattered around an icosphere's shell (some inside it, some
 * held or released from the last substep, a pinned one, fast ones whose paths cross the body),
 * the body still or moving over the substep (its frame target shifted), with push_speed 0 (out at
 * once) and 0.05 m/s (the correction capped, begin's share carried to project). begin: the
 * positions it corrects, the contacts (collider ids, normals: the closest point's side rules, or
 * the plane of the triangle a path crosses), the filter; project: positions and velocities
 * (a crossed path put back in front first), against core's wc_contacts_project_from. Also a box
 * mesh (sharp edges and corners: the edge and vertex side rules), and a mesh with an analytic
 * plane after it (the collider ids). A particle within 1 mm of the surface after begin is left
 * out of begin's comparison (its normal at an edge, along p - q, is not decided in float). The
 * cloth's GPU memory counts the contacts' and the meshes' textures. */
#include "check.h"
#include "collide.h"
#include "gpu_test_device.h"
#include "gpu_contacts_support.h"
#include "test_meshes.h"
#include "test_support.h"
#include "wg_device.h"

static wg_gl_context* g_ctx;
static wg_device* g_dev;
static tmesh g_body;

#define THICK 0.01

/* Particles around the body's shell, offset by [-0.03, 0.03] along the outward direction,
 * velocities from creeping to fast, some coming in (the body already moved to the substep).
 * Returns how many paths over the substep cross the body. */
static int scatter(wc_state* s, const wc_mesh_collider* mc, double h) {
    int crossing = 0;
    int n = s->model->n_particles;
    for (int i = 0; i < n; ++i) {
        double* x = s->x + 3 * i;
        double* v = s->v + 3 * i;
        double u[3] = {srnd(1.0), srnd(1.0), srnd(1.0)};
        v3_scale(u, u, 0.6 / v3_norm(u));
        double nrm[3], vc[3];
        double d = wc_mesh_closest(mc, 0, u, HUGE_VAL, nrm, vc);
        double off = THICK + srnd(0.03) - d;
        for (int k = 0; k < 3; ++k) x[k] = u[k] + off * nrm[k];
        double speed = (i % 3 == 0) ? 0.01 : (i % 3 == 1 ? 0.3 : 2.0);
        for (int k = 0; k < 3; ++k) v[k] = srnd(speed);
        if (i % 7 == 3)
            for (int k = 0; k < 3; ++k) v[k] -= nrm[k] * (0.02 / h);
        double x1[3], t, w[3];
        int tri;
        for (int k = 0; k < 3; ++k) x1[k] = x[k] + h * v[k];
        crossing += wc_mesh_ccd(mc, x, x1, 1e-6, &t, &tri, w);
    }
    frv(s->x, 3 * n);
    frv(s->v, 3 * n);
    wc_contacts* ct = &s->contacts;
    for (int i = 0; i < n; ++i) {
        int r = (int)(urand() * 5);
        ct->collider[2 * i] = ct->collider[2 * i + 1] = -1;
        for (int q = 0; q < 6; ++q) ct->normal[6 * i + q] = 0.0;
        ct->released[i] = r == 2;
        ct->stick[i] = 0;
        if (r <= 1) {
            ct->collider[2 * i] = 0;
            wc_mesh_closest(mc, 0, s->x + 3 * i, HUGE_VAL, ct->normal + 6 * i, NULL);
            frv(ct->normal + 6 * i, 3);
        }
    }
    wc_filter* f = &s->filter;
    for (int i = 0; i < n; ++i) wc_filter_free_particle(f, i);
    memset(f->S, 0, 9 * sizeof(double));
    f->ndof[0] = 3;   /* a pin */
    return crossing;
}

/* kind 0: icosphere, 1: box; moving: the frame's target shifted; push: push_speed (m/s);
 * plane: an analytic floor after the mesh (collider 1). */
static void run_case(int kind, int moving, double push, int plane, unsigned long long seed) {
    printf("  %s, %s, push_speed %g%s:\n", kind ? "box" : "icosphere", moving ? "moving" : "still", push,
           plane ? ", a plane after it" : "");
    rng_state = seed;
    double c0[3] = {0.0, 0.0, 0.0}, lo[3] = {-0.4, -0.3, -0.35}, hi[3] = {0.4, 0.3, 0.35};
    if (kind == 0) icosphere(&g_body, 2, 0.5, c0);
    else box(&g_body, lo, hi);
    frv(g_body.x, 3 * g_body.nv);
    wc_model m;
    CHECK(ts_sheet(&m, 14, 1.0, 0.0, 0, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_PCG;
    sd.threads = 1;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    wc_mesh_collider* mc = NULL;
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, g_body.x, g_body.nv, g_body.t, g_body.nt, THICK, 0.5, NULL, &d), WC_OK);
    mc->push_speed = push;
    CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, &mc, 1, &d), WC_OK);
    wc_collider cs[2];
    memset(cs, 0, sizeof cs);
    cs[0].type = WC_COLLIDER_MESH;
    cs[0].mesh = mc;
    cs[0].thickness = mc->thickness;
    cs[0].friction = mc->friction;
    cs[0].push_speed = push;
    int nc = 1;
    if (plane) {
        cs[1].type = WC_COLLIDER_PLANE;
        cs[1].normal[1] = 1.0;
        cs[1].offset = -0.2;
        cs[1].thickness = 0.005;
        cs[1].friction = 0.3;
        CHECK_EQ_INT(wc_state_set_colliders(s, cs + 1, 1, &d), WC_OK);
        nc = 2;
    }
    const double h = 1.0 / 60.0, a1 = 0.5;
    if (moving) {
        double* tgt = malloc(3 * (size_t)g_body.nv * sizeof(double));
        for (int i = 0; i < g_body.nv; ++i)
            for (int k = 0; k < 3; ++k)
                tgt[3 * i + k] = fr(g_body.x[3 * i + k] + (k == 0 ? 0.06 : k == 1 ? 0.03 : 0.0));
        CHECK_EQ_INT(wc_state_set_mesh_target(s, 0, tgt, &d), WC_OK);
        free(tgt);
    }
    s->sub_alpha0 = 0.0;
    wc_mesh_collider_substep(mc, 0.0, a1, h);   /* as the GPU's begin will (the same result) */
    int n = m.n_particles;
    unsigned char* skip = calloc((size_t)n, 1);
    int crossing = scatter(s, mc, h);

    wg_sim* g = NULL;
    CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
    if (!g) {
        printf("    wg_sim_create: %s\n", d.message);
        wc_state_destroy(s);
        wc_mesh_collider_destroy(mc);
        wc_model_free(&m);
        return;
    }
    g_buf = realloc(g_buf, (size_t)n * 16);
    wg_sim_upload(g, s, &d);
    wg_contacts_upload(g->contacts, s);
    upload_filter(g, &s->filter);
    double* x = malloc((size_t)n * 3 * sizeof(double));
    double* vg = malloc((size_t)n * 3 * sizeof(double));
    double* x_sub = malloc((size_t)n * 3 * sizeof(double));
    snap gs = {malloc((size_t)n * 2 * sizeof(int)), malloc((size_t)n * 6 * sizeof(double)), malloc((size_t)n),
               malloc((size_t)n), 0};

    /* begin: the GPU moves the body to the substep (core's wc_mesh_collider_substep), the CPU
       then runs on the body as moved */
    g->x.keep = g->x.cur;
    g->v.keep = g->v.cur;
    wg_contacts_save(g->contacts);
    wg_contacts_begin(g->contacts, s, a1, h);
    s->all = cs;
    s->n_all = nc;
    int act_cpu = wc_contacts_begin(&s->contacts, cs, nc, s->x, s->v, h, &s->filter, &s->par);
    read3(g, wg_ring_cur(&g->x), x);
    int act_gpu = wg_contacts_active(g->contacts), inside = 0, two = 0, near = 0;
    double pushed = 0.0, ex = 0.0;
    for (int i = 0; i < n; ++i) {
        /* a point within 1 mm of the surface: its normal (p - q over |p - q| at an edge) is not
           decided to float precision */
        double ds = wc_mesh_closest(mc, 0, s->x + 3 * i, HUGE_VAL, NULL, NULL);
        if (fabs(ds) < 1e-3) skip[i] = 1, ++near;
        if (!skip[i]) ex = fmax(ex, err_of(x + 3 * i, s->x + 3 * i, 3));
        inside += ds < 0.0;
        two += s->contacts.collider[2 * i + 1] >= 0;
        pushed = fmax(pushed, s->contacts.pushed[i]);
    }
    printf("    begin: %d paths cross the body, %d particles within 1 mm of it after begin (left out)\n", crossing,
           near);
    printf("    begin: %d in contact (%d with two, %d still inside the body, correction up to %.3g m), gpu %d; "
           "x err %.2g\n", act_cpu, two, inside, pushed, act_gpu, ex);
    CHECK(crossing > 0);
    CHECK(near < n / 10);
    CHECK_EQ_INT(act_gpu, act_cpu);
    CHECK(act_cpu > n / 4);
    CHECK(ex < 1e-5);
    if (push > 0.0) CHECK(inside > 0);   /* the cap left some in: project's share is tested */
    if (plane) CHECK(two > 0);
    compare_filter(g, &s->filter, "begin", NULL, skip);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "begin", skip);

    /* project: positions advanced by h v from the corrected ones */
    memcpy(x_sub, s->x, (size_t)n * 3 * sizeof(double));
    for (int i = 0; i < 3 * n; ++i) s->x[i] = fr(x[i] + h * s->v[i]);
    upload3(g, wg_ring_cur(&g->x), s->x);
    int crossed = 0;
    for (int i = 0; i < n; ++i) {
        double t, w[3];
        int tri;
        crossed += wc_mesh_ccd(mc, x_sub + 3 * i, s->x + 3 * i, 1e-6, &t, &tri, w);
    }
    int moved = wc_contacts_project_from(&s->contacts, cs, nc, &s->filter, x_sub, s->x, s->v, &s->par);
    wg_contacts_project(g->contacts, s);
    read3(g, wg_ring_cur(&g->x), x);
    read3(g, wg_ring_cur(&g->v), vg);
    double epx = 0.0, epv = 0.0, worst = 0.0;
    for (int i = 0; i < n; ++i) {
        epx = fmax(epx, err_of(x + 3 * i, s->x + 3 * i, 3));
        epv = fmax(epv, err_of(vg + 3 * i, s->v + 3 * i, 3));
        /* the GPU's positions against the body (core's query, double) */
        if (i > 0 && push == 0.0)
            worst = fmax(worst, mc->thickness - wc_mesh_closest(mc, 1, x + 3 * i, HUGE_VAL, NULL, NULL));
    }
    printf("    project: %d moved, %d paths crossed the body (put back); x err %.2g, v err %.2g; deepest into the "
           "shell %.2g m\n", moved, crossed, epx, epv, worst);
    CHECK(moved > 0);
    CHECK(crossed > 0);
    CHECK(epx < 1e-5);
    CHECK(epv < 1e-5);
    if (push == 0.0) CHECK(worst < 1e-5);
    CHECK(glGetError() == GL_NO_ERROR);

    free(skip);
    free(x), free(vg), free(x_sub);
    free(gs.collider), free(gs.normal), free(gs.released), free(gs.stick);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
}

/* The GPU memory a cloth holds (wg_sim_gpu_bytes, the backend's device_bytes) counts the
 * contacts' textures and the mesh colliders' (their bodies' too): one sheet without colliders,
 * with room for them, and with an icosphere; each step up holds at least the texels those
 * textures need, 16 bytes each (RGBA32F). */
static void test_device_bytes(void) {
    double c0[3] = {0.0, 0.0, 0.0};
    icosphere(&g_body, 2, 0.5, c0);
    wc_model m;
    CHECK(ts_sheet(&m, 14, 1.0, 0.0, 0, 1.0));
    size_t bytes[3] = {0, 0, 0};
    int n_node = 0;
    for (int k = 0; k < 3; ++k) {
        wc_sim_def sd = wc_default_sim_def();
        sd.solver.type = WC_SOLVER_PCG;
        sd.threads = 1;
        if (k == 0) sd.max_colliders = 0;
        wc_state* s = NULL;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
        wc_mesh_collider* mc = NULL;
        if (k == 2) {
            CHECK_EQ_INT(wc_mesh_collider_create(&mc, g_body.x, g_body.nv, g_body.t, g_body.nt, THICK, 0.5, NULL, &d),
                         WC_OK);
            CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, &mc, 1, &d), WC_OK);
            n_node = mc->bvh.n_nodes;
        }
        wg_sim* g = NULL;
        CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
        if (g) bytes[k] = wg_sim_gpu_bytes(g);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_mesh_collider_destroy(mc);
    }
    /* the contacts, per particle: rings of 3 textures for 3 arrays, their back-ups, the filter's
       scratch (S0, S1, z, b), the diagonal blocks, the surface velocities, x after begin, the
       held impulses */
    const size_t contacts = 16 * (size_t)m.n_particles * (9 + 3 + 4 + 2 + 1 + 1 + 2);
    /* the meshes: vertices (3 texels), triangles (3), nodes (2); the bodies: 5 per vertex (from,
       to, the take's scratch, the back-up, the measure), 1 per triangle and per node */
    size_t meshes = 16 * (3 * (size_t)g_body.nv + 3 * (size_t)g_body.nt + 2 * (size_t)n_node);
    if (g_dev->compute) meshes += 16 * (5 * (size_t)g_body.nv + (size_t)g_body.nt + (size_t)n_node);
    printf("  device bytes: %zu without colliders, %zu with room for them (+%zu at least), %zu with an icosphere "
           "(+%zu at least)\n", bytes[0], bytes[1], contacts, bytes[2], meshes);
    CHECK(bytes[0] > 0);
    CHECK(bytes[1] >= bytes[0] + contacts);
    CHECK(bytes[2] >= bytes[1] + meshes);
    wc_model_free(&m);
}

static void test_cases(void) {
    run_case(0, 0, 0.0, 0, 0x51u);
    run_case(0, 1, 0.0, 0, 0x52u);
    run_case(0, 1, 0.05, 0, 0x53u);
    run_case(1, 0, 0.0, 0, 0x54u);
    run_case(1, 1, 0.05, 1, 0x55u);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_cases);
    RUN_TEST(test_device_bytes);
    tg_gpu_close(g_ctx, g_dev);
    free(g_buf);
    return TEST_SUMMARY();
}
