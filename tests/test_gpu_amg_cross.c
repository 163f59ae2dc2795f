/* The self-contact pairs' cross terms in the GPU's multigrid (gpu/solver/wg_amg.h, "cross terms")
 * against core's (core/amg_cross.c) on the same float input: two 21 x 21 layers, the top one
 * falling onto the bottom one (tests/test_amg_cross.c's system: two pins and a row on a plane in
 * the bottom layer, so the filter acts), the GPU's pairs found and assembled by its own prepare
 * and its A, b and filter replaced by core's. Core's hierarchy is the GPU's method
 * (wg_amg_opts_for(0): unsmoothed aggregation, power iterations; the cross terms reach the coarse
 * levels with P = P_tent only) with its couplings (couplings 1).
 * Checked:
 *   - one V-cycle on a filtered random vector: the GPU's output is core's to float precision
 *     (within 2x of the two sides' difference with no terms on either: float's power iterations
 *     and factor against double's), and with the terms left out of the GPU's levels
 *     (cross_skip, the mutation) over 100x further;
 *   - each coarse level's operator (its blocks and the cross blocks of amg_cross_blocks, read
 *     back) times a random vector: core's F_l x to float precision; without the cross blocks
 *     over 100x further;
 *   - the levels' rule (wg_amg.cross_share): the layers take the terms on every level; shares
 *     above theirs leave every level out (the V-cycle cross_skip's to the bit), the finest
 *     level's share alone at 0 takes them there only (nearer core's than without, not as near);
 *   - PCG with the multigrid, same tolerance: the GPU's iterations within 2 of core's and its
 *     answer solving core's system (couplings included); without the terms, over twice as many;
 *     with the GPU's default finest bound factor (WG_AMG_CROSS_BOUND), under half of those too. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "amg.h"
#include "bsr_rows.h"
#include "check.h"
#include "coupling.h"
#include "egl_context.h"
#include "self_pairs.h"
#include "solve.h"
#include "solve_kernels.h"
#include "state.h"
#include "step.h"
#include "test_support.h"
#include "amg_coupled.h"
#include "gpu_group_support.h"
#include "two_layers.h"
#include "wg_amg.h"
#include "wg_sim_impl.h"

#define N 21
#define SIZE 0.6
#define GAP 0.004
#define TH 0.003
#define H (1.0 / 60.0)

static wg_gl_context* gl;
static wg_device* dev;

static void round_to_float(double* a, size_t count) {
    for (size_t k = 0; k < count; ++k) a[k] = (float)a[k];
}

static wc_state* layers(const wc_model* m, const wc_sim_def* def) {
    wc_state* s = two_layers_approaching(m, N, SIZE, 0.3, def);
    CHECK(s != NULL);
    if (!s) return NULL;
    round_to_float(s->x, 3 * (size_t)m->n_particles);
    round_to_float(s->v, 3 * (size_t)m->n_particles);
    return s;
}

/* one GPU V-cycle on r (n x 3) into z, after a setup (its terms left out with skip) */
static void gpu_vcycle(wg_sim* g, const double* r, double* z, int skip) {
    g->amg->cross_skip = skip;
    wg_amg_setup(g->amg);
    tg_vcycle(g, r, z);
    g->amg->cross_skip = 0;
}

/* Each coarse level's operator as the GPU holds it after a setup (its Galerkin blocks and the
 * cross blocks amg_cross_blocks sums per pair of nodes, read back, wg_amg_cross.c's lists) times a
 * random vector, against core's F_l x on the same input (the level's Galerkin operator plus its
 * couplings, amg_cross.c). The mutation: the same product without the cross blocks. */
