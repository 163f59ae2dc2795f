/* The GPU self proximity pass's margin proof (gpu/solver/wg_self_prox.h, docs/design/gpu_self_prox.md)
 * reached and checked: test_api_gpu_self.c's heap strip (5 x 41 vertices, 0.2 m by 1.6 m, standing
 * on its end, falling onto a floor and onto itself) with a self thickness of 2 cm instead of 3 mm,
 * so that the proximity impulses where it piles up move particles by less than half the listing's
 * margin (0.25 thickness): the pass proves those substeps without the refined walk.
 *
 * The fall and the first contacts (frames 0..PREFIX-1) run once on the host's stage and are
 * saved; each mode then restores it in a cloth of its own (the pass's switches are read at
 * creation) and runs the pile-up (frames PREFIX..FRAMES-1), checking crossings every frame:
 *  - "check" (WEFT_GPU_SELF_PROX_REFINED=check): the margin decides as by default, and after each
 *    pass it proved the refined walk runs anyway: every pair it lists with a particle the pass
 *    moved is one of the first list's (those the pass's CCD checked); the margin proved at least
 *    one pass, every one checked, none missed. Limit: here the refined walks list no pair with a
 *    moved particle (0 compared: at 2 cm every pair near enough for the CCD is already listed
 *    for its proximity), so this check is not exercised past its count here;
 *  - "walk" (=walk): the refined walk after every moving pass: the same bytes as "check", the same
 *    impulses, stage runs and passes settled, its walks the check run's walks plus its proofs;
 *  - "default" (unset): the same bytes as "check" (the check changes nothing);
 *  - "host" (WEFT_GPU_SELF_PROX=off): core's whole stage on the host: the same bytes (the pass's
 *    result is core's stage's), the same impulses and rollbacks.
 * No run has a crossing (weft_cloth_check_collisions) at any frame. */
#define _POSIX_C_SOURCE 200809L   /* setenv */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"

#define DT (1.0 / 60.0)
#define HX AG_HEAP_X
#define HY AG_HEAP_Y
#define THICKNESS 0.02   /* m: the self thickness (the default 3 mm's impulses move past M / 2) */
#define PREFIX 38        /* frames of the fall, run once */
#define FRAMES 45

/* the pass's counts as the GPU cloth logs them (DEBUG): refined walks, passes proved by the margin,
   margin proofs checked, checks that missed a pair; then the stage's runs on the host and substeps
   settled by the pass (-1 before any) */
static long long g_xio[5], g_io[2];

static void io_log(weft_log_level level, const char* message, void* user) {
    (void)user;
    long long v[11];
    double dv[3];
    if (level != WEFT_LOG_DEBUG) return;
    if (sscanf(message, "GPU self proximity pass, since creation: %lld refined walks, %lld proved by the margin; %lld "
                        "local energy gains, %lld full; largest |local - full| %lf J, gain %lf J, total %lf J; margin "
                        "proofs checked %lld, missed %lld (%lld pairs compared)",
               &v[0], &v[1], &v[2], &v[3], &dv[0], &dv[1], &dv[2], &v[4], &v[5], &v[6]) == 10) {
        g_xio[0] = v[0];
        g_xio[1] = v[1];
        g_xio[2] = v[4];
        g_xio[3] = v[5];
        g_xio[4] = v[6];
    }
    if (sscanf(message, "GPU self-collision, transfers since creation: %lld stage runs, %lld bytes read back, %lld "
                        "bytes uploaded by %lld of the runs; idle proof: %lld substeps, %lld skipped, %lld checked, "
                        "%lld broken, %lld untried (backing off); %lld settled by the proximity pass on the listed "
                        "pairs (%lld moved)", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8], &v[9],
               &v[10]) == 11) {
        g_io[0] = v[0];
        g_io[1] = v[9];
    }
}

typedef struct run_result {
    float pos[3 * HX * HY];
    int nv, failed, frames_crossing, impulses, rollbacks;
    long long xio[5], io[2];
} run_result;

