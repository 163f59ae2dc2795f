/* Snapshots through the public API: save at frame 10, run to 30; restore (into the same cloth and
 * into a fresh one of the same def, in another context), run to 30 again: bit-identical, with a
 * moving attachment, a moving collider in contact, object inertia, wind changes and frames that
 * leave transforms unchanged, for each solver (Chebyshev keeps a cached spectral-radius estimate,
 * PCG and Jacobi a warm start, the multigrid its carried eigenvalue estimates, the direct solver
 * neither). Snapshots of other models are refused
 * with SNAPSHOT_MISMATCH, damaged or truncated ones with INVALID_ARGUMENT. */
#include <stdint.h>
#include "api_grid.h"
#include "check.h"

#define N 10
#define DT (1.0 / 60.0)

static ag_mesh g_mesh;
static int g_corners[4];
static weft_attachment_def g_att;
static weft_collider_def g_col;

/* integrator, Newton iterations and line search of the next scene_def */
static weft_integrator g_integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
static int g_newton = 1, g_line_search = 0;
static weft_preconditioner g_precond = WEFT_PRECOND_DEFAULT;

static weft_cloth_def scene_def(weft_solver solver) {
    g_corners[0] = 0;
    g_corners[1] = N - 1;
    g_corners[2] = N * (N - 1);
    g_corners[3] = N * N - 1;
    g_att = weft_default_attachment_def();
    g_att.vertices = g_corners;
    g_att.n_vertices = 4;
    g_col = weft_default_collider_def();
    g_col.radius = 0.3;
    g_col.friction = 0.4;
    ag_transform(g_col.transform, 1, 0, 0, 0.0, 0.05, -0.4, 0.0);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&g_mesh);
    def.n_attachments = 1;
    def.attachments = &g_att;
    def.n_colliders = 1;
    def.colliders = &g_col;
    def.solver = solver;
    def.linear_inertia = 0.5;
    def.angular_inertia = 0.5;
    def.substeps = 2;
    def.integrator = g_integrator;
    def.newton_iterations = g_newton;
    def.line_search = g_line_search;
    def.preconditioner = g_precond;
    return def;
}

/* Frame f's inputs (a function of f only). Some frames leave things unchanged (NULL). */
static weft_status frame(weft_context* ctx, weft_cloth c, int f, weft_frame_stats* st) {
    double t = f * DT;
    float obj[16], bone[16], sphere[16];
    double wind[3] = {2.0 * sin(t), 0.0, 1.0};
    ag_transform(obj, 0, 1, 0, 0.4 * t, 0.2 * t * t, 0.0, 0.0);
    ag_transform(bone, 0, 0, 1, 0.3 * sin(2 * t), 0.1 * sin(3 * t), 0.05 * t, 0.0);
    /* the sphere rises into the sheet, rests there (frames 8..14), rises again */
    double cy = -0.4 + 2.25 * fmin(t, 8 * DT) + 0.5 * fmax(0.0, t - 14 * DT);
    ag_transform(sphere, 1, 0, 0, 0.0, 0.05, cy, 0.0);
    weft_frame fr = weft_default_frame();
    fr.dt = DT;
    fr.object_transform = obj;
    fr.attachment_transforms = f % 4 == 3 ? NULL : bone;
    fr.collider_transforms = f % 3 == 1 ? NULL : sphere;
    fr.wind = f % 5 == 0 ? wind : NULL;
    fr.flags = f == 6 ? WEFT_FRAME_TELEPORT : 0;
    weft_status s = weft_cloth_step(ctx, c, &fr, st);
    if (s != WEFT_OK) fprintf(stderr, "frame %d: %s\n", f, weft_context_last_error(ctx));
    return s;
}