static void check_coarse_levels(wg_sim* g, const wc_amg* ca, wc_par* par) {
    wg_amg* a = g->amg;
    a->cross_skip = 0;
    wg_amg_setup(a);
    CHECK(ca->cross_dropped == 0);
    for (int l = 1; l < a->n_levels; ++l) {
        const wg_amg_level* G = &a->lev[l];
        const wc_amg_level* C = &ca->lev[l];
        CHECK_EQ_INT(G->n, C->n);
        CHECK_EQ_INT(G->nb, C->n_blocks);
        int items = 0;
        const int* v = wg_amg_debug_cross_lists(a, l, &items);
        CHECK(v != NULL && G->cross_nb > 0);
        if (!v || G->n != C->n || G->nb != C->n_blocks) continue;
        const int n = G->n;
        float* blk[3];
        for (int c = 0; c < 3; ++c) {
            blk[c] = malloc(4 * (size_t)G->nb * sizeof(float));
            wg_array_read(&g->layout, &G->a[c], G->nb, blk[c]);
        }
        float* cb = malloc(12 * (size_t)G->cross_nb * sizeof(float));   /* block b's row r: 4 (3 b + r) */
        wg_array_read(&g->layout, &G->cross_a, 3 * G->cross_nb, cb);
        double *x = malloc(3 * (size_t)n * sizeof(double)), *yc = calloc(3 * (size_t)n, sizeof(double)),
               *yg = calloc(3 * (size_t)n, sizeof(double)), *yo = malloc(3 * (size_t)n * sizeof(double));
        unsigned seed = 7u + (unsigned)l;
        for (int k = 0; k < 3 * n; ++k) {
            seed = seed * 1103515245u + 12345u;
            x[k] = ((seed >> 8) & 0xffff) / 32768.0 - 1.0;
        }
        /* the GPU's: its own blocks (core's pattern: the same aggregates), then its cross blocks */
        int most = 0;
        for (int i = 0; i < n; ++i)
            for (int k = C->row_start[i]; k < C->row_start[i + 1]; ++k)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) yg[3 * i + r] += blk[r][4 * k + c] * x[3 * C->col[k] + c];
        memcpy(yo, yg, 3 * (size_t)n * sizeof(double));
        for (int i = 0; i < n; ++i) {
            if (v[4 * i + 1] - v[4 * i] > most) most = v[4 * i + 1] - v[4 * i];
            for (int h = v[4 * i]; h < v[4 * i + 1]; ++h)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) yg[3 * i + r] += cb[4 * (3 * (h - n) + r) + c] * x[3 * v[4 * h] + c];
        }
        /* core's */
        wc_bsr_rows(C->row_start, C->col, C->val, 0, n, NULL, 1.0, x, yc);
        wc_amg_cross_mul_add(C->cross, 1.0, x, yc, n, par);
        const double e = ts_rel_diff(yg, yc, 3 * n), eo = ts_rel_diff(yo, yc, 3 * n);
        printf("  level %d (%d nodes): %d cross blocks (%d a node at most); F x against core's %.1e (without the "
               "cross blocks %.1e)\n", l, n, G->cross_nb, most, e, eo);
        CHECK(items > n + G->cross_nb);
        CHECK(e < 1e-5);
        CHECK(eo > 100.0 * e);
        for (int c = 0; c < 3; ++c) free(blk[c]);
        free(cb), free(x), free(yc), free(yg), free(yo);
    }
}

