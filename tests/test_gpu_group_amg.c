/* PCG with the multigrid's V-cycle in one work group (pcg_group_amg.glsl) against the multi-pass
 * chain with the same multigrid on the same float systems (real EGL: llvmpipe without a GPU; the
 * chain checked against CHOLMOD and core by test_gpu_amg): hanging sheets of one level (the dense
 * factor alone), two and three levels, with pins and plane constraints carrying z, a stiff one, a
 * drape with contacts and friction, separate patches whose coarsest level is smoothed; converged,
 * capped, near float's reach, a zero right-hand side, a non-finite system: the
 * same status and iteration counts (within 1), the final residuals and iterates within float's
 * reach of each other, and the solve itself one dispatch after the multigrid's setup passes; a
 * multigrid cloth past the group's limit is refused when WEFT_GPU_SOLVE=group forces it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "gpu_group_support.h"
#include "test_support.h"
#include "wg_amg.h"
#include "wg_amg_group.h"

static wg_gl_context* gl;
static wg_device* dev;

/* The passes of one solve's multigrid setup and packing (what the group runs before its dispatch) */
static long long setup_passes(wg_sim* g) {
    const long long p0 = wg_sim_debug_passes(g);
    wg_amg_setup(g->amg);
    wg_amg_group_pack(g->amg);
    return wg_sim_debug_passes(g) - p0;
}

/* The group against the chain from the same guess: the same status and convergence, iterations
 * within 1, the final residual within rel_res (relative; or 1 % of the tolerance, or both below
 * 1e-6), the iterates
 * within rel_dv of the largest component, the group one pass after its setup's. Returns the
 * group's run (the caller frees its dv). */
static tg_solved compare(const char* what, wg_sim* g, const wc_solver_opts* o, const double* guess, double rel_dv,
                         double rel_res) {
    g->amg->warm_steps = 0;   /* every setup cold: the same bounds for both solves */
    wg_amg_cold(g->amg);
    const long long setup = setup_passes(g);
    tg_solved a = tg_solve_as(dev, g, o, guess, WG_SOLVE_GROUP), b = tg_solve_as(dev, g, o, guess, WG_SOLVE_PASSES);
    const int n3 = 3 * g->n;
    const double scale = fmax(ts_max_abs(b.dv, n3), 1e-30), e = ts_max_diff(a.dv, b.dv, n3) / scale;
    const double dres = fabs(a.res.residual - b.res.residual) / fmax(b.res.residual, 1e-30);
    printf("  %-30s %5d particles, %d levels (coarsest %3d, %s): iterations group %3d passes %3d, residual "
           "%.4g / %.4g (%.1g apart), iterates %.2g apart, %d restart(s), passes %lld / %lld (setup %lld)\n",
           what, g->n, g->amg->n_levels, g->amg->lev[g->amg->n_levels - 1].n, g->amg->dense ? "factored" : "smoothed",
           a.res.iterations, b.res.iterations, a.res.residual, b.res.residual, dres, e, (int)a.grp[3], a.passes,
           b.passes, setup);
    CHECK_EQ_INT(a.st, b.st);
    CHECK(abs(a.res.iterations - b.res.iterations) <= 1);
    CHECK_EQ_INT(a.res.converged, b.res.converged);
    CHECK(a.res.residual0 == b.res.residual0 || fabs(a.res.residual0 - b.res.residual0) <= 1e-5 * b.res.residual0);
    /* (or both at float's reach: a one-level solve is exact, its residual rounding) */
    CHECK(dres <= rel_res || fabs(a.res.residual - b.res.residual) <= 0.01 * o->tolerance ||
          fmax(a.res.residual, b.res.residual) <= 1e-6);
    CHECK(e <= rel_dv);
    CHECK(a.passes == setup + 1);   /* the setup's passes, then one dispatch: its read-backs are no passes */
    free(b.dv);
    return a;
}

/* Converged to 1e-4 from zeros, then from that answer to 1e-3 (done at once), and capped at
 * `cap` iterations (tolerance 0); the iterates' bounds x dv_loose */
