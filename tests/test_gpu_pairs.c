/* The penalty pairs in the GPU's solve (gpu/solver/wg_pairs.h) against core on the same
 * float-rounded input: two 6 x 6 sheets 2.5 mm apart (tests/two_layers.h), the upper one moving
 * down onto the lower, self-collision with its pairs in the solve (backward Euler, PCG with block
 * Jacobi). One substep's first system: the pairs found (particles, normals) and their active set
 * as core's, b and A (the pairs' diagonal blocks in it) to float precision against core's
 * prepare; the off-diagonal blocks through the GPU's product (A x less the pattern's part) against
 * wc_coupling_mul_offdiag_add; then a solve on each side (the GPU's solution solves core's system,
 * couplings included, to 1e-3) and the recheck of core's solution rounded to float on each: the
 * pairs switched and the active set after it as core's, and b and A after it. With Newton: the
 * pairs' exact terms at an iterate (wc_penalty_pairs_newton) and their part of the incremental
 * potential's change (wc_penalty_pairs_energy), both on the GPU's passes, as core's. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bsr.h"
#include "check.h"
#include "gpu_test_device.h"
#include "penalty_pairs.h"
#include "self_collide.h"
#include "self_pairs.h"
#include "solve.h"
#include "state.h"
#include "step.h"
#include "test_support.h"
#include "two_layers.h"
#include "wg_device.h"
#include "wg_sim_impl.h"

#define LN 6
#define SIZE 0.3
#define H (1.0 / 120.0)

static wg_gl_context* gl;
static wg_device* dev;

/* largest |a - b| over count values, over the largest |b| (1 when b is all zeros) */
static double rel_err(const double* a, const double* b, size_t count) {
    double e = 0.0, s = 0.0;
    for (size_t k = 0; k < count; ++k) {
        e = fmax(e, fabs(a[k] - b[k]));
        s = fmax(s, fabs(b[k]));
    }
    return e / (s > 0.0 ? s : 1.0);
}

static void round_to_float(double* a, size_t count) {
    for (size_t k = 0; k < count; ++k) a[k] = (double)(float)a[k];
}

/* The GPU's uploaded pairs against core's list: the same particles, normals within float, the
 * same active set. Returns the active pairs. */
static int compare_lists(const wc_penalty_pairs* cpu, const wg_pairs* gp, const char* when) {
    const int *ip = NULL;
    const float *fw = NULL, *fnc = NULL;
    int n = wg_pairs_debug_list(gp, &ip, &fw, &fnc);
    CHECK_EQ_INT(n, cpu->n);
    int same_p = 1, same_active = 1, active = 0;
    double en = 0.0, ec = 0.0;
    for (int j = 0; j < n && j < cpu->n; ++j) {
        const wc_coupling_term* t = &cpu->term[j];
        for (int a = 0; a < t->cnt; ++a) {
            same_p &= ip[4 * j + a] == t->p[a];
            en = fmax(en, fabs(fw[4 * j + a] - t->w[a]));
        }
        for (int c = 0; c < 3; ++c) en = fmax(en, fabs(fnc[4 * j + c] - t->n[c]));
        same_active &= (fnc[4 * j + 3] > 0.0f) == (t->c > 0.0);
        if (t->c > 0.0) ec = fmax(ec, fabs(fnc[4 * j + 3] - t->c) / t->c);
        active += t->c > 0.0;
    }
    printf("  %s: %d pairs (core %d), %d active; weights and normals within %.2g, c within %.2g (relative)\n", when,
           n, cpu->n, active, en, ec);
    CHECK(same_p);
    CHECK(same_active);
    CHECK(en < 1e-6);
    CHECK(ec < 1e-6);
    return active;
}

/* x random in [-1, 1] (the state's filter free everywhere: a product's input) */
static void random_vec(double* x, int n3, unsigned seed) {
    for (int k = 0; k < n3; ++k) {
        seed = seed * 1103515245u + 12345u;
        x[k] = ((seed >> 8) & 0xffff) / 32768.0 - 1.0;
    }
}

