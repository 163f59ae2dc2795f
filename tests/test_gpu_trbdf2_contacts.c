/* TR-BDF2's contact passes on the GPU (integ_contacts.glsl, contact_friction.glsl's stage momentum,
 * contact_end.glsl's held impulses) against core/bdf2.c's wc_integ_contacts and
 * wc_integ_contact_impulses and core/collide.c's friction with mom, on the same (float-rounded)
 * input, on a real EGL context (llvmpipe without a GPU): a 6 x 6 sheet's particles scattered
 * around a plane, a sphere or a capsule, still or moving, with a second crossing plane for
 * two-contact corners (test_gpu_contacts.c's scenario). Stage 1: begin, the integrator's xb, v*,
 * then the contact rule (v, xb, v*, z, v_prev compared); friction with a stage momentum term
 * (filter, A, b, sticks); its end holds the impulses and releases nothing. Stage 2 (x_g, x_n, v_n
 * synthetic): begin, xb, v*, mom, the contact rule (v, xb, v*, mom, z); its end adds stage 1's
 * held impulses before releasing (contact state compared, and the held impulses shown to change
 * the decisions). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bdf2.h"
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

/* The contact rule's results on both sides: v, xb, v*, z, and stage 1's v_prev or stage 2's mom.
 * Returns the particles in contact. */
static int compare_rule(wg_sim* g, wc_state* s, int stage, double* tmp) {
    int n = g->n, in_contact = 0;
    for (int i = 0; i < n; ++i) in_contact += s->contacts.collider[2 * i] >= 0;
    read3(g, wg_ring_cur(&g->v), tmp);
    double ev = err_of(tmp, s->v, 3 * n);
    read3(g, &g->xb, tmp);
    double exb = err_of(tmp, s->xb, 3 * n);
    read3(g, &g->vstar, tmp);
    double evs = err_of(tmp, s->vstar, 3 * n);
    read3(g, &g->z, tmp);
    double ez = err_of(tmp, s->filter.z, 3 * n);
    read3(g, stage == 1 ? wg_ring_cur(&g->vp) : &g->mom, tmp);
    double ec = err_of(tmp, stage == 1 ? s->v_prev : s->mom, 3 * n);
    /* v* = v + (xb - x) / he divides xb's rounding by he: its scale is 1 / he larger */
    printf("    stage %d's contact rule: %d in contact; errors v %.2g, xb %.2g, v* %.2g, z %.2g, %s %.2g\n", stage,
           in_contact, ev, exb, evs, ez, stage == 1 ? "v_prev" : "mom", ec);
    CHECK(ev < 1e-5);
    CHECK(exb < 1e-5);
    CHECK(evs < 2e-4);
    CHECK(ez < 1e-5);
    CHECK(ec < 1e-5);
    return in_contact;
}