static void converged_and_capped(const char* what, wg_sim* g, const wc_solver_opts* so, int cap, double dv_loose) {
    wc_solver_opts o = *so;
    o.tolerance = 1e-4;
    o.max_iterations = 300;
    tg_solved a = compare(what, g, &o, NULL, 1e-3 * dv_loose, 0.05);
    CHECK(a.res.converged && a.st == WC_OK);
    o.tolerance = 1e-3;
    tg_solved b = compare("  from its answer, to 1e-3", g, &o, a.dv, 1e-6, 0.05);
    CHECK_EQ_INT(b.res.iterations, 0);
    CHECK(b.res.converged);
    o.tolerance = 0.0;
    o.max_iterations = cap;
    tg_solved c = compare("  capped (tolerance 0)", g, &o, NULL, 4e-5 * cap * dv_loose, 1e-3);
    CHECK_EQ_INT(c.res.iterations, cap);
    CHECK(!c.res.converged);
    free(a.dv), free(b.dv), free(c.dv);
}

/* Sheets of 9 (one level: the dense factor), 169 and 1,024 particles with planes, a stiff one.
 * With P = P_tent the 1,024-particle sheet is capped at 30 iterations: llvmpipe ends an
 * invocation's loops after 65,535 iterations in all, which the coarsest level solved by one
 * invocation (two triangular solves of 48 unknowns, about 2,300 steps a V-cycle) reached at the
 * 22nd iteration, and the group's barriers then parted (a negative r.r, the solve "diverged"); the
 * coarsest solve is one node an invocation now. With the smoothed prolongator it is capped at 8:
 * with rotations it reaches float's reach (2.8e-6) by the 12th iteration, past which float PCG's
 * true residual wanders on both forms (0.4 apart at 20, both stopped "diverged" at the 41st).
 * The stiff sheet is capped at 1 with the smoothed prolongator, one V-cycle (with rotations 1e-7
 * apart), and its converged iterates are compared 5x looser with rotations: PCG's later
 * iterations take a float rounding into the soft modes the coarse levels' rotations hold (the
 * residuals 1e-4 apart converged, 6e-5 capped at 3, the iterates 2.4e-3 and 3.4e-2 of their
 * largest component; with translations 4e-6 and 5e-6). */
