/* The finest level's Gauss-Seidel smoother (core/amg_smooth.c) on a real coupled system: two
 * 21 x 21 layers, the top one falling onto the bottom one, with the substep's self-contact
 * couplings (the dance's case: level 0 holds coupling terms, so the default smooths it so);
 * pins and a plane row in the bottom layer, so the filter acts. Checked:
 *   - the smoother is on there, and off (Chebyshev) on the same model without couplings;
 *   - the V-cycle stays symmetric positive definite (<u, M v> = <M u, v> to rounding): the
 *     backward sweep after the coarse correction is the forward one's adjoint;
 *   - one forward + backward sweep (2 products) contracts the error of F x = 0 in the F-norm on
 *     random and smooth vectors, and more than a degree-2 Chebyshev step on D^-1 F (2 products,
 *     the level's default smoother, computed here from its definition);
 *   - PCG to 1e-8 reaches the Chebyshev V-cycle's answer, with fewer fine-level products;
 *   - the V-cycle is the same to the bit on 1, 2 and 3 threads. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "amg_scene.h"
#include "check.h"
#include "test_support.h"
#include "coupling.h"
#include "self_pairs.h"
#include "solve_kernels.h"
#include "step.h"
#include "two_layers.h"

enum { N = 21 };
static const double SIZE = 0.6, GAP = 0.004, TH = 0.003;

static void random_vec(double* v, int n3, uint64_t* st) {
    for (int k = 0; k < n3; ++k) {
        *st = *st * 6364136223846793005ull + 1442695040888963407ull;
        v[k] = (double)(*st >> 11) / 9007199254740992.0 - 0.5;
    }
}

/* The substep's system of the falling layer, with two pins and a row on a plane y = 0 in the
 * bottom layer (as test_amg_cross.c). */
static wc_state* coupled_layers(wc_model* m) {
    CHECK(two_layers(m, N, SIZE, 0.0, GAP));
    wc_sim_def def = wc_default_sim_def();
    def.self_collision = 1;
    def.self_thickness = TH;
    def.self_in_solve = 1;
    def.sleep_speed = 0;
    def.solver.preconditioner = WC_PRECOND_AMG;
    def.solver.tolerance = 1e-8;
    def.solver.max_iterations = 2000;
    wc_state* s = two_layers_approaching(m, N, SIZE, 0.3, &def);
    CHECK(s != NULL);
    if (!s) return NULL;
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(s, 1.0 / 60, 1.0, &st);
    wc_filter* f = &s->filter;
    for (int hv = 0; hv < N; ++hv) {
        int p = m->host_to_particle[N * (N / 2) + hv];
        double* S = f->S + 9 * p;
        for (int q = 0; q < 9; ++q) S[q] = q % 4 == 0 ? 1.0 : 0.0;
        S[4] = 0.0;
        f->ndof[p] = 1;
    }
    for (int c = 0; c < 2; ++c) {
        int p = m->host_to_particle[c ? N * N - 1 : 0];
        memset(f->S + 9 * p, 0, 9 * sizeof(double));
        f->ndof[p] = 3;
    }
    return s;
}

/* A hierarchy of s's model, with the couplings or without, set up on s's system. */
static wc_amg* hierarchy(wc_state* s, int fine_gs, int couplings, wc_par* par) {
    wc_amg_opts o = wc_default_amg_opts();
    o.fine_gs = fine_gs;
    o.single = 0; /* the double operator, so that F below is the smoother's to the bit */
    wc_amg* a = NULL;
    wc_diag d = {0};
    CHECK(wc_amg_create(&a, s->model, &o, NULL, &d) == WC_OK);
    if (!a) return NULL;
    if (couplings) CHECK(wc_amg_set_coupling(a, &s->self_pairs->coupling, s->self_pairs->list.cap, &d) == WC_OK);
    a->pos = s->x;
    wc_amg_setup(a, s->A, &s->filter, par);
    return a;
}

