/* Self-collision on the GPU backend through the public API (real EGL: llvmpipe without a GPU),
 * GPU against CPU with the GPU's method on both (PCG with block Jacobi, backward Euler, Newton
 * 1, no line search). The GPU runs core's stage on the host after each substep
 * (gpu/solver/wg_self.h) and, as the CPU, the self-contact pairs in its solve (wg_pairs.h). Two
 * scenes, checked every frame with weft_cloth_check_collisions (core's edge-triangle crossings of
 * the positions read back):
 *  - layers: a sheet dropped 4 cm onto a pinned sheet of one mesh (two components), its vertices
 *    over the lower sheet's triangles: no crossing on the GPU, the pairs (found, active, rechecked)
 *    and the stage's impulses in the frame statistics as the CPU's, the upper sheet resting on the
 *    lower one at the CPU's height (positions within a bound), no rollback, no allocation in a
 *    step; without self-collision it falls through;
 *  - heap: a 1.6 m strip standing on its end falls onto a floor and piles up on itself
 *    (tests/heap_strip.h's strip): no crossing at any frame on the GPU, the stage's impacts,
 *    active pairs and recheck passes, no unresolved pair, its height and centre within bounds
 *    of the CPU's.
 * The layers also with BDF2, TR-BDF2 and Newton 2 with the line search.
 * Also: a snapshot mid-run restores to the same bytes and replays bit-identically; -1 means on
 * for a garment (a cloth with seams) and off otherwise, as on the CPU.
 * With the argument "pairs" (test_api_gpu_self_pairs): the self-contact pairs found on the GPU
 * (gpu/solver/wg_self_pairs.h, WEFT_GPU_SELF_PAIRS=gpu) against core's detection on the host
 * (=host), the layers and the heap: core's list either way, so the same bytes (positions equal:
 * the bound is 0), rollbacks, pairs and stage impulses; and the snapshot's replay with it. */
#define _POSIX_C_SOURCE 200809L   /* setenv */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"

#define DT (1.0 / 60.0)

static ag_alloc_counter g_count;
/* the stage's transfers as the GPU cloth logs them after each frame (DEBUG): runs, bytes read
   back, bytes uploaded, runs that uploaded, then the idle proof's substeps, skipped runs, checked
   runs, broken proofs and substeps left untried by its back-off (gpu/solver/wg_self_idle.h); -1
   before any */
#define IO_N 11
static long long g_io[IO_N] = {-1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};

/* the self pairs' GPU finder as the cloth logs it (DEBUG): substeps found, those core found (for
   too many candidates or a non-finite x or v), candidates, bytes read back (gpu/solver/wg_self_pairs.h); -1 before any */
#define PIO_N 4
static long long g_pio[PIO_N] = {-1, -1, -1, -1};

/* the proximity pass's own counts (DEBUG, gpu/solver/wg_self_prox.h): refined walks, passes
   proved by the margin, local gains, full gains; then |local - full| largest, |full gain| largest,
   |total energy| largest (J) */
static long long g_xio[4];
static double g_xgain[3];

static void io_log(weft_log_level level, const char* message, void* user) {
    (void)user;
    long long v[IO_N];
    double dv[3];
    if (level == WEFT_LOG_DEBUG &&
        sscanf(message, "GPU self proximity pass, since creation: %lld refined walks, %lld proved by the margin; %lld "
                        "local energy gains, %lld full; largest |local - full| %lf J, gain %lf J, total %lf J",
               &v[0], &v[1], &v[2], &v[3], &dv[0], &dv[1], &dv[2]) == 7) {
        memcpy(g_xio, v, sizeof g_xio);
        memcpy(g_xgain, dv, sizeof g_xgain);
    }
    if (level == WEFT_LOG_DEBUG &&
        sscanf(message, "GPU self pairs, since creation: %lld substeps found (%lld by core: %lld too many candidates, "
                        "%lld not finite), %lld candidates, %lld bytes read back", &v[0], &v[1], &v[4], &v[5], &v[2],
               &v[3]) == PIO_N + 2)
        memcpy(g_pio, v, sizeof g_pio);
    if (level == WEFT_LOG_DEBUG &&
        sscanf(message, "GPU self-collision, transfers since creation: %lld stage runs, %lld bytes read back, %lld "
                        "bytes uploaded by %lld of the runs; idle proof: %lld substeps, %lld skipped, %lld checked, "
                        "%lld broken, %lld untried (backing off); %lld settled by the proximity pass on the listed "
                        "pairs (%lld moved)", &v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8], &v[9],
               &v[10]) == IO_N)
        memcpy(g_io, v, sizeof v);
}