/* The layers on both sides: core's state sc and the GPU's sg (its cloth g) at the same
 * float-rounded positions and velocities, with newton_iterations and the line search as given;
 * core's first system prepared on sc (its statistics in st), the GPU's on g (A and b read back).
 * 0 when something could not be made. */
typedef struct fixture {
    wc_model m;
    wc_state *sc, *sg;
    wg_sim* g;
    wc_step_stats st;
    int n, nb;
    size_t n3;
    double *A, *b;              /* the GPU's first system read back */
} fixture;

static int setup(fixture* fx, int newton, int search) {
    memset(fx, 0, sizeof *fx);
    CHECK(two_layers(&fx->m, LN, SIZE, 0.0, 0.0025));
    wc_sim_def sd = wc_default_sim_def();
    sd.solver.type = WC_SOLVER_PCG;
    sd.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    sd.threads = 1;
    sd.newton_iterations = newton;
    sd.line_search = search;
    sd.self_collision = 1;
    sd.self_in_solve = 1;
    fx->sc = two_layers_approaching(&fx->m, LN, SIZE, 0.5, &sd);
    fx->sg = two_layers_approaching(&fx->m, LN, SIZE, 0.5, &sd);
    CHECK(fx->sc && fx->sg && fx->sc->self_pairs && fx->sg->self_pairs);
    if (!fx->sc || !fx->sg) return 0;
    fx->n = fx->m.n_particles;
    fx->nb = fx->m.pattern.n_blocks;
    fx->n3 = 3 * (size_t)fx->n;
    round_to_float(fx->sc->x, fx->n3);
    round_to_float(fx->sc->v, fx->n3);
    memcpy(fx->sg->x, fx->sc->x, fx->n3 * sizeof(double));
    memcpy(fx->sg->v, fx->sc->v, fx->n3 * sizeof(double));
    wc_diag d = {0};
    CHECK_EQ_INT(wg_sim_create(dev, fx->sg, NULL, &fx->g, &d), WC_OK);
    if (!fx->g) {
        printf("  wg_sim_create: %s\n", d.message);
        return 0;
    }
    CHECK(fx->g->pairs != NULL);
    wg_sim_upload(fx->g, fx->sg, &d);
    /* core's first system; the GPU's from the same positions (the stage's start as both take it) */
    wc_self_begin(fx->sc->self, fx->sc->x);
    wc_self_begin(fx->sg->self, fx->sg->x);
    wc_substep_prepare(fx->sc, H, 1.0, &fx->st);
    fx->A = malloc(9 * (size_t)fx->nb * sizeof(double));
    fx->b = malloc(fx->n3 * sizeof(double));
    CHECK_EQ_INT(wg_sim_debug_prepare(fx->g, fx->sg, H, 1.0, fx->A, fx->b, NULL, NULL, NULL, NULL, &d), WC_OK);
    return 1;
}

static void teardown(fixture* fx) {
    free(fx->A);
    free(fx->b);
    wg_sim_destroy(fx->g);
    wc_state_destroy(fx->sc);
    wc_state_destroy(fx->sg);
    wc_model_free(&fx->m);
}