static weft_context* new_ctx(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 2;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

static void run_solver(weft_solver solver, const char* name) {
    weft_cloth_def def = scene_def(solver);
    weft_context* ctx = new_ctx();
    weft_cloth c;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &c), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    size_t sz = info.snapshot_size;
    unsigned char *s10 = malloc(sz), *end1 = malloc(sz), *end2 = malloc(sz), *end3 = malloc(sz);
    int contacts = 0;
    weft_frame_stats st;
    for (int f = 1; f <= 10; ++f) CHECK_EQ_INT(frame(ctx, c, f, &st), WEFT_OK);
    int contacts_at_save = st.contacts;
    CHECK_EQ_INT(weft_cloth_save(ctx, c, s10, sz), WEFT_OK);
    for (int f = 11; f <= 30; ++f) {
        CHECK_EQ_INT(frame(ctx, c, f, &st), WEFT_OK);
        if (st.contacts > contacts) contacts = st.contacts;
    }
    CHECK_EQ_INT(weft_cloth_save(ctx, c, end1, sz), WEFT_OK);
    int n = info.n_vertices;
    float *p1 = malloc(sizeof(float) * 3 * n), *p2 = malloc(sizeof(float) * 3 * n);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, p1, NULL, n, &n), WEFT_OK);

    /* restore into the same cloth */
    CHECK_EQ_INT(weft_cloth_restore(ctx, c, s10, sz), WEFT_OK);
    for (int f = 11; f <= 30; ++f) CHECK_EQ_INT(frame(ctx, c, f, &st), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, end2, sz), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, c, WEFT_SPACE_WORLD, p2, NULL, n, &n), WEFT_OK);
    CHECK(memcmp(end1, end2, sz) == 0);
    CHECK(memcmp(p1, p2, sizeof(float) * 3 * n) == 0);
    CHECK(st.frame == 30);

    /* into a fresh cloth of the same def in another context (its Chebyshev rho cache is empty
       before the restore: without the cached value in the snapshot it would estimate another) */
    weft_context* ctx2 = new_ctx();
    weft_cloth c2;
    CHECK_EQ_INT(weft_cloth_create(ctx2, &def, &c2), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(ctx2, c2, s10, sz), WEFT_OK);
    for (int f = 11; f <= 30; ++f) CHECK_EQ_INT(frame(ctx2, c2, f, &st), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(ctx2, c2, end3, sz), WEFT_OK);
    CHECK(memcmp(end1, end3, sz) == 0);

    /* the run really differs from a cloth that was not restored (the state carries) */
    CHECK(memcmp(s10 + 64, end1 + 64, sz - 64) != 0);
    printf("  %-9s snapshot %zu bytes, %d contacts at the save, up to %d after, restored runs bit-identical: %s\n", name, sz, contacts_at_save, contacts,
           memcmp(end1, end2, sz) == 0 && memcmp(end1, end3, sz) == 0 ? "yes" : "NO");
    CHECK(contacts_at_save > 0);
    CHECK(contacts > 0);
    weft_context_destroy(ctx);
    weft_context_destroy(ctx2);
    free(s10);
    free(end1);
    free(end2);
    free(end3);
    free(p1);
    free(p2);
}

static void test_restore_bit_identical(void) {
    run_solver(WEFT_SOLVER_PCG, "pcg");
    run_solver(WEFT_SOLVER_CHEBYSHEV, "chebyshev");
    run_solver(WEFT_SOLVER_JACOBI, "jacobi");
    run_solver(WEFT_SOLVER_DIRECT, "direct");
    /* BDF2: the snapshot holds the history (a fresh cloth has none: without it the restored
       run would take a backward-Euler substep first), carried by the inertia and reset by the
       teleport of frame 6; with Newton iterations and line search on top */
    g_integrator = WEFT_INTEGRATOR_BDF2;
    run_solver(WEFT_SOLVER_PCG, "bdf2");
    g_newton = 2;
    g_line_search = 1;
    run_solver(WEFT_SOLVER_PCG, "bdf2+nwt");
    /* TR-BDF2: one-step, nothing beyond x and v to save (core/bdf2.h) */
    g_integrator = WEFT_INTEGRATOR_TRBDF2;
    run_solver(WEFT_SOLVER_PCG, "trbdf2+nwt");
    g_newton = 1;
    g_line_search = 0;
    run_solver(WEFT_SOLVER_PCG, "trbdf2");
    g_integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
    g_newton = 1;
    g_line_search = 0;
    /* the multigrid: a substep's first solve may take an earlier substep's eigenvalue estimates
       (core/amg.h bound_carry), so the snapshot holds them (a fresh cloth has none: without them
       the restored run would estimate afresh at frame 11) */
    g_precond = WEFT_PRECOND_AMG;
    g_newton = 2;
    g_line_search = 1;
    run_solver(WEFT_SOLVER_PCG, "pcg+amg");
    g_precond = WEFT_PRECOND_DEFAULT;
    g_newton = 1;
    g_line_search = 0;
}

