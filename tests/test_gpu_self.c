/* The GPU's self-collision (gpu/solver/wg_self.h: core's stage on the host after each GPU
 * substep) against core's CPU step with the stage alone (sim def self_in_solve = 0: the same
 * stage, no self-contact pairs in the solve, which the GPU does not have), on a real EGL context
 * (llvmpipe without a GPU): tests/two_layers.h's upper sheet dropped onto its pinned lower one,
 * 20 frames, with backward Euler, BDF2 and TR-BDF2 (block Jacobi PCG, one linearised step). Both
 * run the same stage on the same kind of input, so they roll back the same substeps (the energy
 * judge sees the stage the same way), are free of crossings at every frame (core's
 * wc_self_intersections), need proximity impulses in the same measure (within 5 % in the frames
 * neither rolled back: a rejected attempt's state is far from the solution, where float and
 * double part) and end close: 2 mm (backward Euler), 5 mm (BDF2), 1 cm (TR-BDF2).
 * With WEFT_GPU_SELF_IDLE=check (test_gpu_self_idle_check): the GPU's idle proof
 * (gpu/solver/wg_self_idle.h) is checked: core's stage, run anyway where the proof said idle,
 * moved nothing there, and it acted on some of the substeps left to it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "self_crossings.h"
#include "step.h"
#include "test_support.h"
#include "two_layers.h"
#include "wg_sim.h"

#define LN 10
#define FRAMES 20

static wg_gl_context* gl;
static wg_device* dev;

/* The two layers at two_layers_shifted's positions, the lower one pinned where it is. */
static wc_state* layers_state(const wc_model* m, wc_integrator integ) {
    wc_sim_def def = wc_default_sim_def();
    def.solver.type = WC_SOLVER_PCG;
    def.solver.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    def.integrator = integ;
    def.newton_iterations = 1;
    def.line_search = 0;
    def.substeps = 2;
    def.sleep_speed = 0.0;
    def.max_colliders = 0;
    def.self_collision = 1;
    def.self_in_solve = 0;
    wc_state* s = two_layers_approaching(m, LN, 0.5, 0.0, &def);
    if (!s) return NULL;
    wc_pin pins[LN * LN];
    memset(pins, 0, sizeof pins);
    for (int v = 0; v < LN * LN; ++v) {
        pins[v].particle = m->host_to_particle[v];
        v3_copy(pins[v].target, s->x + 3 * pins[v].particle);
    }
    wc_diag d = {0};
    if (wc_state_set_pins(s, pins, LN * LN, &d) != WC_OK) {
        fprintf(stderr, "pins: %s\n", d.message);
        wc_state_destroy(s);
        return NULL;
    }
    return s;
}

typedef struct totals {
    int rollbacks, proximity, impacts, zones, unresolved, failed, crossings;
    int proximity_kept;         /* proximity impulses in the frames neither backend rolled back */
} totals;

static void add(totals* t, const wc_step_stats* st, wc_status r) {
    t->rollbacks += st->rollbacks;
    t->proximity += st->self_proximity;
    t->impacts += st->self_impacts;
    t->zones += st->self_zones;
    t->unresolved += st->self_unresolved;
    t->failed += r != WC_OK;
}

/* the stage's transfers and its idle proof's counts (gpu/solver/wg_self_idle.h) as the frame logs
   them: runs, bytes read back, bytes uploaded, runs that uploaded, proofs, skipped, checked,
   broken, untried (the back-off) */
static long long g_io[9];

static void io_log(wc_log_level level, const char* message, void* user) {
    (void)user;
    long long v[9];
    if (level == WC_LOG_DEBUG &&
        sscanf(message, "GPU self-collision, transfers since creation: %lld stage runs, %lld bytes read back, %lld "
                        "bytes uploaded by %lld of the runs; idle proof: %lld substeps, %lld skipped, %lld checked, "
                        "%lld broken, %lld untried", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8]) == 9)
        memcpy(g_io, v, sizeof v);
}