static weft_context* make_ctx(weft_backend backend) {
    memset(g_io, 0xff, sizeof g_io);
    memset(g_pio, 0xff, sizeof g_pio);
    weft_context_def cd = ap_context_def(backend);
    cd.allocator.alloc = ag_count_alloc;
    cd.allocator.free = ag_count_free;
    cd.allocator.user = &g_count;
    cd.log = io_log;
    cd.log_level = WEFT_LOG_DEBUG;
    return ap_try_create(&cd);
}

/* Two horizontal 10 x 10 sheets of 0.5 m: the lower at y = 0 (host vertices 0..99), the upper
 * 4 cm above it, shifted a third of a cell along x and a fifth along z so that its vertices sit
 * over the lower sheet's triangles. */
#define LN 10
static float g_drop = 0.04f;   /* m: the upper sheet's height above the lower */
static void layers(ag_mesh* m) {
    memset(m, 0, sizeof *m);
    ag_mesh a;
    ag_grid(&a, LN, 0.5, 0.0, 0, 0);
    m->nv = 2 * a.nv;
    m->nf = 2 * a.nf;
    m->pos = malloc(3 * sizeof(float) * (size_t)m->nv);
    m->sizes = malloc(sizeof(int) * (size_t)m->nf);
    m->idx = malloc(4 * sizeof(int) * (size_t)m->nf);
    double cell = 0.5 / (LN - 1);
    for (int L = 0; L < 2; ++L) {
        for (int v = 0; v < a.nv; ++v) {
            float* p = m->pos + 3 * (L * a.nv + v);
            p[0] = a.pos[3 * v] + (L ? (float)(cell / 3.0) : 0.0f);
            p[1] = L ? g_drop : 0.0f;
            p[2] = a.pos[3 * v + 2] + (L ? (float)(cell / 5.0) : 0.0f);
        }
        for (int f = 0; f < a.nf; ++f) {
            m->sizes[L * a.nf + f] = 4;
            for (int k = 0; k < 4; ++k) m->idx[4 * (L * a.nf + f) + k] = a.idx[4 * f + k] + L * a.nv;
        }
    }
    ag_free(&a);
}

#define HX AG_HEAP_X
#define HY AG_HEAP_Y

typedef struct run_result {
    float pos[3 * 2 * LN * LN > 3 * HX * HY ? 3 * 2 * LN * LN : 3 * HX * HY];
    int nv;
    int max_crossings, frames_crossing;
    long long io1[IO_N], io[IO_N]; /* the GPU stage's transfers after frame 1 and at the end (g_io) */
    long long pio[PIO_N];          /* the self pairs' GPU finder's at the end (g_pio) */
    int impacts, proximity, zones, unresolved, rollbacks, failed, iterations;
    int pairs, pairs_active, pair_passes;   /* the self-contact pairs in the solve */
    long step_allocs;           /* allocations through the context's allocator in frames 2.. */
    double ms_self, ms_total;
} run_result;

static int g_pinned[LN * LN];
/* the method of run()'s cloths: the GPU's (backward Euler, one linearised step) unless a test
   changes it */
static weft_integrator g_integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
static int g_newton = 1, g_search = 0;

/* The layers' lower sheet pinned where it is (att: the attachment d points at). */
static void pin_lower(weft_cloth_def* d, weft_attachment_def* att) {
    for (int k = 0; k < LN * LN; ++k) g_pinned[k] = k;
    *att = weft_default_attachment_def();
    att->vertices = g_pinned;
    att->n_vertices = LN * LN;
    d->attachments = att;
    d->n_attachments = 1;
}

static weft_cloth_def method_def(const ag_mesh* m, int self) {
    weft_cloth_def d = weft_default_cloth_def();
    d.mesh = ag_desc(m);
    d.solver = WEFT_SOLVER_PCG;
    d.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    d.integrator = g_integrator;
    d.newton_iterations = g_newton;
    d.line_search = g_search;
    d.substeps = 2;
    d.sleep_speed = 0;
    d.self_collision = self;
    return d;
}

/* scene 0: the layers (the lower sheet pinned); 1: the heap on a floor. Frames of DT; with
 * snapshot, *snapshot (allocated here) is the state after `snapshot` frames. */