/* y = F x on level 0: the BSR part and the couplings, serially. */
static void fine_mul(const wc_amg_level* L, const double* x, double* y) {
    wc_par par;
    wc_par_init(&par, 1);
    memset(y, 0, 3 * (size_t)L->n * sizeof(double));
    for (int i = 0; i < L->n; ++i)
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            m3_mulv_add(y + 3 * i, L->val + 9 * (size_t)k, x + 3 * L->col[k]);
    if (L->cross && L->cross->n_terms > 0) wc_amg_cross_mul_add(L->cross, 1.0, x, y, L->n, &par);
}

static double fnorm(const wc_amg_level* L, const double* x, double* tmp) {
    fine_mul(L, x, tmp);
    double s = 0;
    for (int k = 0; k < 3 * L->n; ++k) s += x[k] * tmp[k];
    return sqrt(s);
}

/* x <- the degree-2 Chebyshev step on D^-1 F over [bound / 10, bound] for F x = 0. */
static void chebyshev2(const wc_amg_level* L, double* x, double* t, double* d) {
    const double b = L->bound, a = b / 10.0, theta = 0.5 * (b + a), delta = 0.5 * (b - a), sigma = theta / delta;
    const int n3 = 3 * L->n;
    double rho = 1.0 / sigma;
    fine_mul(L, x, t);
    for (int i = 0; i < L->n; ++i) {
        double e[3], mt[3] = {-t[3 * i], -t[3 * i + 1], -t[3 * i + 2]};
        m3_mulv(e, L->Dinv + 9 * (size_t)i, mt);
        v3_scale(d + 3 * i, e, 1.0 / theta);
    }
    for (int k = 0; k < n3; ++k) x[k] += d[k];
    fine_mul(L, x, t);
    double rn = 1.0 / (2.0 * sigma - rho), c1 = rn * rho, c2 = 2.0 * rn / delta;
    for (int i = 0; i < L->n; ++i) {
        double e[3], mt[3] = {-t[3 * i], -t[3 * i + 1], -t[3 * i + 2]};
        m3_mulv(e, L->Dinv + 9 * (size_t)i, mt);
        for (int c = 0; c < 3; ++c) {
            d[3 * i + c] = c1 * d[3 * i + c] + c2 * e[c];
            x[3 * i + c] += d[3 * i + c];
        }
    }
}