/* A GPU cloth of the heap at the GPU's method (as test_api_gpu_self.c's), the idle proof on. */
static int make(weft_context** ctx, weft_cloth* c, ag_mesh* m, weft_collider_def* floor) {
    memset(g_xio, 0xff, sizeof g_xio);
    memset(g_io, 0xff, sizeof g_io);
    weft_context_def cd = ap_context_def(WEFT_BACKEND_GPU);
    cd.log = io_log;
    cd.log_level = WEFT_LOG_DEBUG;
    *ctx = ap_try_create(&cd);
    CHECK(*ctx != NULL);
    if (!*ctx) return 0;
    weft_cloth_def d = weft_default_cloth_def();
    d.mesh = ag_desc(m);
    d.solver = WEFT_SOLVER_PCG;
    d.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    d.integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
    d.newton_iterations = 1;
    d.line_search = 0;
    d.substeps = 2;
    d.sleep_speed = 0;
    d.self_collision = 1;
    d.self_collision_thickness = THICKNESS;
    *floor = weft_default_collider_def();
    floor->type = WEFT_COLLIDER_PLANE;   /* y = 0, free side +y */
    floor->thickness = 0.005;
    floor->friction = 0.3;
    d.colliders = floor;
    d.n_colliders = 1;
    const weft_status st = weft_cloth_create(*ctx, &d, c);
    CHECK_EQ_INT(st, WEFT_OK);
    return st == WEFT_OK;
}

/* frames f0..f1-1, crossings checked at each; r's counts from them */
static void frames(weft_context* ctx, weft_cloth c, int f0, int f1, run_result* r) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    for (int f = f0; f < f1; ++f) {
        weft_frame_stats fs;
        if (weft_cloth_step(ctx, c, &fr, &fs) != WEFT_OK) ++r->failed;
        r->impulses += fs.self_impacts + fs.self_proximity;
        r->rollbacks += fs.rollbacks;
        weft_collision_check chk;
        CHECK_EQ_INT(weft_cloth_check_collisions(ctx, c, &chk), WEFT_OK);
        r->frames_crossing += chk.self_intersections > 0;
    }
}

/* The fall on the host's stage (WEFT_GPU_SELF_PROX unset): its snapshot after PREFIX frames
   (allocated here, *size bytes; NULL on failure). */
static unsigned char* fall(ag_mesh* m, size_t* size, run_result* r) {
    memset(r, 0, sizeof *r);
    weft_context* ctx;
    weft_cloth c;
    weft_collider_def floor;
    if (!make(&ctx, &c, m, &floor)) {
        weft_context_destroy(ctx);
        return NULL;
    }
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    *size = info.snapshot_size;
    unsigned char* snap = malloc(*size);
    frames(ctx, c, 0, PREFIX, r);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, snap, *size), WEFT_OK);
    weft_context_destroy(ctx);
    return snap;
}

/* The pile-up from the fall's snapshot in a cloth created under the environment set by the caller. */
static void pile(ag_mesh* m, const unsigned char* snap, size_t size, run_result* r) {
    memset(r, 0, sizeof *r);
    weft_context* ctx;
    weft_cloth c;
    weft_collider_def floor;
    if (make(&ctx, &c, m, &floor)) {
        CHECK_EQ_INT(weft_cloth_restore(ctx, c, snap, size), WEFT_OK);
        frames(ctx, c, PREFIX, FRAMES, r);
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, r->pos, NULL, m->nv, &r->nv), WEFT_OK);
    }
    memcpy(r->xio, g_xio, sizeof g_xio);
    memcpy(r->io, g_io, sizeof g_io);
    weft_context_destroy(ctx);
}

static double max_distance(const run_result* a, const run_result* b) {
    double d = 0.0;
    for (int i = 0; i < a->nv; ++i)
        d = fmax(d, sqrt(pow(a->pos[3 * i] - b->pos[3 * i], 2) + pow(a->pos[3 * i + 1] - b->pos[3 * i + 1], 2) +
                         pow(a->pos[3 * i + 2] - b->pos[3 * i + 2], 2)));
    return d;
}

enum { CHECKED, WALK, DEFAULT, HOST, N_MODES };