static void run(weft_backend backend, int scene, int self, int frames, run_result* r) {
    memset(r, 0, sizeof *r);
    weft_context* ctx = make_ctx(backend);
    CHECK(ctx != NULL);
    if (!ctx) return;
    ag_mesh m;
    if (scene == 0) layers(&m);
    else ag_heap_strip(&m);
    weft_cloth_def d = method_def(&m, self);
    weft_attachment_def att = weft_default_attachment_def();
    weft_collider_def floor = weft_default_collider_def();
    if (scene == 0) {
        pin_lower(&d, &att);
    } else {
        floor.type = WEFT_COLLIDER_PLANE;   /* y = 0, free side +y */
        floor.thickness = 0.005;
        floor.friction = 0.3;
        d.colliders = &floor;
        d.n_colliders = 1;
    }
    weft_cloth c;
    weft_status st = weft_cloth_create(ctx, &d, &c);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        printf("  create: %s\n", weft_context_last_error(ctx));
        weft_context_destroy(ctx);
        ag_free(&m);
        return;
    }
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    CHECK_EQ_INT(info.self_collision, self);
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    for (int f = 0; f < frames; ++f) {
        weft_frame_stats fs;
        long before = g_count.allocs;
        if (weft_cloth_step(ctx, c, &fr, &fs) != WEFT_OK) ++r->failed;
        if (f > 0) r->step_allocs += g_count.allocs - before;
        if (f == 0) memcpy(r->io1, g_io, sizeof g_io);
        r->impacts += fs.self_impacts;
        r->proximity += fs.self_proximity;
        r->zones += fs.self_zones;
        r->unresolved += fs.self_unresolved;
        r->rollbacks += fs.rollbacks;
        r->iterations += fs.iterations;
        r->pairs += fs.self_pairs;
        r->pairs_active += fs.self_pairs_active;
        r->pair_passes += fs.self_pair_passes;
        r->ms_self += fs.ms_self_collide;
        r->ms_total += fs.ms_total;
        weft_collision_check chk;
        CHECK_EQ_INT(weft_cloth_check_collisions(ctx, c, &chk), WEFT_OK);
        if (chk.self_intersections > r->max_crossings) r->max_crossings = chk.self_intersections;
        r->frames_crossing += chk.self_intersections > 0;
    }
    memcpy(r->io, g_io, sizeof g_io);
    memcpy(r->pio, g_pio, sizeof g_pio);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, r->pos, NULL, m.nv, &r->nv), WEFT_OK);
    weft_context_destroy(ctx);
    ag_free(&m);
}

static void print_run(const char* name, const run_result* r) {
    printf("  %s: max crossings %d (%d frames), proximity %d, impacts %d, zones %d, unresolved %d, rollbacks %d, "
           "%d solver iterations, allocations in steps %ld, %.1f of %.1f ms in the stage; pairs %d, active %d, "
           "passes %d\n",
           name, r->max_crossings, r->frames_crossing, r->proximity, r->impacts, r->zones, r->unresolved, r->rollbacks,
           r->iterations, r->step_allocs, r->ms_self, r->ms_total, r->pairs, r->pairs_active, r->pair_passes);
}

static double max_distance(const run_result* a, const run_result* b) {
    double d = 0.0;
    for (int i = 0; i < a->nv; ++i) {
        double s = 0.0;
        for (int k = 0; k < 3; ++k) s += pow(a->pos[3 * i + k] - b->pos[3 * i + k], 2);
        d = fmax(d, sqrt(s));
    }
    return d;
}

/* The self-contact pairs of a and b (found, active) within 5 % of each other, both nonzero. */
static int pairs_near(const run_result* a, const run_result* b) {
    return a->pairs > 0 && a->pairs_active > 0 && fabs((double)a->pairs - b->pairs) <= 0.05 * b->pairs &&
           fabs((double)a->pairs_active - b->pairs_active) <= 0.05 * b->pairs_active;
}

/* The upper sheet's lowest and mean height above the lower one (which is pinned at y = 0). */
static void upper_heights(const run_result* r, double* lowest, double* mean) {
    *lowest = HUGE_VAL;
    *mean = 0.0;
    for (int i = LN * LN; i < 2 * LN * LN; ++i) {
        *lowest = fmin(*lowest, r->pos[3 * i + 1]);
        *mean += r->pos[3 * i + 1] / (LN * LN);
    }
}