static void test_spd_and_contraction(void) {
    wc_model m;
    wc_state* s = coupled_layers(&m);
    if (!s) return;
    wc_par par;
    wc_par_init(&par, 1);
    const int n = m.n_particles, n3 = 3 * n;
    wc_amg* plain = hierarchy(s, 1, 0, &par);
    wc_amg* a = hierarchy(s, 1, 1, &par);
    if (!a || !plain) return;
    printf("  %d particles, %d active couplings, %d levels\n", n, a->lev[0].cross->n_terms, a->n_levels);
    CHECK(a->lev[0].cross->n_terms > 100);
    CHECK(wc_amg_gs_on(a, 0));
    CHECK(!wc_amg_gs_on(plain, 0));
    CHECK(a->lev[0].cross->n_entries >= WC_AMG_GS_ENTRIES * n);
    CHECK(!wc_amg_gs_on(a, 1));
    amg_check_spd(a, s, "Gauss-Seidel on level 0");

    wc_amg_level* L = &a->lev[0];
    double *zero = calloc(n3, sizeof(double)), *x = malloc(n3 * sizeof(double)), *y = malloc(n3 * sizeof(double)),
           *t = malloc(n3 * sizeof(double)), *d = malloc(n3 * sizeof(double)), *e0 = malloc(n3 * sizeof(double));
    uint64_t st = 31337;
    double worst_gs = 0, worst_cheb = 0;
    for (int trial = 0; trial < 4; ++trial) {
        random_vec(e0, n3, &st);
        if (trial % 2)
            for (int i = 0; i < n; ++i)
                for (int c = 0; c < 3; ++c) e0[3 * i + c] = sin(9.0 * m.rest_pos[3 * i + 2] + c) + 0.2 * e0[3 * i + c];
        for (int i = 0; i < n; ++i) wc_filter_apply(&s->filter, i, e0 + 3 * i, e0 + 3 * i);
        const double n0 = fnorm(L, e0, t);
        memcpy(x, e0, n3 * sizeof(double));
        wc_amg_gs_part(L, 0, zero, x, 0, 0); /* one thread, outside a region: its barriers bind to none */
        wc_amg_gs_part(L, 0, zero, x, 0, 1);
        const double ngs = fnorm(L, x, t) / n0;
        memcpy(y, e0, n3 * sizeof(double));
        chebyshev2(L, y, t, d);
        const double nch = fnorm(L, y, t) / n0;
        printf("  %s error, F-norm after 2 products: Gauss-Seidel forward + backward %.3f, Chebyshev degree 2 %.3f\n",
               trial % 2 ? "smooth" : "random", ngs, nch);
        CHECK(ngs < 1.0);
        CHECK(ngs < nch);
        if (ngs > worst_gs) worst_gs = ngs;
        if (nch > worst_cheb) worst_cheb = nch;
    }
    free(zero);
    free(x);
    free(y);
    free(t);
    free(d);
    free(e0);
    wc_amg_destroy(a);
    wc_amg_destroy(plain);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* PCG to 1e-8 on the system with the solver's hierarchy: Gauss-Seidel on level 0 (the default)
 * against Chebyshev; the same answer. */
static int solve(wc_state* s, double* dv) {
    memset(dv, 0, 3 * (size_t)s->model->n_particles * sizeof(double));
    wc_solve_result res;
    CHECK_EQ_INT(wc_solve(s->solver, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res), WC_OK);
    CHECK(res.converged);
    return res.iterations;
}

static void test_pcg(void) {
    wc_model m;
    wc_state* s = coupled_layers(&m);
    if (!s) return;
    const int n3 = 3 * m.n_particles;
    wc_amg* a = s->solver->amg;
    CHECK(a != NULL);
    if (!a) return;
    double *gs = malloc(n3 * sizeof(double)), *ch = malloc(n3 * sizeof(double));
    CHECK(a->opts.fine_gs == 1);
    int it_gs = solve(s, gs);
    CHECK(wc_amg_gs_on(a, 0));
    a->opts.fine_gs = 0;
    int it_ch = solve(s, ch);
    CHECK(!wc_amg_gs_on(a, 0));
    a->opts.fine_gs = 1;
    double diff = ts_rel_diff(gs, ch, n3);
    printf("  PCG to 1e-8: %d iterations with Gauss-Seidel on level 0, %d with Chebyshev; answers differ by %.1e\n",
           it_gs, it_ch, diff);
    /* a V-cycle's fine products: Gauss-Seidel about 2.5 (half a sweep from zero, the residual,
       a sweep), Chebyshev 4 (1 + 1 + 2): fewer a solve */
    CHECK(5 * it_gs < 8 * it_ch);
    CHECK(diff < 1e-5);
    free(gs);
    free(ch);
    wc_state_destroy(s);
    wc_model_free(&m);
}

static void test_threads(void) {
    wc_model m;
    wc_state* s = coupled_layers(&m);
    if (!s) return;
    const int n3 = 3 * m.n_particles;
    double *r = malloc(n3 * sizeof(double)), *z[3];
    uint64_t st = 99;
    random_vec(r, n3, &st);
    wc_amg* a = s->solver->amg;
    CHECK(a != NULL);
    if (!a) return;
    for (int t = 1; t <= 3; ++t) {
        wc_par par;
        wc_par_init(&par, t);
        wc_amg_setup(a, s->A, &s->filter, &par);
        CHECK(wc_amg_gs_on(a, 0));
        z[t - 1] = malloc(n3 * sizeof(double));
        wc_amg_apply(a, r, z[t - 1], &par);
    }
    int same = memcmp(z[0], z[1], n3 * sizeof(double)) == 0 && memcmp(z[0], z[2], n3 * sizeof(double)) == 0;
    CHECK(same);
    printf("  V-cycle with Gauss-Seidel on level 0 on 1, 2 and 3 threads: %s\n", same ? "bit-identical" : "differ");
    free(r);
    for (int t = 0; t < 3; ++t) free(z[t]);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_spd_and_contraction);
    RUN_TEST(test_pcg);
    RUN_TEST(test_threads);
    return TEST_SUMMARY();
}