static void run_case(int kind, int moving, unsigned long long seed) {
    static const char* names[] = {"plane", "sphere", "capsule"};
    printf("  %s, collider %s:\n", names[kind], moving ? "moving" : "still");
    rng_state = seed;
    wc_model m;
    CHECK(ts_sheet(&m, 6, 1.0, 0.0, 0, 1.0));
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_PCG;
    sd.threads = 1;
    sd.integrator = WC_INTEGRATOR_TRBDF2;
    wc_state* s = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    wc_collider c[2];
    int nc = make_colliders(kind, moving, c);
    CHECK_EQ_INT(wc_state_set_colliders(s, c, nc, &d), WC_OK);
    memcpy(c, s->colliders, (size_t)nc * sizeof *c);
    const double h = 1.0 / 30.0;
    int n = m.n_particles, nb = m.pattern.n_blocks;
    wc_integ ig;
    wc_integ_coefficients(s, h, 1, &ig);
    scatter_analytic(s, c, nc, ig.h);

    wg_sim* g = NULL;
    CHECK_EQ_INT(wg_sim_create(g_dev, s, NULL, &g, &d), WC_OK);
    if (!g) {
        printf("    wg_sim_create: %s\n", d.message);
        wc_state_destroy(s);
        wc_model_free(&m);
        return;
    }
    CHECK(g->contacts != NULL && g->integ);
    g_buf = realloc(g_buf, (size_t)(n > nb ? n : nb) * 16);
    wg_sim_upload(g, s, &d);
    wg_contacts_upload(g->contacts, s);
    upload_filter(g, &s->filter);
    g->x.keep = g->x.cur;   /* as the step's save does */
    g->v.keep = g->v.cur;
    g->vp.keep = g->vp.cur;
    wg_contacts_save(g->contacts);

    double* tmp = malloc((size_t)n * 3 * sizeof(double));
    double* A = malloc((size_t)nb * 9 * sizeof(double));
    double* b = malloc((size_t)n * 3 * sizeof(double));
    double* f = malloc((size_t)n * 3 * sizeof(double));
    double* dv = malloc((size_t)n * 3 * sizeof(double));
    double* r2 = malloc((size_t)n * 3 * sizeof(double));
    snap gs = {malloc((size_t)n * 2 * sizeof(int)), malloc((size_t)n * 6 * sizeof(double)), malloc((size_t)n),
               malloc((size_t)n), 0};
    const wg_contact_integ io = {&g->xb, &g->vstar, &g->mom, &g->vp};

    /* stage 1: begin, xb / v* / v_prev, the contact rule */
    wc_integ_begin(s, h, &ig);
    const wg_tex* x_start = wg_ring_cur(&g->x);
    wc_contacts_begin(&s->contacts, c, nc, s->x, s->v, ig.h, &s->filter, &s->par);
    wc_integ_prepare(s, &ig);
    wc_integ_contacts(s, &ig);
    wg_contacts_begin(g->contacts, s, 1.0, ig.h);
    wg_integ_prepare(g, s, &ig, x_start);
    wg_contacts_integ(g->contacts, &io, 1, ig.h, ig.he);
    int in1 = compare_rule(g, s, 1, tmp);
    CHECK(in1 > n / 4);

    /* stage 1's friction with its momentum term mom = he f0 / m (synthetic, as large as gravity's) */
    synth_system(s, c, ig.he, A, b, f);
    for (int k = 0; k < 3 * n; ++k) s->mom[k] = fr(srnd(ig.he * 15.0));
    upload_A(g, A);
    upload3(g, &g->b, b);
    upload3(g, &g->ftot, f);
    upload3(g, &g->mom, s->mom);
    int st_cpu = wc_contacts_friction(&s->contacts, c, nc, s->v, m.mass, f, s->mom, ig.he, &s->filter, A,
                                      m.pattern.diag, b, &s->par);
    wg_contacts_friction(g->contacts, s, ig.he, &g->mom);
    int n_stick = 0;
    compare_filter(g, &s->filter, "friction with mom", &n_stick, NULL);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "friction with mom", NULL);
    double* Ag = malloc((size_t)nb * 9 * sizeof(double));
    read_A(g, Ag);
    read3(g, &g->b, tmp);
    double eA = err_of(Ag, A, 9 * nb), eb = err_of(tmp, b, 3 * n);
    CHECK(eA < 1e-5);
    CHECK(eb < 1e-5);
    memcpy(A, Ag, (size_t)nb * 9 * sizeof(double));   /* the GPU's A and b (float) on both sides from here: */
    memcpy(b, tmp, (size_t)n * 3 * sizeof(double));   /* the impulses' signs are decided alike */
    free(Ag);
    /* what the momentum term changed: the same friction without it on a copy */
    int st_nomom = 0;
    {
        wc_state* s2 = NULL;
        CHECK_EQ_INT(wc_state_create(&s2, &m, &sd, NULL, &d), WC_OK);
        CHECK_EQ_INT(wc_state_set_colliders(s2, c, nc, &d), WC_OK);
        rng_state = seed;
        scatter_analytic(s2, c, nc, ig.h);
        wc_integ ig2;
        wc_integ_begin(s2, h, &ig2);
        wc_contacts_begin(&s2->contacts, c, nc, s2->x, s2->v, ig2.h, &s2->filter, &s2->par);
        wc_integ_prepare(s2, &ig2);
        wc_integ_contacts(s2, &ig2);
        double* A2 = malloc((size_t)nb * 9 * sizeof(double));
        double* b2 = malloc((size_t)n * 3 * sizeof(double));
        synth_system(s2, c, ig2.he, A2, b2, f);
        st_nomom = wc_contacts_friction(&s2->contacts, c, nc, s2->v, m.mass, f, NULL, ig2.he, &s2->filter, A2,
                                        m.pattern.diag, b2, &s2->par);
        free(A2), free(b2);
        wc_state_destroy(s2);
    }
    printf("    friction with the stage's mom: %d stick (ndof 3 on the GPU: %d, the fixed pin included), A err "
           "%.2g, b err %.2g; %d stick without mom\n", st_cpu, n_stick, eA, eb, st_nomom);
    CHECK(st_cpu > 0);
    CHECK(st_cpu != st_nomom);   /* the momentum term decides some contacts */

    /* stage 1's end: the impulses held, nothing released */
    for (int k = 0; k < 3 * n; ++k) dv[k] = fr(srnd(0.3));
    upload3(g, &g->sv[0], dv);
    residual(&m, A, b, dv, s->r);
    CHECK_EQ_INT(wc_integ_contact_impulses(s, &ig), 0);
    wg_contacts_end(g->contacts, s, &g->sv[0], 1);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "stage 1's end", NULL);
    CHECK_EQ_INT(wg_contacts_active(g->contacts), in1);

    /* stage 2: x_g (solved), the substep's start x_n, v_n synthetic; x, v as the GPU holds them */
    read3(g, wg_ring_cur(&g->x), s->x);
    read3(g, wg_ring_cur(&g->v), s->v);
    for (int k = 0; k < 3 * n; ++k) {
        s->xs[k] = fr(s->x[k] + srnd(0.01));
        s->x_prev[k] = fr(s->x[k] - srnd(0.02));
        s->v_prev[k] = fr(s->v[k] + srnd(0.2));
    }
    upload3(g, &g->xs, s->xs);
    upload3(g, wg_ring_cur(&g->xp), s->x_prev);
    upload3(g, wg_ring_cur(&g->vp), s->v_prev);
    s->sub_alpha0 = WC_TRBDF2_GAMMA;
    wc_integ_begin_stage2(s, h, &ig);
    wc_contacts_begin(&s->contacts, c, nc, s->x, s->v, ig.h, &s->filter, &s->par);
    wc_integ_prepare(s, &ig);
    wc_integ_contacts(s, &ig);
    wg_contacts_begin(g->contacts, s, 1.0, ig.h);
    wg_integ_prepare(g, s, &ig, wg_ring_cur(&g->x));
    wg_contacts_integ(g->contacts, &io, 2, ig.h, ig.he);
    int in2 = compare_rule(g, s, 2, tmp);
    CHECK(in2 > n / 4);

    /* stage 2's end: stage 1's impulses added before the release */
    for (int k = 0; k < 3 * n; ++k) dv[k] = fr(srnd(0.3));
    upload3(g, &g->sv[1], dv);
    residual(&m, A, b, dv, s->r);
    memcpy(r2, s->r, (size_t)n * 3 * sizeof(double));
    int flips = 0;   /* single contacts whose impulse changes sign with stage 1's added */
    for (int i = 0; i < n; ++i) {
        if (s->contacts.collider[2 * i] < 0 || s->contacts.collider[2 * i + 1] >= 0) continue;
        const double* nn = s->contacts.normal + 6 * i;
        double a = 0.0, q = 0.0;
        for (int k = 0; k < 3; ++k) {
            a += r2[3 * i + k] * nn[k];
            q += (r2[3 * i + k] + s->stage1_impulse[3 * i + k]) * nn[k];
        }
        flips += (a < 0.0) != (q < 0.0);
    }
    CHECK_EQ_INT(wc_integ_contact_impulses(s, &ig), 1);
    wc_contacts_end(&s->contacts, nc, s->r, &s->par);
    wg_contacts_end(g->contacts, s, &g->sv[1], 2);
    take_gpu(g, s, &gs);
    compare_contacts(&s->contacts, &gs, n, 1, "stage 2's end", NULL);
    int rel = 0;
    for (int i = 0; i < n; ++i) rel += s->contacts.released[i];
    printf("    stage 2's end: %d still in contact (GPU %d), %d released; stage 1's impulses turn %d decisions\n",
           s->contacts.active, wg_contacts_active(g->contacts), rel, flips);
    CHECK_EQ_INT(wg_contacts_active(g->contacts), s->contacts.active);
    CHECK(rel > 0);
    CHECK(flips > 0);

    free(tmp), free(A), free(b), free(f), free(dv), free(r2);
    free(gs.collider), free(gs.normal), free(gs.released), free(gs.stick);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

static void test_cases(void) {
    run_case(0, 0, 11);
    run_case(1, 1, 12);
    run_case(2, 1, 13);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_cases);
    free(g_buf);
    tg_gpu_close(g_ctx, g_dev);
    return TEST_SUMMARY();
}