static void test_layers(void) {
    run_result gpu, cpu, off;
    run(WEFT_BACKEND_GPU, 0, 1, 30, &gpu);
    run(WEFT_BACKEND_CPU, 0, 1, 30, &cpu);
    run(WEFT_BACKEND_GPU, 0, 0, 30, &off);
    double glo, gmean, clo, cmean, olo, omean;
    upper_heights(&gpu, &glo, &gmean);
    upper_heights(&cpu, &clo, &cmean);
    upper_heights(&off, &olo, &omean);
    double dist = max_distance(&gpu, &cpu);
    printf("layers (%d vertices, 30 frames):\n", gpu.nv);
    print_run("GPU", &gpu);
    print_run("CPU", &cpu);
    print_run("GPU, no self-collision", &off);
    printf("  upper sheet above the lower: lowest %.2f mm, mean %.2f mm on the GPU; %.2f, %.2f on the CPU; "
           "%.1f, %.1f mm without; largest vertex distance GPU - CPU %.2e m (bound 1e-3)\n",
           1e3 * glo, 1e3 * gmean, 1e3 * clo, 1e3 * cmean, 1e3 * olo, 1e3 * omean, dist);
    CHECK_EQ_INT(gpu.failed, 0);
    CHECK_EQ_INT(gpu.frames_crossing, 0);
    CHECK_EQ_INT(gpu.unresolved, 0);
    /* the pairs held it, as on the CPU: the stage had what the CPU's had to correct */
    CHECK(pairs_near(&gpu, &cpu));
    CHECK(abs(gpu.pair_passes - cpu.pair_passes) <= 2 + cpu.pair_passes / 20);
    CHECK_EQ_INT(gpu.proximity + gpu.impacts, cpu.proximity + cpu.impacts);
    if (cpu.rollbacks == 0) CHECK_EQ_INT(gpu.rollbacks, 0);
    CHECK(gpu.ms_self > 0.0);
    CHECK_EQ_INT(gpu.step_allocs, 0);
    /* transfers: the GPU's idle proof on every substep (a 4-byte count read back), and where it
       could not show the stage idle the stage's run: 3 arrays of 16-byte texels read back; frame 1
       (the upper sheet falling, 4 cm above) moved nothing: every substep proved idle, no run;
       later runs uploaded spans of x and v where the stage moved something */
    printf("  GPU transfers: after frame 1: %lld runs of %lld substeps, %lld bytes read back, %lld uploaded; at the "
           "end: %lld runs of %lld substeps (%lld skipped), %lld bytes read back, %lld uploaded by %lld runs\n",
           gpu.io1[0], gpu.io1[4], gpu.io1[1], gpu.io1[2], gpu.io[0], gpu.io[4], gpu.io[5], gpu.io[1], gpu.io[2],
           gpu.io[3]);
    if (gpu.io[4] > 0) {   /* compute passes: the proof */
        CHECK(gpu.io1[4] >= 2 && gpu.io1[5] == gpu.io1[4] && gpu.io1[0] == 0 && gpu.io1[1] == 4LL * gpu.io1[4]);
        CHECK(gpu.io[0] + gpu.io[5] == gpu.io[4] + gpu.io[8] && gpu.io[0] > 0 && gpu.io[5] > 0);
    } else {   /* fragment passes: the stage every substep */
        CHECK(gpu.io1[0] >= 2 && gpu.io1[1] == 48LL * gpu.nv * gpu.io1[0] && gpu.io1[2] == 0);
    }
    CHECK(gpu.io[1] == 48LL * gpu.nv * gpu.io[0] + 4LL * gpu.io[4] && gpu.io[3] <= gpu.io[0]);
    CHECK(gpu.io[2] >= 32LL * gpu.io[3] && gpu.io[2] <= 32LL * gpu.nv * gpu.io[3]);
    CHECK_EQ_INT(cpu.frames_crossing, 0);
    CHECK(omean < 0.0);   /* without it the upper sheet falls through the lower */
    CHECK_EQ_INT(off.impacts + off.proximity, 0);
    /* resting on the lower sheet about 1.1 thickness (3.3 mm) above it, as on the CPU */
    CHECK(glo > 0.0 && gmean > 0.002 && gmean < 0.006);
    CHECK(fabs(gmean - cmean) < 2e-4 && fabs(glo - clo) < 2e-4);
    CHECK(dist < 1e-3);
}

static void heap_shape(const run_result* r, double* top, double* cy) {
    *top = -HUGE_VAL;
    *cy = 0.0;
    for (int i = 0; i < r->nv; ++i) {
        *top = fmax(*top, r->pos[3 * i + 1]);
        *cy += r->pos[3 * i + 1] / r->nv;
    }
}

static void test_heap(void) {
    run_result gpu, cpu;
    run(WEFT_BACKEND_GPU, 1, 1, 45, &gpu);
    run(WEFT_BACKEND_CPU, 1, 1, 45, &cpu);
    double gtop, gcy, ctop, ccy;
    heap_shape(&gpu, &gtop, &gcy);
    heap_shape(&cpu, &ctop, &ccy);
    printf("heap (%d vertices, 45 frames):\n", gpu.nv);
    print_run("GPU", &gpu);
    print_run("CPU", &cpu);
    printf("  top %.3f m, mean height %.3f m on the GPU; %.3f, %.3f m on the CPU (bounds 0.1 m, 0.03 m)\n", gtop, gcy,
           ctop, ccy);
    CHECK_EQ_INT(gpu.failed, 0);
    CHECK_EQ_INT(gpu.frames_crossing, 0);
    CHECK_EQ_INT(gpu.unresolved, 0);
    CHECK(gpu.impacts + gpu.proximity > 0);
    CHECK(gpu.pairs_active > 0 && gpu.pair_passes > 0);   /* the pairs in the solve, rechecked */
    CHECK_EQ_INT(cpu.frames_crossing, 0);
    CHECK(fabs(gtop - ctop) < 0.1);
    CHECK(fabs(gcy - ccy) < 0.03);
}