static void test_margin(void) {
    static const char* names[N_MODES] = {"margin, checked", "refined walk always", "margin", "host's stage"};
    static run_result pre, r[N_MODES];
    ag_mesh m;
    ag_heap_strip(&m);
    size_t size = 0;
    unsigned char* snap = fall(&m, &size, &pre);
    CHECK(snap != NULL);
    CHECK_EQ_INT(pre.failed, 0);
    CHECK_EQ_INT(pre.frames_crossing, 0);
    for (int k = 0; k < N_MODES && snap; ++k) {
        setenv("WEFT_GPU_SELF_IDLE", "on", 1);
        setenv("WEFT_GPU_SELF_PROX", k == HOST ? "off" : "512", 1);   /* the most room */
        if (k == CHECKED) setenv("WEFT_GPU_SELF_PROX_REFINED", "check", 1);
        if (k == WALK) setenv("WEFT_GPU_SELF_PROX_REFINED", "walk", 1);
        pile(&m, snap, size, &r[k]);
        unsetenv("WEFT_GPU_SELF_PROX_REFINED");
        unsetenv("WEFT_GPU_SELF_PROX");
        unsetenv("WEFT_GPU_SELF_IDLE");
        const run_result* q = &r[k];
        printf("heap, thickness %g m, frames %d..%d, %s: refined walks %lld, proved by the margin %lld (checked "
               "%lld, missed %lld, %lld pairs compared), stage runs %lld, settled by the pass %lld, impulses %d, rollbacks %d, frames "
               "crossing %d, largest distance from the checked run %.3g m%s\n",
               THICKNESS, PREFIX, FRAMES - 1, names[k], q->xio[0], q->xio[1], q->xio[2], q->xio[3], q->xio[4], q->io[0], q->io[1],
               q->impulses, q->rollbacks, q->frames_crossing, max_distance(q, &r[CHECKED]),
               memcmp(q->pos, r[CHECKED].pos, sizeof q->pos) == 0 ? " (the same bytes)" : "");
    }
    free(snap);
    ag_free(&m);
    if (!snap) return;
    for (int k = 0; k < N_MODES; ++k) {
        CHECK_EQ_INT(r[k].failed, 0);
        CHECK_EQ_INT(r[k].frames_crossing, 0);
        CHECK_EQ_INT(r[k].nv, HX * HY);
    }
    const long long *c = r[CHECKED].xio, *w = r[WALK].xio;
    /* the margin's skip reached, and every proof it gave checked against the refined walk */
    CHECK(c[1] >= 1 && c[2] == c[1] && c[3] == 0);
    /* the refined walk every time: the same decisions, so the same bytes */
    CHECK(w[1] == 0 && w[2] == 0 && w[0] == c[0] + c[1]);
    CHECK(memcmp(r[WALK].pos, r[CHECKED].pos, sizeof r[WALK].pos) == 0);
    CHECK_EQ_INT(r[WALK].impulses, r[CHECKED].impulses);
    CHECK(r[WALK].io[0] == r[CHECKED].io[0] && r[WALK].io[1] == r[CHECKED].io[1]);
    /* the check changes nothing */
    CHECK(memcmp(r[DEFAULT].pos, r[CHECKED].pos, sizeof r[DEFAULT].pos) == 0);
    CHECK(r[DEFAULT].xio[0] == c[0] && r[DEFAULT].xio[1] == c[1] && r[DEFAULT].xio[2] == 0);
    /* core's stage on the host: the same bytes and impulses, the pass settling nothing */
    CHECK(memcmp(r[HOST].pos, r[CHECKED].pos, sizeof r[HOST].pos) == 0);
    CHECK_EQ_INT(r[HOST].impulses, r[CHECKED].impulses);
    CHECK_EQ_INT(r[HOST].rollbacks, r[CHECKED].rollbacks);
    CHECK(r[HOST].io[1] == 0 && r[HOST].io[0] > r[CHECKED].io[0]);
}

int main(void) {
    if (!ap_gpu_here()) {
        printf("no GPU context: skipped\n");
        return 0;
    }
    RUN_TEST(test_margin);
    return TEST_SUMMARY();
}