/* dist (m): the bound on the end positions' distance */
static void run(wc_integrator integ, const char* name, double dist) {
    wc_model m;
    if (!two_layers(&m, LN, 0.5, 0.0, 0.04)) return;
    wc_state* c = layers_state(&m, integ);
    wc_state* s = layers_state(&m, integ);
    CHECK(c && s);
    wg_sim* g = NULL;
    wc_diag d = {0};
    d.log = io_log;
    memset(g_io, 0, sizeof g_io);
    if (s) CHECK(wg_sim_create(dev, s, NULL, &g, &d) == WC_OK);
    if (!c || !s || !g) {
        wc_state_destroy(c);
        wc_state_destroy(s);
        wc_model_free(&m);
        return;
    }
    totals tg = {0}, tc = {0};
    int n = m.n_particles, count = 0;
    for (int f = 0; f < FRAMES; ++f) {
        wc_step_stats sg, sc;
        add(&tg, &sg, wg_sim_step_frame(g, s, 1.0 / 60.0, &sg, &d));
        add(&tc, &sc, wc_step_frame(c, 1.0 / 60.0, &sc, &d));
        CHECK(wg_sim_download(g, s, &d) == WC_OK);
        CHECK(wc_self_intersections(&m, s->x, NULL, &count, &d) == WC_OK);
        tg.crossings += count;
        CHECK(wc_self_intersections(&m, c->x, NULL, &count, &d) == WC_OK);
        tc.crossings += count;
        if (sg.rollbacks == 0 && sc.rollbacks == 0) {
            tg.proximity_kept += sg.self_proximity;
            tc.proximity_kept += sc.self_proximity;
        }
    }
    double e = ts_max_diff(s->x, c->x, 3 * n);
    printf("  %s, %d frames: GPU rollbacks %d, proximity %d (%d in frames without a rollback), impacts %d, zones %d, "
           "crossings %d; CPU (the stage alone) %d, %d (%d), %d, %d, %d; max |x_gpu - x_cpu| = %.3g m\n",
           name, FRAMES, tg.rollbacks, tg.proximity, tg.proximity_kept, tg.impacts, tg.zones, tg.crossings,
           tc.rollbacks, tc.proximity, tc.proximity_kept, tc.impacts, tc.zones, tc.crossings, e);
    CHECK_EQ_INT(tg.failed, 0);
    CHECK_EQ_INT(tg.crossings, 0);
    CHECK_EQ_INT(tg.unresolved, 0);
    const char* idle = getenv("WEFT_GPU_SELF_IDLE");
    if (idle && strcmp(idle, "check") == 0) {   /* test_gpu_self_idle_check */
        printf("    idle proof: %lld substeps, %lld proved idle (the stage run anyway: %lld moved something), %lld "
               "left to the stage (%lld moved something)\n", g_io[4], g_io[6], g_io[7], g_io[0] - g_io[6], g_io[3]);
        CHECK(g_io[6] > 0 && g_io[7] == 0);   /* the stage moved nothing where the proof said idle */
        CHECK(g_io[0] - g_io[6] > 0 && g_io[3] > 0);   /* and it acted on some of the others */
    }
    CHECK_EQ_INT(tc.crossings, 0);
    CHECK_EQ_INT(tg.rollbacks, tc.rollbacks);
    CHECK(tc.proximity_kept > 0 && fabs((double)tg.proximity_kept - tc.proximity_kept) < 0.05 * tc.proximity_kept);
    CHECK(e < dist);
    wg_sim_destroy(g);
    wc_state_destroy(s);
    wc_state_destroy(c);
    wc_model_free(&m);
}

static void test_be(void) { run(WC_INTEGRATOR_BE, "backward Euler", 2e-3); }
static void test_bdf2(void) { run(WC_INTEGRATOR_BDF2, "BDF2", 5e-3); }
static void test_trbdf2(void) { run(WC_INTEGRATOR_TRBDF2, "TR-BDF2", 1e-2); }

int main(void) {
    if (!tg_gpu_open(&gl, &dev)) return 1;
    RUN_TEST(test_be);
    RUN_TEST(test_bdf2);
    RUN_TEST(test_trbdf2);
    tg_gpu_close(gl, dev);
    return TEST_SUMMARY();
}
