/* The GPU contact passes (gpu/solver/wg_contacts.c) against core/collide.c, step by step, on the
 * same (float-rounded) input: a 6 x 6 sheet's particles scattered around a plane, a sphere or a
 * capsule (each with a second, crossing plane for two-contact corners), with held, released and
 * pinned particles, moving and still colliders, velocities from creeping (sticks) to fast
 * (slides). Each hook runs on the GPU and its CPU function on the state's arrays; positions,
 * filters, contact state, the friction's diagonal blocks and b are read back and compared to
 * float precision. A synthetic system stands in for the assembly (A = M + small symmetric
 * blocks, b = h f + noise): the hooks only read it. Also: save/restore, upload/download. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "collide.h"
#include "collide_friction.h"
#include "gpu_test_device.h"
#include "state.h"
#include "test_support.h"
#include "wg_device.h"
#include "wg_sim_impl.h"
#include "gpu_contacts_support.h"

static wg_gl_context* g_ctx;
static wg_device* g_dev;

static void run_case(int kind, int moving, unsigned long long seed) {
    static const char* names[] = {"plane", "sphere", "capsule"};
    printf("  %s, collider %s:\n", names[kind], moving ? "moving" : "still");
    rng_state = seed;
    wc_model m;
    CHECK(ts_sheet(&m, 6, 1.0, 0.0, 0, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_PCG;
    sd.threads = 1;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    wc_collider c[2];
    int nc = make_colliders(kind, moving, c);
    CHECK_EQ_INT(wc_state_set_colliders(s, c, nc, &d), WC_OK);
    memcpy(c, s->colliders, (size_t)nc * sizeof *c);
    const double h = 1.0 / 60.0;
    int n = m.n_particles, nb = m.pattern.n_blocks;
    scatter_analytic(s, c, nc, h);

    wg_sim* g = NULL;
    CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
    if (!g) {
        printf("    wg_sim_create: %s\n", d.message);
        wc_state_destroy(s);
        wc_model_free(&m);
        return;
    }
    CHECK(g->contacts != NULL);
    g_buf = realloc(g_buf, (size_t)(n > nb ? n : nb) * 16);
    wg_sim_upload(g, s, &d);
    wg_contacts_upload(g->contacts, s);
    upload_filter(g, &s->filter);

    double* x = malloc((size_t)n * 3 * sizeof(double));
    double* A = malloc((size_t)nb * 9 * sizeof(double));
    double* Ag = malloc((size_t)nb * 9 * sizeof(double));
    double* b = malloc((size_t)n * 3 * sizeof(double));
    double* f = malloc((size_t)n * 3 * sizeof(double));
    double* dv = malloc((size_t)n * 3 * sizeof(double));
    double* r = malloc((size_t)n * 3 * sizeof(double));
    snap gs = {malloc((size_t)n * 2 * sizeof(int)), malloc((size_t)n * 6 * sizeof(double)), malloc((size_t)n),
               malloc((size_t)n), 0};
    snap before = {malloc((size_t)n * 2 * sizeof(int)), malloc((size_t)n * 6 * sizeof(double)), malloc((size_t)n),
                   malloc((size_t)n), 0};

    /* upload / download round trip */
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "upload/download", NULL);

    /* 1. begin */
    g->x.keep = g->x.cur;   /* as the step's save does */
    g->v.keep = g->v.cur;
    wg_contacts_save(g->contacts);
    int x_start = g->x.cur, v_start = g->v.cur;
    take_gpu(g, s, &before);
    int act_cpu = wc_contacts_begin(&s->contacts, c, nc, s->x, s->v, h, &s->filter, &s->par);
    wg_contacts_begin(g->contacts, s, 1.0, h);
    read3(g, wg_ring_cur(&g->x), x);
    double ex = err_of(x, s->x, 3 * n);
    int act_gpu = wg_contacts_active(g->contacts);
    int two = 0;
    for (int i = 0; i < n; ++i) two += s->contacts.collider[2 * i + 1] >= 0;
    printf("    begin: %d in contact (%d with two), gpu %d; x err %.2g\n", act_cpu, two, act_gpu, ex);
    CHECK_EQ_INT(act_gpu, act_cpu);
    CHECK(act_cpu > n / 4);
    CHECK(ex < 1e-5);
    compare_filter(g, &s->filter, "begin", NULL, NULL);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "begin", NULL);

    /* save / restore: back to the state before begin, then forward again */
    wg_contacts_restore(g->contacts);
    take_gpu(g, s, &gs);
    int diff = memcmp(gs.collider, before.collider, (size_t)n * 2 * sizeof(int)) != 0 ||
               memcmp(gs.normal, before.normal, (size_t)n * 6 * sizeof(double)) != 0 ||
               memcmp(gs.released, before.released, (size_t)n) != 0;
    CHECK(!diff);
    CHECK_EQ_INT(wg_contacts_active(g->contacts), before.active);
    /* redo begin on the GPU from the original input (x, filter were changed: re-upload) */
    {
        wc_state* s2 = NULL;
        CHECK_EQ_INT(wc_state_create(&s2, &m, &sd, NULL, &d), WC_OK);
        CHECK_EQ_INT(wc_state_set_colliders(s2, c, nc, &d), WC_OK);
        rng_state = seed;
        scatter_analytic(s2, c, nc, h);
        wg_sim_upload(g, s2, &d);
        upload_filter(g, &s2->filter);
        wc_state_destroy(s2);
    }
    wg_contacts_begin(g->contacts, s, 1.0, h);
    read3(g, wg_ring_cur(&g->x), x);
    CHECK(err_of(x, s->x, 3 * n) < 1e-5);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "begin after restore", NULL);

    /* 2. friction */
    synth_system(s, c, h, A, b, f);
    upload_A(g, A);
    upload3(g, &g->b, b);
    upload3(g, &g->ftot, f);
    int st_cpu = wc_contacts_friction(&s->contacts, c, nc, s->v, m.mass, f, NULL, h, &s->filter, A, m.pattern.diag, b,
                                      &s->par);
    wg_contacts_friction(g->contacts, s, h, NULL);
    int n_stick = 0;
    compare_filter(g, &s->filter, "friction", &n_stick, NULL);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "friction", NULL);
    read_A(g, Ag);
    double eA = err_of(Ag, A, 9 * nb);
    double* bg = malloc((size_t)n * 3 * sizeof(double));
    read3(g, &g->b, bg);
    double eb = err_of(bg, b, 3 * n);
    int slides = 0;
    for (int i = 0; i < n; ++i) slides += s->contacts.collider[2 * i] >= 0 && !s->contacts.stick[i];
    printf("    friction: %d stick, %d slide; A err %.2g, b err %.2g\n", st_cpu, slides, eA, eb);
    CHECK(st_cpu > 0);
    CHECK(slides > 0);
    CHECK(eA < 1e-5);
    CHECK(eb < 1e-5);

    /* 3b. recheck: dv a guess, r = A dv - b */
    for (int i = 0; i < 3 * n; ++i) dv[i] = fr(srnd(0.5));
    upload3(g, &g->sv[0], dv);
    residual(&m, A, b, dv, r);
    int ch_cpu = wc_contacts_friction_recheck(&s->contacts, c, nc, s->v, m.mass, r, &s->filter, A, m.pattern.diag, b,
                                              &s->par);
    int ch_gpu = wg_contacts_recheck(g->contacts, s, &g->sv[0]);
    compare_filter(g, &s->filter, "recheck", NULL, NULL);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "recheck", NULL);
    read_A(g, Ag);
    read3(g, &g->b, bg);
    eA = err_of(Ag, A, 9 * nb);
    eb = err_of(bg, b, 3 * n);
    printf("    recheck: %d sticks let go (gpu says changed: %d); A err %.2g, b err %.2g\n", ch_cpu, ch_gpu, eA, eb);
    CHECK_EQ_INT(ch_gpu, ch_cpu > 0);
    CHECK(eA < 1e-5);
    CHECK(eb < 1e-5);

    /* 4. end: a second guess, r = A dv - b with the system as it is now */
    for (int i = 0; i < 3 * n; ++i) dv[i] = fr(srnd(0.3));
    upload3(g, &g->sv[1], dv);
    /* use the GPU's A and b (float) on both sides, so that the sign of each impulse is decided
       on the same numbers */
    memcpy(A, Ag, (size_t)nb * 9 * sizeof(double));
    memcpy(b, bg, (size_t)n * 3 * sizeof(double));
    residual(&m, A, b, dv, r);
    wc_contacts_end(&s->contacts, nc, r, &s->par);
    wg_contacts_end(g->contacts, s, &g->sv[1], 0);
    int rel = 0;
    for (int i = 0; i < n; ++i) rel += s->contacts.released[i];
    act_gpu = wg_contacts_active(g->contacts);
    printf("    end: %d still in contact (gpu %d), %d released\n", s->contacts.active, act_gpu, rel);
    CHECK_EQ_INT(act_gpu, s->contacts.active);
    CHECK(rel > 0);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "end", NULL);

    /* 5. project: positions advanced by h v from the corrected ones, v as given */
    read3(g, wg_ring_cur(&g->x), x);
    for (int i = 0; i < 3 * n; ++i) s->x[i] = fr(x[i] + h * s->v[i] * 2.0);
    upload3(g, wg_ring_cur(&g->x), s->x);
    int moved = wc_contacts_project(&s->contacts, c, nc, &s->filter, s->x, s->v, &s->par);
    wg_contacts_project(g->contacts, s);
    /* the substep's start (saved) is never written: a rollback can return to it */
    CHECK(g->x.cur != x_start);
    CHECK(g->v.cur != v_start);
    double* vg = malloc((size_t)n * 3 * sizeof(double));
    read3(g, wg_ring_cur(&g->x), x);
    read3(g, wg_ring_cur(&g->v), vg);
    double epx = err_of(x, s->x, 3 * n), epv = err_of(vg, s->v, 3 * n);
    printf("    project: %d moved; x err %.2g, v err %.2g\n", moved, epx, epv);
    CHECK(moved > 0);
    CHECK(epx < 1e-5);
    CHECK(epv < 1e-5);
    /* nothing on the GPU is left inside a shell */
    double worst = 0;
    for (int i = 1; i < n; ++i)
        for (int k = 0; k < nc; ++k) {
            double nn[3], dd = wc_collider_distance(&c[k], x + 3 * i, nn) - c[k].thickness;
            if (-dd > worst) worst = -dd;
        }
    printf("    project: deepest left %.2g m\n", worst);
    CHECK(worst < 1e-5);

    free(vg);
    free(bg);
    free(x), free(A), free(Ag), free(b), free(f), free(dv), free(r);
    free(gs.collider), free(gs.normal), free(gs.released), free(gs.stick);
    free(before.collider), free(before.normal), free(before.released), free(before.stick);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* max_colliders 0: nothing is allocated, the hooks are no-ops. */
