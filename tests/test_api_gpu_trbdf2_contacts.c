/* TR-BDF2 on a cloth with colliders, GPU backend through the public API (real EGL: llvmpipe
 * without a GPU), GPU against CPU with the GPU's method on both (PCG with block Jacobi, Newton 2
 * with the line search, no self-collision): a 12 x 12 sheet dropped on a plane tilted by 15 degrees
 * with friction 0.5 (it lands and stops), on a capsule sliding along its axis 1 cm a frame (the
 * collider's velocity), and on an icosphere mesh collider. Both stages land their contacts on the
 * shells (core/bdf2.c wc_integ_contacts) and stage 1's contact impulses are held into stage 2's
 * release (wc_integ_contact_impulses) on both backends. Measured: the largest vertex distance
 * GPU - CPU at the end against the CPU's own TR-BDF2 - backward Euler difference, the deepest
 * vertex behind the collider, rollbacks (0 on the GPU where the CPU has 0), contacts at the end;
 * the bounds are the CPU's own spread when its collider moves by 0.1 mm.
 * A snapshot taken mid-run with contacts held replays bit-identically. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "api_grid.h"
#include "check.h"
#include "test_meshes.h"

#define N 12
#define DT (1.0 / 30.0)
#define FRAMES 45

static ag_mesh g_sheet;
static tmesh g_tm;
static float g_body[3 * 2600];
static weft_collider_def g_col;
static weft_mesh_collider_def g_mesh;

/* The capsule's transform at frame f: lying along x (rotated about z), its axis 0.25 m below the
 * sheet's plane, sliding along its axis 1 cm a frame (friction carries the sheet along). Rising
 * instead, the sheet balanced on it tips to one side or the other: TR-BDF2 at Newton 2 on the CPU
 * alone ends 0.13 m apart with the capsule's radius moved by 0.3 mm (backward Euler: 0.5 mm), so
 * that scene bounds nothing; the contact rule's normal collider motion is compared pass by pass
 * (test_gpu_trbdf2_contacts.c). */
static void capsule_at(int f, float* T) {
    ag_transform(T, 0, 0, 1, 0.5 * 3.14159265358979323846, 0.01 * f, 0.25, 0.0);
}

/* scene 0: the tilted plane; 1: the sliding capsule; 2: the icosphere mesh. Friction 0.5. */
static weft_cloth_def sheet_def(int scene, weft_integrator integ) {
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&g_sheet);
    if (scene != 2) {
        g_col = weft_default_collider_def();
        g_col.friction = 0.5;
        if (scene == 0) {
            g_col.type = WEFT_COLLIDER_PLANE;
            ag_transform(g_col.transform, 0, 0, 1, 15.0 * 3.14159265358979323846 / 180.0, 0.0, 0.0, 0.0);
        } else {
            g_col.type = WEFT_COLLIDER_CAPSULE;
            g_col.radius = 0.15;
            g_col.half_height = 0.3;
            capsule_at(0, g_col.transform);
        }
        def.colliders = &g_col;
        def.n_colliders = 1;
    } else {
        double c[3] = {0.0, 0.0, 0.0};
        icosphere(&g_tm, 2, 0.3, c);
        for (int i = 0; i < 3 * g_tm.nv; ++i) g_body[i] = (float)g_tm.x[i];
        g_mesh = weft_default_mesh_collider_def();
        g_mesh.mesh.positions = g_body;
        g_mesh.mesh.n_vertices = g_tm.nv;
        g_mesh.mesh.indices = g_tm.t;
        g_mesh.mesh.n_faces = g_tm.nt;
        g_mesh.friction = 0.5;
        def.mesh_colliders = &g_mesh;
        def.n_mesh_colliders = 1;
    }
    def.solver = WEFT_SOLVER_PCG;
    def.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    def.integrator = integ;
    def.newton_iterations = 2;
    def.line_search = 1;
    def.self_collision = 0;
    return def;
}

/* One frame of scene `scene` at frame f (the capsule's transform). */
static weft_status step(weft_context* ctx, weft_cloth c, int scene, int f, weft_frame_stats* fs) {
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    float T[16];
    if (scene == 1) {
        capsule_at(f + 1, T);
        fr.collider_transforms = T;
    }
    return weft_cloth_step(ctx, c, &fr, fs);
}

typedef struct run_result {
    float pos[3 * N * N];
    double depth;   /* m: deepest behind the collider over the frames */
    int rollbacks, contacts, ok;
} run_result;