/* The layers with the other integrators and Newton (the pinned sheet is no collider: all run on
 * the GPU): BDF2 (the stage's corrections dv = dx / he with he = 2h/3), TR-BDF2 (the stage after
 * each of its two stages, stage 1's energy carried to stage 2's judge) and Newton 2 with the
 * line search: no crossing, no unresolved pair, no failed frame, the upper sheet resting on the
 * lower within 0.5 mm of the CPU's height, the pairs and the stage's impulses as the CPU's, its
 * rollbacks. */
static void test_methods(void) {
    static const struct { weft_integrator in; int newton, search; const char* name; } cases[] = {
        {WEFT_INTEGRATOR_BDF2, 1, 0, "BDF2"},
        {WEFT_INTEGRATOR_TRBDF2, 1, 0, "TR-BDF2"},
        {WEFT_INTEGRATOR_BACKWARD_EULER, 2, 1, "Newton 2 + line search"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        g_integrator = cases[k].in;
        g_newton = cases[k].newton;
        g_search = cases[k].search;
        run_result gpu, cpu;
        run(WEFT_BACKEND_GPU, 0, 1, 30, &gpu);
        run(WEFT_BACKEND_CPU, 0, 1, 30, &cpu);
        double glo, gmean, clo, cmean;
        upper_heights(&gpu, &glo, &gmean);
        upper_heights(&cpu, &clo, &cmean);
        printf("layers, %s, 30 frames:\n", cases[k].name);
        print_run("GPU", &gpu);
        print_run("CPU", &cpu);
        printf("  upper sheet: lowest %.2f mm, mean %.2f mm on the GPU; %.2f, %.2f on the CPU\n", 1e3 * glo,
               1e3 * gmean, 1e3 * clo, 1e3 * cmean);
        CHECK_EQ_INT(gpu.failed, 0);
        CHECK_EQ_INT(gpu.frames_crossing, 0);
        CHECK_EQ_INT(gpu.unresolved, 0);
        CHECK(glo > 0.0 && fabs(gmean - cmean) < 5e-4);
        CHECK(pairs_near(&gpu, &cpu));
        /* rechecked without Newton's iterations; Newton's systems take the pairs exactly instead */
        CHECK(abs(gpu.pair_passes - cpu.pair_passes) <= 2 + cpu.pair_passes / 20);
        if (cases[k].newton == 1) CHECK(gpu.pair_passes > 0);
        CHECK_EQ_INT(gpu.proximity + gpu.impacts, cpu.proximity + cpu.impacts);
        CHECK_EQ_INT(gpu.rollbacks, cpu.rollbacks);
    }
    g_integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
    g_newton = 1;
    g_search = 0;
}

/* A snapshot of the layers after 12 frames (the upper sheet landing) restores to the same bytes
 * and replays the next 13 frames bit-identically, the same self-contact pairs active in them. */
static void test_snapshot(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_GPU);
    CHECK(ctx != NULL);
    if (!ctx) return;
    ag_mesh m;
    layers(&m);
    weft_cloth_def d = method_def(&m, 1);
    weft_attachment_def att;
    pin_lower(&d, &att);
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &d, &c), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    size_t sz = info.snapshot_size;
    unsigned char *s12 = malloc(sz), *end1 = malloc(sz), *end2 = malloc(sz);
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    int impacts[2] = {0, 0};
    for (int pass = 0; pass < 2; ++pass) {
        int f0 = 0;
        if (pass == 1) {
            CHECK_EQ_INT(weft_cloth_restore(ctx, c, s12, sz), WEFT_OK);
            CHECK(ag_same_snapshot(ctx, c, s12, sz));
            f0 = 12;
        }
        for (int f = f0; f < 25; ++f) {
            if (pass == 0 && f == 12) CHECK_EQ_INT(weft_cloth_save(ctx, c, s12, sz), WEFT_OK);
            weft_frame_stats fs;
            CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, &fs), WEFT_OK);
            if (f >= 12) impacts[pass] += fs.self_impacts + fs.self_proximity + fs.self_pairs_active;
        }
        CHECK_EQ_INT(weft_cloth_save(ctx, c, pass == 0 ? end1 : end2, sz), WEFT_OK);
    }
    int same = memcmp(end1, end2, sz) == 0;
    printf("snapshot at frame 12, restored, run to 25: %s (%zu bytes; %d and %d stage impulses and active pairs "
           "after it)\n",
           same ? "bit-identical" : "DIFFERENT", sz, impacts[0], impacts[1]);
    CHECK(same);
    CHECK(impacts[0] > 0 && impacts[0] == impacts[1]);
    free(s12);
    free(end1);
    free(end2);
    weft_context_destroy(ctx);
    ag_free(&m);
}