/* Other models: refused with SNAPSHOT_MISMATCH; damaged / truncated: INVALID_ARGUMENT. */
static void test_refused(void) {
    weft_context* ctx = new_ctx();
    weft_cloth_def def = scene_def(WEFT_SOLVER_PCG);
    weft_cloth a;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &a), WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, a, &info), WEFT_OK);
    size_t sz = info.snapshot_size;
    unsigned char* snap = malloc(sz + 16);
    for (int f = 1; f <= 5; ++f) CHECK_EQ_INT(frame(ctx, a, f, NULL), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(ctx, a, snap, sz), WEFT_OK);

    /* other models */
    struct {
        const char* what;
        weft_cloth_def def;
    } others[4];
    for (int k = 0; k < 4; ++k) others[k].def = scene_def(WEFT_SOLVER_PCG);
    ag_mesh bigger;
    ag_grid(&bigger, N + 1, 1.0, 0.0, 0, 0);
    others[0].what = "other mesh";
    others[0].def.mesh = ag_desc(&bigger);
    others[1].what = "other material";
    others[1].def.material.stiffness[0] *= 2;
    others[2].what = "other attachments";
    others[2].def.n_attachments = 0;
    others[3].what = "other colliders";
    others[3].def.n_colliders = 0;
    for (int k = 0; k < 4; ++k) {
        weft_cloth b;
        CHECK_EQ_INT(weft_cloth_create(ctx, &others[k].def, &b), WEFT_OK);
        weft_status st = weft_cloth_restore(ctx, b, snap, sz);
        if (st != WEFT_ERROR_SNAPSHOT_MISMATCH) fprintf(stderr, "%s: status %d\n", others[k].what, (int)st);
        CHECK_EQ_INT(st, WEFT_ERROR_SNAPSHOT_MISMATCH);
        CHECK(strstr(weft_context_last_error(ctx), "another model") != NULL);
        CHECK_EQ_INT(weft_cloth_destroy(ctx, b), WEFT_OK);
    }
    /* a different solver or inertia is the same model: accepted */
    weft_cloth_def same = scene_def(WEFT_SOLVER_CHEBYSHEV);
    same.linear_inertia = 1.0;
    weft_cloth b;
    CHECK_EQ_INT(weft_cloth_create(ctx, &same, &b), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(ctx, b, snap, sz), WEFT_OK);

    /* truncated, damaged anywhere (header or payload), another version */
    CHECK_EQ_INT(weft_cloth_restore(ctx, a, snap, sz - 1), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_restore(ctx, a, snap, 12), WEFT_ERROR_INVALID_ARGUMENT);
    size_t where[5] = {0, 20, 30, 100, sz - 3};
    for (int k = 0; k < 5; ++k) {
        snap[where[k]] ^= 0x10;
        CHECK_EQ_INT(weft_cloth_restore(ctx, a, snap, sz), WEFT_ERROR_INVALID_ARGUMENT);
        snap[where[k]] ^= 0x10;
    }
    snap[8] ^= 1;   /* the ABI field */
    CHECK_EQ_INT(weft_cloth_restore(ctx, a, snap, sz), WEFT_ERROR_SNAPSHOT_MISMATCH);
    snap[8] ^= 1;
    CHECK_EQ_INT(weft_cloth_restore(ctx, a, snap, sz + 16), WEFT_OK);   /* a larger buffer is fine */
    free(snap);
    ag_free(&bigger);
    weft_context_destroy(ctx);
}

int main(void) {
    ag_grid(&g_mesh, N, 1.0, 0.0, 0, 0);
    RUN_TEST(test_restore_bit_identical);
    RUN_TEST(test_refused);
    ag_free(&g_mesh);
    return TEST_SUMMARY();
}