static void test_first_system(void) {
    fixture fx;
    if (!setup(&fx, 1, 0)) {
        teardown(&fx);
        return;
    }
    const wc_model* m = &fx.m;
    wc_state *sc = fx.sc, *sg = fx.sg;
    wg_sim* g = fx.g;
    const wc_step_stats st = fx.st;
    const int n = fx.n, nb = fx.nb;
    const size_t n3 = fx.n3;
    const double *A = fx.A, *b = fx.b;
    wc_diag d = {0};
    const wc_penalty_pairs* lc = &sc->self_pairs->list;
    int active = compare_lists(lc, g->pairs, "first system");
    CHECK(active >= 10);
    CHECK_EQ_INT(wg_pairs_counts(g->pairs)->self, st.self_pairs);
    CHECK_EQ_INT(wg_pairs_counts(g->pairs)->self_active, st.self_pairs_active);
    /* the pairs' share of A's diagonal: what they add, against the error */
    double pair_diag = 0.0;
    for (int j = 0; j < lc->n; ++j)
        if (lc->term[j].c > 0.0) pair_diag = fmax(pair_diag, lc->term[j].c * lc->term[j].w[0] * lc->term[j].w[0]);
    double eA = rel_err(A, sc->A, 9 * (size_t)nb), eb = rel_err(b, sc->b, n3);
    printf("  A within %.2g, b within %.2g of core's (relative; the pairs' largest diagonal term %.3g kg)\n", eA, eb,
           pair_diag);
    CHECK(eA < 1e-6);
    CHECK(eb < 1e-5);
    CHECK(pair_diag > 1e-3);

    /* the off-diagonal blocks: the GPU's A x less the pattern's part of it, against core's */
    double* x = malloc(n3 * sizeof(double));
    double* y = malloc(n3 * sizeof(double));
    double* yp = malloc(n3 * sizeof(double));
    double* yc = calloc(n3, sizeof(double));
    random_vec(x, (int)n3, 7u);
    round_to_float(x, n3);
    CHECK_EQ_INT(wg_sim_debug_spmv(g, x, y, &d), WC_OK);
    wc_par par;
    wc_par_init(&par, 1);
    wc_bsr_mul(&m->pattern, A, x, yp, &par);
    for (size_t k = 0; k < n3; ++k) y[k] -= yp[k];
    wc_coupling_mul_offdiag_add(&sc->self_pairs->coupling, 1.0, x, yc);
    double eo = rel_err(y, yc, n3), so = 0.0;
    for (size_t k = 0; k < n3; ++k) so = fmax(so, fabs(yc[k]));
    printf("  off-diagonal product within %.2g of wc_coupling_mul_offdiag_add (relative; largest %.3g)\n", eo, so);
    CHECK(so > 1e-3);
    CHECK(eo < 1e-4);   /* a difference of two float products of A's size */

    /* a solve on each side (the two within the solvers' tolerance), then the recheck of core's
       solution, rounded to float, on each side */
    wc_solve_result res;
    memset(sc->dv, 0, n3 * sizeof(double));
    CHECK_EQ_INT(wc_solve(sc->solver, WC_SOLVER_PCG, sc->A, sc->b, &sc->filter, sc->dv, &sc->par, &res), WC_OK);
    const wg_tex* out = NULL;
    wc_solver_opts o = sg->def.solver;
    CHECK_EQ_INT(wg_solve(g, &o, WC_SOLVER_PCG, wg_ring_cur(&g->dv), &out, &res), WC_OK);
    /* the GPU's dv in core's system (A with its couplings, the filter free): |A dv - b| / |b| */
    wg_array_read(&g->layout, out, n, g->rb);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) x[3 * i + c] = g->rb[4 * i + c];
    wc_state_mul_system(sc, x, y);
    double rr = 0.0, bb = 0.0;
    for (size_t k = 0; k < n3; ++k) {
        rr += (y[k] - sc->b[k]) * (y[k] - sc->b[k]);
        bb += sc->b[k] * sc->b[k];
    }
    printf("  the GPU's solution in core's system: relative residual %.2g\n", sqrt(rr / bb));
    CHECK(sqrt(rr / bb) < 1e-3);
    round_to_float(sc->dv, n3);
    for (int i = 0; i < n; ++i)
        for (int c = 0; c < 4; ++c) g->rb[4 * i + c] = c < 3 ? (float)sc->dv[3 * i + c] : 0.0f;
    const wg_tex* dv_in = &g->dv.t[wg_ring_other(&g->dv, 0)];
    wg_array_upload(&g->layout, dv_in, n, g->rb);
    wc_integ ig;
    wc_integ_coefficients(sg, H, 1, &ig);
    int sw_c = wc_penalty_pairs_recheck(&sc->self_pairs->list, m, sc->x, sc->v, sc->dv, H, sc->A, sc->b);
    int sw_g = wg_pairs_recheck(g->pairs, sg, 1, &ig, dv_in);
    int apart = 0;
    for (int j = 0; j < lc->n; ++j) apart += lc->active[j] != sg->self_pairs->list.active[j];
    printf("  recheck: %d pairs switched on the GPU, %d by core, active sets %d apart\n", sw_g, sw_c, apart);
    CHECK(sw_c > 0);
    CHECK_EQ_INT(sw_g, sw_c);
    CHECK_EQ_INT(apart, 0);
    compare_lists(lc, g->pairs, "after the recheck");
    double* A2 = malloc(9 * (size_t)nb * sizeof(double));
    double* b2 = malloc(n3 * sizeof(double));
    CHECK_EQ_INT(wg_sim_debug_read_system(g, A2, b2, &d), WC_OK);
    eA = rel_err(A2, sc->A, 9 * (size_t)nb);
    eb = rel_err(b2, sc->b, n3);
    printf("  after the recheck: A within %.2g, b within %.2g of core's\n", eA, eb);
    CHECK(eA < 1e-6);
    CHECK(eb < 1e-5);

    free(A2);
    free(b2);
    free(x);
    free(y);
    free(yp);
    free(yc);
    teardown(&fx);
}