/* The GPU's idle proof (gpu/solver/wg_self_idle.h, WEFT_GPU_SELF_IDLE): scene `scene` run with
 * the proof (r[0]), without it (r[1]: the stage every substep) and in its check mode (r[2]: the
 * stage run anyway where the proof said idle). The proof skips only runs that move nothing, so
 * all three end at the same bytes; the check mode finds no run it called idle that moved
 * something, and both kinds of substep occur (with `moves`, runs where the stage moved
 * something among those left to it, and substeps the back-off left untried). */
static void idle_case(const char* name, int scene, int frames, int moves) {
    static run_result r[3];
    static const char* modes[3] = {"on", "off", "check"};
    for (int k = 0; k < 3; ++k) {
        setenv("WEFT_GPU_SELF_IDLE", modes[k], 1);
        run(WEFT_BACKEND_GPU, scene, 1, frames, &r[k]);
    }
    unsetenv("WEFT_GPU_SELF_IDLE");
    const long long* on = r[0].io;
    const long long* chk = r[2].io;
    printf("%s, %d frames: proof: tried on %lld of %lld substeps (%lld untried, backing off), %lld skipped, %lld runs "
           "(%lld moved something), %lld bytes read back; without: %lld runs, "
           "%lld bytes read back; check: %lld runs proved idle rerun, %lld moved something, %lld runs left to the stage; "
           "same positions: %s, %s\n", name, frames, on[4], on[4] + on[8], on[8], on[5], on[0], on[3], on[1], r[1].io[0],
           r[1].io[1], chk[6],
           chk[7], chk[0] - chk[6], memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0 ? "yes" : "NO",
           memcmp(r[2].pos, r[1].pos, sizeof r[0].pos) == 0 ? "yes" : "NO");
    for (int k = 0; k < 3; ++k) CHECK_EQ_INT(r[k].failed, 0);
    CHECK(memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0);
    CHECK(memcmp(r[2].pos, r[1].pos, sizeof r[0].pos) == 0);
    CHECK_EQ_INT(r[0].impacts + r[0].proximity, r[1].impacts + r[1].proximity);
    const long long substeps = on[4] + on[8];
    CHECK(on[4] > 0 && on[5] > 0 && on[0] == substeps - on[5]);
    CHECK(r[1].io[4] == 0 && r[1].io[0] == substeps);   /* without the proof: a run every substep */
    /* the check mode tries every substep, so it proves at least what the back-off let be tried */
    CHECK(chk[8] == 0 && chk[7] == 0 && chk[6] >= on[5] && chk[0] == substeps);
    /* the back-off tries again after at most 8 substeps: it skips at least one idle substep in 9
       of those the check mode proved idle (each untried substep follows a failure) */
    CHECK(on[8] <= 8 * (on[4] - on[5]));
    CHECK(chk[0] - chk[6] > 0);   /* substeps the proof left to the stage */
    if (moves) CHECK(on[3] > 0 && on[8] > 0);   /* the stage acts in runs of substeps: the back-off waits */
}

static void test_idle(void) {
    idle_case("layers", 0, 30, 0);
    idle_case("heap", 1, 45, 1);
    g_drop = 0.6f;   /* a fast drop: the upper sheet lands at 3.4 m/s, 3 cm a substep */
    idle_case("layers dropped from 0.6 m", 0, 30, 0);
    g_drop = 0.04f;
    g_integrator = WEFT_INTEGRATOR_TRBDF2;   /* the stage after each of TR-BDF2's two stages */
    idle_case("layers, TR-BDF2", 0, 30, 0);
    g_integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
}

/* Core's proximity pass on the GPU's listed pairs (gpu/solver/wg_self_prox.h, WEFT_GPU_SELF_PROX)
 * against core's whole stage on the host: scene `scene` with the idle proof on, with the pass
 * (r[0]) and without it (r[1]). Where the pass settles a substep, the result is core's stage's on
 * the same input, so both end at the same bytes, with the same impulses and rollbacks; the pass
 * settled `settles` substeps or more, `moves` or more of them moving something (its impulses
 * applied on the listed pairs, the refined proof then holding). */