static void test_sheets(void) {
    static const struct {
        const char* name;
        int n, warm, cap, cap_smoothed, levels;
        double k_scale, dv_rot;
    } cases[] = {
        {"hanging 3 x 3 (one level)", 3, 2, 1, 1, 1, 1.0, 1.0},
        {"hanging 13 x 13", 13, 2, 5, 5, 2, 1.0, 1.0},
        {"hanging 32 x 32", 32, 3, 30, 8, 3, 1.0, 1.0},
        {"hanging 24 x 24, k x1000", 24, 3, 3, 1, 3, 1000.0, 5.0},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        wc_model m;
        wg_sim* g = NULL;
        dev->solve = WG_SOLVE_GROUP;   /* the multigrid's group textures are made under =group only */
        wc_state* s = tg_sheet_system(dev, &m, cases[k].n, cases[k].warm, cases[k].k_scale, WC_PRECOND_AMG, &g);
        dev->solve = WG_SOLVE_AUTO;
        CHECK(s != NULL && g != NULL && g->amg != NULL);
        if (!s || !g || !g->amg) return;
        CHECK(g->amg->n_levels >= cases[k].levels);
        CHECK_EQ_INT(g->amg->rotations, g->amg->n_levels > 1 && dev->amg_smooth && dev->amg_rot);
        if (g->amg->rotations) CHECK(g->amg->lev[1].pair);
        converged_and_capped(cases[k].name, g, &s->def.solver, g->amg->smoothed ? cases[k].cap_smoothed : cases[k].cap,
                             g->amg->rotations ? cases[k].dv_rot : 1.0);
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* A drape over a sphere (contacts and friction in the filter) and 40 separate patches (the
 * coarsest level smoothed: no dense factor). Both are compared 1.5x looser: PCG capped at 3
 * takes the two orders' rounding to 1.4e-4 of the largest component (rotations about the current
 * positions, WEFT_GPU_AMG_CURRENT=1; about the rest positions 9.6e-5 before core's setup went to
 * float, 1.4e-4 since: the drape's input is 20 CPU frames on core's multigrid); one V-cycle agrees
 * to 2e-7 on both (the stiff sheet's, test_sheets). The patches' input is three CPU frames, and
 * with the CPU's V-cycle on float iterates they end 1.3e-4 apart (the bound at 1.0: 1.2e-4). */
static void test_drape_and_patches(void) {
    const wc_sim_def def = ts_amg_def();
    for (int k = 0; k < 2; ++k) {
        wc_model m;
        wc_state* s = k == 0 ? ts_draped(&m, 20, &def, 20) : ts_patches(&m, 40, &def);
        CHECK(s != NULL);
        if (!s) return;
        if (k == 0) CHECK(s->contacts.active > 0);
        dev->solve = WG_SOLVE_GROUP;
        wg_sim* g = tg_gpu_system(dev, s, 0);
        dev->solve = WG_SOLVE_AUTO;
        CHECK(g != NULL && g->amg != NULL);
        if (g && g->amg) {
            CHECK_EQ_INT(g->amg->dense, k == 0);
            converged_and_capped(k == 0 ? "draped over a sphere" : "40 separate patches", g, &s->def.solver, 3, 1.5);
        }
        wg_sim_destroy(g);
        wc_state_destroy(s);
        wc_model_free(&m);
    }
}

/* A tolerance near float's reach (the multigrid's recurrence stays close to the true residual
 * there: no restart, where block Jacobi restarts, test_gpu_group), a zero right-hand side (dv = z,
 * no iteration) and a non-finite b (diverged, dv = z) in both */
static void test_edges(void) {
    wc_model m;
    wg_sim* g = NULL;
    dev->solve = WG_SOLVE_GROUP;
    wc_state* s = tg_sheet_system(dev, &m, 10, 0, 1.0, WC_PRECOND_AMG, &g);
    dev->solve = WG_SOLVE_AUTO;
    CHECK(s != NULL && g != NULL);
    if (!s || !g) return;
    /* the group's copies are made under =group only (the chain's cloth holds none) */
    CHECK(wg_amg_group_fits(g->amg));
    wg_sim* chain = tg_gpu_system(dev, s, 1);
    CHECK(chain != NULL && chain->amg != NULL && !wg_amg_group_fits(chain->amg));
    wg_sim_destroy(chain);
    wc_solver_opts o = s->def.solver;
    o.max_iterations = 300;
    o.tolerance = 4e-7;
    tg_solved r = compare("tolerance 4e-7", g, &o, NULL, 1e-4, 0.5);
    free(r.dv);

    tg_zero_and_bad_b(dev, s, g, o, compare);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* WEFT_GPU_SOLVE=group on a multigrid cloth past the group's limit: refused at creation with a
 * message naming the limit, the state untouched; =passes takes it. */
static void test_limit_refused(void) { tg_limit_refused(dev, WC_PRECOND_AMG); }

/* The multigrid's form from the argument: none, the default (the smoothed prolongator with
 * rotations about the rest positions: pair levels, 6x6 block-diagonal smoothers); "trans" the
 * smoothed prolongator with translations (WEFT_GPU_AMG_ROT=0); "tent" P = P_tent
 * (WEFT_GPU_AMG_SMOOTH=0). ctest runs all three. */
int main(int argc, char** argv) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    const char* form = argc > 1 ? argv[1] : "rot";
    dev->amg_smooth = strcmp(form, "tent") != 0;
    dev->amg_rot = strcmp(form, "rot") == 0;
    printf("multigrid: %s\n", dev->amg_smooth ? dev->amg_rot ? "smoothed P, rotations" : "smoothed P, translations" : "P = P_tent");
    if (!dev->compute) {   /* the multigrid and the one-group solve are compute shaders */
        printf("fragment passes: no multigrid\n");
    } else {
        RUN_TEST(test_sheets);
        RUN_TEST(test_drape_and_patches);
        RUN_TEST(test_edges);
        RUN_TEST(test_limit_refused);
    }
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