/* n x 3 doubles into the texture t (rounded to float) */
static void upload3(wg_sim* g, const wg_tex* t, const double* a) {
    for (int i = 0; i < g->n; ++i)
        for (int c = 0; c < 4; ++c) g->rb[4 * i + c] = c < 3 ? (float)a[3 * i + c] : 0.0f;
    wg_array_upload(&g->layout, t, g->n, g->rb);
}

/* Newton (sim def newton_iterations 2): at an iterate w (core's first solution, rounded to float),
 * the pairs' exact terms the GPU adds to its system on its own passes (A and b after
 * wg_pairs_newton less before, and its active set read back) against core's
 * wc_penalty_pairs_newton at the same x(w) = x + h (v + w) in double, and the pairs' part of the
 * potential's change from w = 0 to w (pairs_energy.glsl, reduced) against core's
 * wc_penalty_pairs_energy; neither reads anything back for the pairs. */
static void test_newton(void) {
    fixture fx;
    if (!setup(&fx, 2, 1)) {
        teardown(&fx);
        return;
    }
    const wc_model* m = &fx.m;
    wc_state *sc = fx.sc, *sg = fx.sg;
    wg_sim* g = fx.g;
    const int nb = fx.nb;
    const size_t n3 = fx.n3;
    wc_diag d = {0};
    wc_solve_result res;
    memset(sc->dv, 0, n3 * sizeof(double));
    CHECK_EQ_INT(wc_solve(sc->solver, WC_SOLVER_PCG, sc->A, sc->b, &sc->filter, sc->dv, &sc->par, &res), WC_OK);
    round_to_float(sc->dv, n3);
    double* xw = malloc(n3 * sizeof(double));
    double* x0 = malloc(n3 * sizeof(double));
    for (size_t k = 0; k < n3; ++k) {
        x0[k] = sc->x[k] + H * sc->v[k];
        xw[k] = sc->x[k] + H * (sc->v[k] + sc->dv[k]);
    }
    /* core's terms alone, on zeroed scratch */
    double* Ac = calloc(9 * (size_t)nb, sizeof(double));
    double* bc = calloc(n3, sizeof(double));
    wc_penalty_pairs* lc = &sc->self_pairs->list;
    int touching = wc_penalty_pairs_newton(lc, m, xw, H, Ac, bc);
    /* the GPU's: its system before and after */
    double* A0 = malloc(9 * (size_t)nb * sizeof(double));
    double* b0 = malloc(n3 * sizeof(double));
    double* A1 = malloc(9 * (size_t)nb * sizeof(double));
    double* b1 = malloc(n3 * sizeof(double));
    CHECK_EQ_INT(wg_sim_debug_read_system(g, A0, b0, &d), WC_OK);
    const wg_tex* wt = &g->nw_w[1];
    upload3(g, wt, sc->dv);
    wc_integ ig;
    wc_integ_coefficients(sg, H, 1, &ig);
    const long long read0 = wg_pairs_transfers(g->pairs)->read_bytes;
    wg_pairs_newton(g->pairs, &ig, wt);
    /* the pairs' part of the potential's change from w = 0 to w, on zeros as the other terms */
    const wg_tex* parts = wg_pairs_energy_change(g->pairs, &ig, &g->nw_zero, wt, &g->nw_zero);
    float e4[4];
    wg_read1(&g->layout, wg_reduce(&g->run, &g->red_p[0], parts, 0, 0, 0, 0), e4);
    const long long read1 = wg_pairs_transfers(g->pairs)->read_bytes;
    CHECK_EQ_INT(wg_sim_debug_read_system(g, A1, b1, &d), WC_OK);
    for (size_t k = 0; k < 9 * (size_t)nb; ++k) A1[k] -= A0[k];
    for (size_t k = 0; k < n3; ++k) b1[k] -= b0[k];
    /* core's in-pattern list would put cross blocks into A; this one is coupled: diagonal only */
    double eA = rel_err(A1, Ac, 9 * (size_t)nb), eb = rel_err(b1, bc, n3);
    const int active = wg_pairs_debug_active(g->pairs);
    printf("  Newton's system at an iterate: %d pairs touching, %d on the GPU; their terms in A within %.2g, in b "
           "within %.2g of core's (relative); the pairs read back %lld bytes\n", touching, active, eA, eb,
           read1 - read0);
    CHECK(touching > 0);
    CHECK_EQ_INT(active, touching);
    CHECK(eA < 1e-5);   /* a difference of two float systems */
    CHECK(eb < 1e-4);
    CHECK(read1 == read0);
    compare_lists(lc, g->pairs, "Newton's system");
    const double ec = wc_penalty_pairs_energy(lc, xw) - wc_penalty_pairs_energy(lc, x0);
    const double eg = (double)e4[0];
    printf("  the pairs' energy change: GPU %.9g J, core %.9g J (%.2g relative)\n", eg, ec, fabs(eg - ec) / fabs(ec));
    CHECK(ec != 0.0);
    CHECK(fabs(eg - ec) <= 1e-6 * fabs(ec));
    /* and from w to a step 2^-10 longer, as a late backtrack compares: a change a thousandth of
       the energies, which the pass keeps to float's digits of the change itself */
    double* w2 = malloc(n3 * sizeof(double));
    double* x2 = malloc(n3 * sizeof(double));
    for (size_t k = 0; k < n3; ++k) {
        w2[k] = (double)(float)(sc->dv[k] * (1.0 + ldexp(1.0, -10)));
        x2[k] = sc->x[k] + H * (sc->v[k] + w2[k]);
    }
    upload3(g, &g->nw_w[2], w2);
    parts = wg_pairs_energy_change(g->pairs, &ig, wt, &g->nw_w[2], &g->nw_zero);
    wg_read1(&g->layout, wg_reduce(&g->run, &g->red_p[0], parts, 0, 0, 0, 0), e4);
    const double ec2 = wc_penalty_pairs_energy(lc, x2) - wc_penalty_pairs_energy(lc, xw), eg2 = (double)e4[0];
    printf("  and to a step 2^-10 longer: GPU %.9g J, core %.9g J (%.2g relative)\n", eg2, ec2,
           fabs(eg2 - ec2) / fabs(ec2));
    CHECK(ec2 != 0.0);
    CHECK(fabs(eg2 - ec2) <= 1e-5 * fabs(ec2));
    free(w2);
    free(x2);
    free(xw);
    free(x0);
    free(Ac);
    free(bc);
    free(A0);
    free(b0);
    free(A1);
    free(b1);
    teardown(&fx);
}

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    RUN_TEST(test_first_system);
    RUN_TEST(test_newton);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