static void prox_case(const char* name, int scene, int frames, int settles, int moves) {
    static run_result r[2];
    setenv("WEFT_GPU_SELF_IDLE", "on", 1);
    for (int k = 0; k < 2; ++k) {
        setenv("WEFT_GPU_SELF_PROX", k == 0 ? "512" : "off", 1);   /* the most room */
        run(WEFT_BACKEND_GPU, scene, 1, frames, &r[k]);
    }
    unsetenv("WEFT_GPU_SELF_PROX");
    unsetenv("WEFT_GPU_SELF_IDLE");
    const long long *a = r[0].io, *b = r[1].io;
    printf("%s, %d frames: with the pass: %lld stage runs, %lld substeps settled by it (%lld moved something), %lld "
           "bytes read back, %lld uploaded, impulses %d, rollbacks %d; without: %lld runs, %lld skipped, %lld bytes read "
           "back, impulses %d, rollbacks %d; same positions: %s\n",
           name, frames, a[0], a[9], a[10], a[1], a[2], r[0].impacts + r[0].proximity, r[0].rollbacks, b[0], b[5], b[1],
           r[1].impacts + r[1].proximity, r[1].rollbacks, memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0 ? "yes" : "NO");
    for (int k = 0; k < 2; ++k) CHECK_EQ_INT(r[k].failed, 0);
    CHECK(memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0);
    CHECK_EQ_INT(r[0].impacts + r[0].proximity, r[1].impacts + r[1].proximity);
    CHECK_EQ_INT(r[0].rollbacks, r[1].rollbacks);
    CHECK_EQ_INT(r[0].max_crossings, r[1].max_crossings);
    CHECK(a[9] >= settles && a[10] >= moves);
    CHECK(b[9] == 0);   /* without the pass: none settled by it */
    CHECK(a[0] + a[5] <= b[0] + b[5]);   /* it only takes substeps off the host */
}

static void test_prox(void) {
    prox_case("layers", 0, 30, 0, 0);
    prox_case("heap", 1, 45, 1, 1);
}

/* The pass's two shortcuts against what they replace, on the heap (45 frames, room 512):
 * - the margin's proof (the listing walk proves too_far with a margin to spare, so a pass moving
 *   particles by at most half that needs no refined walk) against the
 *   refined walk after every moving pass (WEFT_GPU_SELF_PROX_REFINED=walk): the same bytes,
 *   impulses and host runs, as many moving passes proved either way;
 * - the energy judge's gain from the moved particles and their springs (their neighbours' x read
 *   back) against core's total energy difference on the whole state read back
 *   (WEFT_GPU_SELF_PROX_GAIN=both): within 1e-12 of the totals' size (the full difference's
 *   rounding) plus 1e-15 J, on at least one moving pass. */
static void test_prox_parts(void) {
    static run_result r[2];
    static long long xio[2][4];
    static double xg[2][3];
    setenv("WEFT_GPU_SELF_IDLE", "on", 1);
    setenv("WEFT_GPU_SELF_PROX", "512", 1);
    for (int k = 0; k < 2; ++k) {
        if (k == 1) setenv("WEFT_GPU_SELF_PROX_REFINED", "walk", 1);
        setenv("WEFT_GPU_SELF_PROX_GAIN", "both", 1);
        memset(g_xio, 0xff, sizeof g_xio);
        run(WEFT_BACKEND_GPU, 1, 1, 45, &r[k]);
        memcpy(xio[k], g_xio, sizeof g_xio);
        memcpy(xg[k], g_xgain, sizeof g_xgain);
    }
    unsetenv("WEFT_GPU_SELF_PROX_REFINED");
    unsetenv("WEFT_GPU_SELF_PROX_GAIN");
    unsetenv("WEFT_GPU_SELF_PROX");
    unsetenv("WEFT_GPU_SELF_IDLE");
    for (int k = 0; k < 2; ++k)
        printf("heap, 45 frames, %s: refined walks %lld, proved by the margin %lld, gains %lld local / %lld full, "
               "largest |local - full| %.3g J (|full| up to %.3g J, totals up to %.3g J), stage runs %lld, same "
               "positions: %s\n", k == 0 ? "the margin" : "the refined walk always", xio[k][0], xio[k][1],
               xio[k][2], xio[k][3], xg[k][0], xg[k][1], xg[k][2], r[k].io[0],
               memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0 ? "yes" : "NO");
    for (int k = 0; k < 2; ++k) CHECK_EQ_INT(r[k].failed, 0);
    CHECK(memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0);
    CHECK_EQ_INT(r[0].impacts + r[0].proximity, r[1].impacts + r[1].proximity);
    CHECK(r[0].io[0] == r[1].io[0] && r[0].io[9] == r[1].io[9]);
    /* the heap's one moving pass moves a particle by more than half the margin (also at 0.5 and
       0.9 thicknesses), so both runs walk; the margin's proof is exercised by the suit (bench) */
    CHECK(xio[1][1] == 0 && xio[1][0] >= 1 && xio[0][0] + xio[0][1] == xio[1][0]);
    for (int k = 0; k < 2; ++k) {
        CHECK(xio[k][2] >= 1 && xio[k][2] == xio[k][3]);
        CHECK(xg[k][1] > 0.0);
        CHECK(xg[k][0] <= 1e-12 * xg[k][2] + 1e-15);
    }
}