static void run(weft_backend backend, int scene, weft_integrator integ, run_result* r) {
    memset(r, 0, sizeof *r);
    weft_context* ctx = ap_try_context(backend);
    CHECK(ctx != NULL);
    if (!ctx) return;
    weft_cloth_def def = sheet_def(scene, integ);
    weft_cloth c;
    weft_status st = weft_cloth_create(ctx, &def, &c);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) {
        printf("  create: %s\n", weft_context_last_error(ctx));
        weft_context_destroy(ctx);
        return;
    }
    weft_frame_stats fs;
    int count = 0;
    for (int f = 0; f < FRAMES; ++f) {
        st = step(ctx, c, scene, f, &fs);
        CHECK_EQ_INT(st, WEFT_OK);
        if (st != WEFT_OK) break;
        r->rollbacks += fs.rollbacks;
        weft_collision_check chk;
        CHECK_EQ_INT(weft_cloth_check_collisions(ctx, c, &chk), WEFT_OK);
        r->depth = fmax(r->depth, chk.max_penetration);
    }
    r->contacts = fs.contacts;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, r->pos, NULL, N * N, &count), WEFT_OK);
    r->ok = st == WEFT_OK;
    weft_context_destroy(ctx);
}

static double distance(const run_result* a, const run_result* b) { return ag_max_distance(a->pos, b->pos, N * N); }

static void test_vs_cpu(void) {
    static const char* names[] = {"tilted plane", "sliding capsule", "icosphere mesh"};
    /* bounds: float against double solvers to the same tolerance, contacts and line searches
       decided at thresholds. The CPU alone with its collider moved by 0.1 mm (the plane along y,
       the capsule's radius, the mesh's thickness) ends 1.0 cm, 4.4 mm and 2.1 cm from itself, so
       each bound is about that, and a quarter of what separates TR-BDF2 from backward Euler on
       the CPU: the GPU follows TR-BDF2's rules, not backward Euler's */
    static const double bound[] = {0.015, 0.01, 0.03};
    for (int k = 0; k < 3; ++k) {
        static run_result cpu, gpu, cpu_be;
        run(WEFT_BACKEND_CPU, k, WEFT_INTEGRATOR_TRBDF2, &cpu);
        run(WEFT_BACKEND_GPU, k, WEFT_INTEGRATOR_TRBDF2, &gpu);
        run(WEFT_BACKEND_CPU, k, WEFT_INTEGRATOR_BACKWARD_EULER, &cpu_be);
        if (!cpu.ok || !gpu.ok || !cpu_be.ok) continue;
        double d = distance(&cpu, &gpu), dbe = distance(&cpu, &cpu_be);
        printf("  TR-BDF2, sheet dropped on the %s, %d frames: GPU - CPU %.3g m (the CPU's TR-BDF2 - backward Euler: "
               "%.3g m); deepest behind the collider GPU %.3g m, CPU %.3g m; rollbacks GPU %d, CPU %d; in contact GPU "
               "%d, CPU %d\n",
               names[k], FRAMES, d, dbe, gpu.depth, cpu.depth, gpu.rollbacks, cpu.rollbacks, gpu.contacts,
               cpu.contacts);
        CHECK(d < bound[k]);
        CHECK(d < 0.25 * dbe);
        CHECK(gpu.depth < 1e-3);
        if (cpu.rollbacks == 0) CHECK_EQ_INT(gpu.rollbacks, 0);
        CHECK(gpu.contacts > 0);
        CHECK(abs(gpu.contacts - cpu.contacts) <= cpu.contacts / 10 + 2);
    }
}

static weft_status capsule_frame(weft_context* ctx, weft_cloth c, int f, weft_frame_stats* fs, void* user) {
    (void)user;
    return step(ctx, c, 1, f, fs);
}

/* A snapshot after 10 frames on the sliding capsule (contacts held, the collider moving) restores
 * to the same bytes and replays bit-identically to frame 25. */
static void test_snapshot(void) {
    weft_context* ctx = ap_try_context(WEFT_BACKEND_GPU);
    CHECK(ctx != NULL);
    if (!ctx) return;
    weft_cloth_def def = sheet_def(1, WEFT_INTEGRATOR_TRBDF2);
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    ag_replay r = ag_snapshot_replay(ctx, c, 10, 25, NULL, capsule_frame, NULL);
    printf("  TR-BDF2: snapshot at frame 10 (%d particles in contact), restored, run to 25: %s (%zu bytes)\n",
           r.before.contacts, r.same ? "bit-identical" : "DIFFERENT", r.bytes);
    CHECK(r.ok);
    CHECK(r.restored_same);
    CHECK(r.before.contacts > 0);
    CHECK(r.same);
    weft_context_destroy(ctx);
}

int main(void) {
    if (!ap_gpu_here()) {
        printf("no GPU context here: skipped\n");
        return 0;
    }
    ag_grid(&g_sheet, N, 1.0, 0.5, 0, 0);
    RUN_TEST(test_vs_cpu);
    RUN_TEST(test_snapshot);
    ag_free(&g_sheet);
    return TEST_SUMMARY();
}