static void test_cross_terms(void) {
    wc_model m;
    CHECK(two_layers(&m, N, SIZE, 0.0, GAP));
    wc_sim_def def = wc_default_sim_def();
    def.self_collision = 1;
    def.self_thickness = TH;
    def.self_in_solve = 1;
    def.sleep_speed = 0;
    def.threads = 1;
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_AMG;
    def.solver.tolerance = 1e-4;
    def.solver.max_iterations = 2000;
    wc_state* sc = layers(&m, &def);
    wc_state* sg = layers(&m, &def);
    if (!sc || !sg) return;
    const int n = m.n_particles;
    const size_t n3 = 3 * (size_t)n;
    wc_diag d = {0};
    wg_sim* g = NULL;
    CHECK_EQ_INT(wg_sim_create(dev, sg, NULL, &g, &d), WC_OK);
    if (!g) {
        printf("  wg_sim_create: %s\n", d.message);
        return;
    }
    CHECK(g->pairs != NULL && g->amg != NULL);
    if (!g->amg) return;
    g->amg->cross_bound_scale = 1.0;   /* core's power method has no such factor (wg_amg.h) */
    g->amg->warm_steps = 0;   /* nor warm steps: every setup from core's start vector, as core's */
    /* core's system and the GPU's (its pairs found and assembled by its own prepare) */
    wc_self_begin(sc->self, sc->x);
    wc_self_begin(sg->self, sg->x);
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(sc, H, 1.0, &st);
    amg_coupled_constrain(&m, N, &sc->filter);
    CHECK_EQ_INT(wg_sim_debug_prepare(g, sg, H, 1.0, NULL, NULL, NULL, NULL, NULL, NULL, &d), WC_OK);
    CHECK_EQ_INT(wg_sim_debug_set_system(g, sc->A, sc->b, &sc->filter, &d), WC_OK);
    const int active = wc_coupling_active(&sc->self_pairs->coupling);
    CHECK_EQ_INT(wg_pairs_counts(g->pairs)->self_active, active);
    CHECK(g->amg->cross_n > 0);

    /* core's hierarchy: the GPU's method with the couplings */
    wc_par par;
    wc_par_init(&par, 1);
    wc_amg_opts ao = wg_amg_opts_for(0);
    ao.values = 1;
    ao.couplings = 1;
    wc_amg* ca = NULL;
    CHECK_EQ_INT(wc_amg_create(&ca, &m, &ao, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_amg_set_coupling(ca, &sc->self_pairs->coupling, sc->self_pairs->list.cap, &d), WC_OK);
    wc_amg_setup(ca, sc->A, &sc->filter, &par);
    CHECK_EQ_INT(ca->n_levels, g->amg->n_levels);
    CHECK(ca->n_levels >= 3);
    CHECK_EQ_INT(ca->cross_terms[0], active);

    /* one V-cycle on a filtered random vector */
    double *r = malloc(n3 * sizeof(double)), *zc = calloc(n3, sizeof(double)), *zg = calloc(n3, sizeof(double)),
           *zs = calloc(n3, sizeof(double));
    unsigned seed = 99u;
    for (size_t k = 0; k < n3; ++k) {
        seed = seed * 1103515245u + 12345u;
        r[k] = ((seed >> 8) & 0xffff) / 32768.0 - 1.0;
    }
    for (int i = 0; i < n; ++i) wc_filter_apply(&sc->filter, i, r + 3 * i, r + 3 * i);
    round_to_float(r, n3);
    wc_amg_apply(ca, r, zc, &par);
    gpu_vcycle(g, r, zg, 0);
    gpu_vcycle(g, r, zs, 1);
    const double e = ts_rel_diff(zg, zc, (int)n3), es = ts_rel_diff(zs, zc, (int)n3);
    /* the float floor: both sides without any terms (core's hierarchy with couplings 0) */
    wc_amg_opts a0 = ao;
    a0.couplings = 0;
    wc_amg* c0 = NULL;
    CHECK_EQ_INT(wc_amg_create(&c0, &m, &a0, NULL, &d), WC_OK);
    wc_amg_setup(c0, sc->A, &sc->filter, &par);
    double* z0 = calloc(n3, sizeof(double));
    wc_amg_apply(c0, r, z0, &par);
    const double e0 = ts_rel_diff(zs, z0, (int)n3);
    free(z0);
    wc_amg_destroy(c0);
    printf("  %d particles, %d levels, %d active pairs: one V-cycle, GPU against core %.1e (the terms left "
           "out of the GPU's levels: %.1e; neither side with them: %.1e, float's floor)\n",
           n, ca->n_levels, active, e, es, e0);
    CHECK(active > 100);
    CHECK(e < 2.0 * e0 + 1e-4);
    CHECK(es > 100.0 * e);
    /* the levels' rule (wg_amg.cross_share): the layers' shares take the terms on every level;
       with the shares above them every level leaves them out (the V-cycle is cross_skip's to the
       bit), with the finest level's share 0 alone only it takes them */
    CHECK_EQ_INT(g->amg->cross_levels, g->amg->n_levels);
    const double shares[2] = {g->amg->cross_share[0], g->amg->cross_share[1]};
    double* zr = calloc(n3, sizeof(double));
    g->amg->cross_share[0] = g->amg->cross_share[1] = 2.0;
    wg_amg_set_pairs(g->amg, g->pairs);
    CHECK_EQ_INT(g->amg->cross_levels, 0);
    gpu_vcycle(g, r, zr, 0);
    CHECK(memcmp(zr, zs, n3 * sizeof(double)) == 0);
    g->amg->cross_share[0] = 0.0;
    wg_amg_set_pairs(g->amg, g->pairs);
    CHECK_EQ_INT(g->amg->cross_levels, 1);
    CHECK(g->amg->lev[0].cross_use && !g->amg->lev[1].cross_use);
    gpu_vcycle(g, r, zr, 0);
    const double ef = ts_rel_diff(zr, zc, (int)n3);
    printf("  the levels' rule: the layers' cross blocks a share of the blocks %.2f / %.2f / %.2f by level, "
           "all in; the finest level's alone: V-cycle against core's %.1e\n",
           (double)g->amg->lev[0].cross_nb / g->amg->lev[0].nb, (double)g->amg->lev[1].cross_nb / g->amg->lev[1].nb,
           (double)g->amg->lev[2].cross_nb / g->amg->lev[2].nb, ef);
    CHECK(ef > 10.0 * e && ef < es);
    g->amg->cross_share[0] = shares[0];
    g->amg->cross_share[1] = shares[1];
    wg_amg_set_pairs(g->amg, g->pairs);
    CHECK_EQ_INT(g->amg->cross_levels, g->amg->n_levels);
    free(zr);
    check_coarse_levels(g, ca, &par);

    /* PCG with the multigrid on each side */
    wc_solver* cpu = NULL;
    wc_solver_opts o = def.solver;
    CHECK_EQ_INT(wc_solver_create(&cpu, &m, &o, 0, NULL, &d), WC_OK);
    wc_amg_destroy(cpu->amg);
    cpu->amg = NULL;
    CHECK_EQ_INT(wc_amg_create(&cpu->amg, &m, &ao, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_solver_set_coupling(cpu, &sc->self_pairs->coupling, sc->self_pairs->list.cap, &d), WC_OK);
    wc_solver_set_residual_floor(cpu, wc_state_residual_floor(sc, H));
    wc_solve_result rc, rg, rs;
    double *dc = calloc(n3, sizeof(double)), *dg = calloc(n3, sizeof(double)), *y = malloc(n3 * sizeof(double));
    CHECK_EQ_INT(wc_solve(cpu, WC_SOLVER_PCG, sc->A, sc->b, &sc->filter, dc, &sc->par, &rc), WC_OK);
    CHECK_EQ_INT(wg_sim_debug_solve(g, WC_SOLVER_PCG, dg, &rg, &d), WC_OK);
    /* the GPU's answer in core's system (the filter's part: dg - z in range(S)) */
    wc_state_mul_system(sc, dg, y);
    double rr = 0.0, bb = 0.0;
    for (int i = 0; i < n; ++i) {
        double t[3], u[3];
        for (int c = 0; c < 3; ++c) t[c] = sc->b[3 * i + c] - y[3 * i + c];
        wc_filter_apply(&sc->filter, i, t, u);
        for (int c = 0; c < 3; ++c) {
            double bf = sc->b[3 * i + c];
            rr += u[c] * u[c];
            bb += bf * bf;
        }
    }
    memset(dg, 0, n3 * sizeof(double));
    g->amg->cross_skip = 1;
    wg_sim_debug_solve(g, WC_SOLVER_PCG, dg, &rs, &d);
    g->amg->cross_skip = 0;
    /* the GPU's default: the finest bound x WG_AMG_CROSS_BOUND while the terms are in the levels */
    wc_solve_result rb;
    memset(dg, 0, n3 * sizeof(double));
    g->amg->cross_bound_scale = WG_AMG_CROSS_BOUND;
    wg_sim_debug_solve(g, WC_SOLVER_PCG, dg, &rb, &d);
    printf("  PCG to %.0e: GPU %d iterations, core (same method) %d; the GPU's answer in core's system: relative "
           "residual %.1e; the GPU without the terms in its levels: %d iterations; with its default bound "
           "factor %.1f: %d\n",
           o.tolerance, rg.iterations, rc.iterations, sqrt(rr / bb), rs.iterations, WG_AMG_CROSS_BOUND, rb.iterations);
    /* rs too: a Chebyshev bound below lambda_max broke PCG down at 6 iterations, which the count
       alone passed */
    CHECK(rc.converged && rg.converged && rs.converged && rb.converged);
    CHECK(abs(rg.iterations - rc.iterations) <= 2);
    CHECK(sqrt(rr / bb) < 1e-3);
    CHECK(2 * rg.iterations < rs.iterations);
    CHECK(2 * rb.iterations < rs.iterations);

    /* the same two solves with the GPU's warm steps: the one without the terms takes 3 warm steps
       from the iterate of the levels with them, whose quotient alone falls to 0.73 x the cold
       bound; the floor (WG_AMG_WARM_FLOOR x the cold quotient) keeps the interval above
       lambda_max */
    g->amg->warm_steps = WG_AMG_POWER_WARM;
    g->amg->cross_bound_scale = 1.0;
    wg_amg_cold(g->amg);
    wc_solve_result rt, rw;
    memset(dg, 0, n3 * sizeof(double));
    wg_sim_debug_solve(g, WC_SOLVER_PCG, dg, &rt, &d);
    float cold[4], warm[4];
    wg_read1(&g->layout, g->amg->lev[0].bound, cold);
    const long warm0 = g->amg->warm_setups;
    memset(dg, 0, n3 * sizeof(double));
    g->amg->cross_skip = 1;
    const wc_status sw = wg_sim_debug_solve(g, WC_SOLVER_PCG, dg, &rw, &d);
    g->amg->cross_skip = 0;
    wg_read1(&g->layout, g->amg->lev[0].bound, warm);
    printf("  warm steps: with the terms %d iterations (cold setup), then without them %d (warm setup; status %d), "
           "finest quotient cold %.3f, warm %.3f, its floor %.3f\n",
           rt.iterations, rw.iterations, (int)sw, cold[0] / cold[1], warm[0] / warm[1], warm[3]);
    CHECK(g->amg->warm_setups == warm0 + 1);
    CHECK(sw == WC_OK && rt.converged && rw.converged);
    CHECK(abs(rt.iterations - rg.iterations) <= 1);
    CHECK(rw.iterations <= rs.iterations + rs.iterations / 5);
    CHECK(fabs(warm[3] - WG_AMG_WARM_FLOOR * cold[0] / cold[1]) <= 1e-5 * warm[3]);

    free(r), free(zc), free(zg), free(zs), free(dc), free(dg), free(y);
    wc_solver_destroy(cpu);
    wc_amg_destroy(ca);
    wg_sim_destroy(g);
    wc_state_destroy(sc);
    wc_state_destroy(sg);
    wc_model_free(&m);
}

int main(void) {
    wg_gl_context_desc cd;
    memset(&cd, 0, sizeof cd);
    char err[512];
    if (wg_gl_context_create(&cd, &gl, err, sizeof err) != WC_OK || wg_gl_begin(gl, err, sizeof err) != WC_OK) {
        fprintf(stderr, "no GL context: %s\n", err);
        return 1;
    }
    /* the terms are opt-in (wg_device.amg_cross): a value other than 0 or 1 is refused by name */
    setenv("WEFT_GPU_AMG_CROSS", "yes", 1);
    err[0] = 0;
    CHECK(wg_device_create(gl, &dev, err, sizeof err) == WC_ERROR_GPU && dev == NULL);
    CHECK(strstr(err, "WEFT_GPU_AMG_CROSS='yes'") != NULL);
    setenv("WEFT_GPU_AMG_CROSS", "1", 1);
    if (wg_device_create(gl, &dev, err, sizeof err) != WC_OK) {
        fprintf(stderr, "device: %s\n", err);
        return 1;
    }
    CHECK(dev->amg_cross == 1);
    dev->amg_smooth = 0;   /* P = P_tent: the terms on every level (wg_amg_cross.c) */
    printf("device: %s (%s passes)\n", dev->renderer, dev->compute ? "compute" : "fragment");
    if (dev->compute) RUN_TEST(test_cross_terms);
    else printf("  skipped: the multigrid needs compute passes\n");
    wg_device_destroy(dev);
    wg_gl_end(gl);
    wg_gl_context_destroy(gl);
    return TEST_SUMMARY();
}