/* The self pairs found on the GPU (r[0]) and by core on the host (r[1]): the same lists, so the
 * same bytes at the end (a float bound of 0), rollbacks, pairs and stage impulses; the GPU's
 * finder found every substep's (none left to core for want of room). */
static void pairs_case(const char* name, int scene, int frames) {
    static run_result r[2];
    static const char* modes[2] = {"gpu", "host"};
    for (int k = 0; k < 2; ++k) {
        setenv("WEFT_GPU_SELF_PAIRS", modes[k], 1);
        run(WEFT_BACKEND_GPU, scene, 1, frames, &r[k]);
    }
    unsetenv("WEFT_GPU_SELF_PAIRS");
    const long long* p = r[0].pio;
    const double dist = max_distance(&r[0], &r[1]);
    printf("%s, %d frames: GPU finder: %lld substeps (%lld by core), %lld candidates, %lld bytes read back (%.0f a "
           "substep); pairs %d / %d, active %d / %d, rollbacks %d / %d, impulses %d / %d (GPU / host); positions "
           "%s (max distance %.3g m)\n",
           name, frames, p[0], p[1], p[2], p[3], p[0] > 0 ? (double)p[3] / (double)p[0] : 0.0, r[0].pairs, r[1].pairs,
           r[0].pairs_active, r[1].pairs_active, r[0].rollbacks, r[1].rollbacks, r[0].impacts + r[0].proximity,
           r[1].impacts + r[1].proximity, memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0 ? "the same" : "DIFFER",
           dist);
    for (int k = 0; k < 2; ++k) CHECK_EQ_INT(r[k].failed, 0);
    CHECK(memcmp(r[0].pos, r[1].pos, sizeof r[0].pos) == 0);
    CHECK(dist <= 0.0);
    CHECK_EQ_INT(r[0].rollbacks, r[1].rollbacks);
    CHECK_EQ_INT(r[0].pairs, r[1].pairs);
    CHECK_EQ_INT(r[0].pairs_active, r[1].pairs_active);
    CHECK_EQ_INT(r[0].impacts + r[0].proximity, r[1].impacts + r[1].proximity);
    CHECK(r[0].pairs > 0 && r[0].pairs_active > 0);
    CHECK(p[0] > 0 && p[1] == 0 && p[2] >= r[0].pairs && p[3] == 4 * p[0] + 8 * p[2]);
    CHECK(r[1].pio[0] == -1);   /* the host's: no finder */
}

static void test_pairs(void) {
    pairs_case("layers", 0, 30);
    pairs_case("heap", 1, 45);
    setenv("WEFT_GPU_SELF_PAIRS", "gpu", 1);
    test_snapshot();
    unsetenv("WEFT_GPU_SELF_PAIRS");
}

/* -1: on for a garment (here a cloth with a seam), off for a plain cloth, as on the CPU. */
static void test_default(void) {
    weft_context* ctx = make_ctx(WEFT_BACKEND_GPU);
    CHECK(ctx != NULL);
    if (!ctx) return;
    ag_mesh m;
    layers(&m);
    static const int sa[1] = {0}, sb[1] = {LN * LN};
    for (int k = 0; k < 2; ++k) {
        weft_cloth_def d = method_def(&m, -1);
        if (k == 1) {
            d.seam_a = sa;
            d.seam_b = sb;
            d.n_seams = 1;
        }
        weft_cloth c;
        CHECK_EQ_INT(weft_cloth_create(ctx, &d, &c), WEFT_OK);
        weft_cloth_info info;
        CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
        CHECK_EQ_INT(info.self_collision, k);
        CHECK_EQ_INT(weft_cloth_destroy(ctx, c), WEFT_OK);
    }
    weft_context_destroy(ctx);
    ag_free(&m);
}

int main(int argc, char** argv) {
    weft_context* probe = make_ctx(WEFT_BACKEND_GPU);
    if (!probe) {
        printf("no GPU context: skipped\n");
        return 0;
    }
    weft_context_destroy(probe);
    if (argc > 1 && strcmp(argv[1], "pairs") == 0) {   /* test_api_gpu_self_pairs */
        RUN_TEST(test_pairs);
        return TEST_SUMMARY();
    }
    if (argc > 1 && strcmp(argv[1], "prox") == 0) {   /* test_api_gpu_self_prox */
        RUN_TEST(test_prox);
        RUN_TEST(test_prox_parts);
        return TEST_SUMMARY();
    }
    if (argc > 1 && strcmp(argv[1], "idle") == 0) {   /* test_api_gpu_self_idle */
        RUN_TEST(test_idle);
        return TEST_SUMMARY();
    }
    RUN_TEST(test_default);
    RUN_TEST(test_layers);
    RUN_TEST(test_heap);
    RUN_TEST(test_methods);
    RUN_TEST(test_snapshot);
    return TEST_SUMMARY();
}