static void test_no_capacity(void) {
    wc_model m;
    CHECK(ts_sheet(&m, 3, 1.0, 0.0, 0, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_PCG;
    sd.max_colliders = 0;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    wg_sim* g = NULL;
    CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
    if (g) {
        CHECK(g->contacts == NULL);
        CHECK_EQ_INT(wg_contacts_active(g->contacts), 0);
        wg_sim_destroy(g);
    }
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Through the step (wg_step.c drives the hooks): a 16 x 16 sheet dropped on a sphere or capsule
 * over a floor plane, as test_step_contacts' "nothing ends inside" on the CPU; the GPU run ends
 * with contacts and nothing inside a shell (float: a few ulps), and stays near the CPU run. */
static void test_drop_frames(void) {
    for (int type = 1; type < 3; ++type) {
        int n = 16;
        wc_model m;
        CHECK(ts_sheet(&m, n, 1.0, 0.8, 0, 1.0));
        wc_sim_def sd = wc_default_sim_def();
        sd.solver.type = WC_SOLVER_PCG;
        sd.threads = 1;
        wc_state *s = NULL, *sc = NULL;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
        CHECK_EQ_INT(wc_state_create(&sc, &m, &sd, NULL, &d), WC_OK);
        wc_collider c[2];
        memset(c, 0, sizeof c);
        c[0].type = type;
        c[0].thickness = 0.01;
        c[0].friction = 0.4;
        if (type == WC_COLLIDER_SPHERE) {
            c[0].center[0] = 0.05, c[0].center[1] = 0.3, c[0].center[2] = 0.02;
            c[0].radius = 0.3;
        } else {
            c[0].a[0] = -0.6, c[0].a[1] = 0.25, c[0].a[2] = 0.1;
            c[0].b[0] = 0.6, c[0].b[1] = 0.3, c[0].b[2] = -0.1;
            c[0].radius = 0.15;
        }
        c[1].type = WC_COLLIDER_PLANE;
        c[1].normal[1] = 1.0;
        c[1].thickness = 0.01;
        c[1].friction = 0.4;
        CHECK_EQ_INT(wc_state_set_colliders(s, c, 2, &d), WC_OK);
        CHECK_EQ_INT(wc_state_set_colliders(sc, c, 2, &d), WC_OK);
        wg_sim* g = NULL;
        CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
        if (!g) {
            printf("  wg_sim_create: %s\n", d.message);
            wc_state_destroy(s), wc_state_destroy(sc), wc_model_free(&m);
            continue;
        }
        wc_status st = WC_OK;
        wc_step_stats gst, cst;
        memset(&gst, 0, sizeof gst);
        memset(&cst, 0, sizeof cst);
        for (int f = 0; f < 45 && st == WC_OK; ++f) {
            st = wg_sim_step_frame(g, s, 1.0 / 30, &gst, &d);
            CHECK_EQ_INT(wc_step_frame(sc, 1.0 / 30, &cst, &d), WC_OK);
        }
        CHECK_EQ_INT(st, WC_OK);
        if (st != WC_OK) printf("  step: %s\n", d.message);
        CHECK_EQ_INT(wg_sim_download(g, s, &d), WC_OK);
        int np = m.n_particles;
        double worst = 0, diff = 0;
        for (int i = 0; i < np; ++i) {
            for (int k = 0; k < 2; ++k) {
                double nn[3], dd = c[k].thickness - wc_collider_distance(&c[k], s->x + 3 * i, nn);
                if (dd > worst) worst = dd;
            }
            for (int k = 0; k < 3; ++k) diff = fmax(diff, fabs(s->x[3 * i + k] - sc->x[3 * i + k]));
        }
        printf("  %s: gpu %d in contact (cpu %d), deepest %.2g m, max |x_gpu - x_cpu| %.3g m\n",
               type == 1 ? "sphere" : "capsule", gst.contacts, cst.contacts, worst, diff);
        CHECK(gst.contacts > 0);
        CHECK(worst < 1e-5);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_state_destroy(sc);
        wc_model_free(&m);
    }
}

/* Friction through the step: a sheet lying on a floor under gravity tilted by 20 degrees
 * (tan = 0.36): with mu 0.6 it stays put, with mu 0.2 it slides at g (sin - mu cos); the GPU's
 * mean displacement after 1 s matches the CPU's. */
static void test_incline(void) {
    const double th = 20.0 * 3.14159265358979323846 / 180.0;
    for (int run = 0; run < 2; ++run) {
        double mu = run == 0 ? 0.6 : 0.2;
        wc_model m;
        CHECK(ts_sheet(&m, 8, 0.5, 0.01, 0, 1.0));
        wc_sim_def sd = wc_default_sim_def();
        sd.solver.type = WC_SOLVER_PCG;
        sd.threads = 1;
        sd.gravity[0] = 9.81 * sin(th), sd.gravity[1] = -9.81 * cos(th), sd.gravity[2] = 0.0;
        wc_state *s = NULL, *sc = NULL;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
        CHECK_EQ_INT(wc_state_create(&sc, &m, &sd, NULL, &d), WC_OK);
        wc_collider c;
        memset(&c, 0, sizeof c);
        c.type = WC_COLLIDER_PLANE;
        c.normal[1] = 1.0;
        c.thickness = 0.01;
        c.friction = mu;
        CHECK_EQ_INT(wc_state_set_colliders(s, &c, 1, &d), WC_OK);
        CHECK_EQ_INT(wc_state_set_colliders(sc, &c, 1, &d), WC_OK);
        wg_sim* g = NULL;
        CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
        if (!g) {
            wc_state_destroy(s), wc_state_destroy(sc), wc_model_free(&m);
            continue;
        }
        int np = m.n_particles;
        double x0 = 0;
        for (int i = 0; i < np; ++i) x0 += s->x[3 * i] / np;
        wc_step_stats gst, cst;
        wc_status st = WC_OK;
        for (int f = 0; f < 30 && st == WC_OK; ++f) {
            st = wg_sim_step_frame(g, s, 1.0 / 30, &gst, &d);
            CHECK_EQ_INT(wc_step_frame(sc, 1.0 / 30, &cst, &d), WC_OK);
        }
        CHECK_EQ_INT(st, WC_OK);
        CHECK_EQ_INT(wg_sim_download(g, s, &d), WC_OK);
        double xg = 0, xc = 0;
        for (int i = 0; i < np; ++i) xg += s->x[3 * i] / np, xc += sc->x[3 * i] / np;
        xg -= x0, xc -= x0;
        double expect = mu > tan(th) ? 0.0 : 0.5 * 9.81 * (sin(th) - mu * cos(th));
        printf("  mu %.1f: slid %.4f m on the GPU, %.4f m on the CPU (particle alone: %.4f); %d / %d in contact\n",
               mu, xg, xc, expect, gst.contacts, cst.contacts);
        CHECK(fabs(xg - xc) < 1e-3 + 0.02 * fabs(xc));
        CHECK_EQ_INT(gst.contacts, cst.contacts);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_state_destroy(sc);
        wc_model_free(&m);
    }
}

static void test_cases(void) {
    for (int kind = 0; kind < 3; ++kind)
        for (int moving = 0; moving < 2; ++moving) run_case(kind, moving, 0x1234567ull + 977ull * kind + moving);
    CHECK(glGetError() == GL_NO_ERROR);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_cases);
    RUN_TEST(test_no_capacity);
    RUN_TEST(test_drop_frames);
    RUN_TEST(test_incline);
    tg_gpu_close(g_ctx, g_dev);
    free(g_buf);
    return TEST_SUMMARY();
}
