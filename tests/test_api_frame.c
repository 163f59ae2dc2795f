/* The public API (libweft.so, weft.h) driven as a host would, checked against core run directly
 * and against the geometry it must reproduce: identical positions to a core run, pinned vertices
 * exactly on their moving bones, host vertex order, normals, inertia, teleport, reset, colliders,
 * two interleaved contexts, no allocation in a step, errors reaching the logger. */
#include <stdint.h>
#include "api_grid.h"
#include "check.h"
#include "model.h"
#include "state.h"
#include "step.h"

#define N 8
#define SIZE 0.5
#define DT (1.0 / 60.0)

static weft_context* new_context(ag_log* log, ag_alloc_counter* counter) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    if (log) {
        cd.log = ag_log_fn;
        cd.log_user = log;
    }
    if (counter) {
        cd.allocator.alloc = ag_count_alloc;
        cd.allocator.free = ag_count_free;
        cd.allocator.user = counter;
    }
    weft_context* ctx = NULL;
    weft_status st = weft_context_create(WEFT_ABI, &cd, &ctx);
    CHECK_EQ_INT(st, WEFT_OK);
    return ctx;
}

/* A hanging sheet, its two top corners pinned to one attachment (identity bind). */
static weft_cloth hanging(weft_context* ctx, const ag_mesh* m, weft_cloth_def* def_out) {
    static int corners[2];
    corners[0] = 0 + m->n * (m->n - 1);
    corners[1] = (m->n - 1) + m->n * (m->n - 1);
    static weft_attachment_def att;
    att = weft_default_attachment_def();
    att.vertices = corners;
    att.n_vertices = 2;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(m);
    def.n_attachments = 1;
    def.attachments = &att;
    weft_cloth cloth = {0};
    weft_status st = weft_cloth_create(ctx, &def, &cloth);
    if (st != WEFT_OK) fprintf(stderr, "create: %s\n", weft_context_last_error(ctx));
    CHECK_EQ_INT(st, WEFT_OK);
    if (def_out) *def_out = def;
    return cloth;
}

/* Same sheet through core: model, state, pins at the rest positions of the corners. */
static void test_core_equivalence(void) {
    ag_mesh m;
    ag_grid(&m, N, SIZE, 1.0, 1, 0);
    weft_context* ctx = new_context(NULL, NULL);
    weft_cloth_def def;
    weft_cloth cloth = hanging(ctx, &m, &def);
    /* the CPU's defaults, as weft_cloth_get_info reports them (64 particles: IC(0), every solve
       to a tolerance of 1e-3) */
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    CHECK_EQ_INT(info.preconditioner, WEFT_PRECOND_IC0);
    CHECK(info.newton_forcing == 0.0);
    CHECK(info.tolerance == 1e-3);
    CHECK_EQ_INT(info.integrator, WEFT_INTEGRATOR_BACKWARD_EULER);
    CHECK_EQ_INT(info.newton_iterations, 2);
    CHECK_EQ_INT(info.line_search, 1);

    double* pos = malloc(sizeof(double) * 3 * m.nv);
    for (int i = 0; i < 3 * m.nv; ++i) pos[i] = m.pos[i];
    wc_source_mesh src;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, m.nv, m.sizes, m.nf, m.idx, 1.0, &d), WEFT_OK);
    wc_model model;
    wc_model_def md = wc_default_model_def();
    CHECK_EQ_INT(wc_model_build(&model, &src, &md, NULL, &d), WEFT_OK);
    wc_sim_def sd = wc_default_sim_def();
    sd.threads = 1;
    sd.max_colliders = 0;
    /* the CPU backend's defaults (core/cloth_cpu.c, resolved by plugin/cloth_create.c) */
    sd.solver.preconditioner = WC_PRECOND_IC0;
    sd.newton_forcing = 0.0;
    sd.solver.tolerance = 1e-3;
    sd.newton_iterations = 2;
    sd.line_search = 1;
    wc_state* s = NULL;
    CHECK_EQ_INT(wc_state_create(&s, &model, &sd, NULL, &d), WEFT_OK);
    wc_pin pins[2];
    int corner_host[2] = {N * (N - 1), N - 1 + N * (N - 1)};
    for (int k = 0; k < 2; ++k) {
        memset(&pins[k], 0, sizeof pins[k]);
        pins[k].particle = model.host_to_particle[corner_host[k]];
        memcpy(pins[k].target, model.rest_pos + 3 * pins[k].particle, sizeof pins[k].target);
    }
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &d), WEFT_OK);

    float* out = malloc(sizeof(float) * 3 * m.nv);
    int same = 1;
    for (int f = 0; f < 40; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = DT;
        CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(wc_step_frame(s, DT, NULL, &d), WEFT_OK);
        int count = 0;
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, out, NULL, m.nv, &count), WEFT_OK);
        CHECK_EQ_INT(count, m.nv);
        for (int v = 0; v < m.nv; ++v)
            for (int k = 0; k < 3; ++k)
                if (out[3 * v + k] != (float)s->x[3 * model.host_to_particle[v] + k]) same = 0;
    }
    CHECK(same);
    /* it moved: the top edge sags between the pinned corners */
    CHECK(s->x[3 * model.host_to_particle[N / 2 + N * (N - 1)] + 1] < 1.0 - 1e-4);
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_vertices, m.nv);
    CHECK_EQ_INT(info.n_particles, model.n_particles);
    CHECK_EQ_INT(info.n_triangles, model.n_tris);
    CHECK_EQ_INT(info.n_pinned_particles, 2);
    CHECK_EQ_INT(info.n_attachments, 1);
    CHECK_EQ_INT(info.backend, WEFT_BACKEND_CPU);
    CHECK_NEAR(info.total_mass, 0.15 * SIZE * SIZE, 1e-12);
    CHECK(info.snapshot_size > 0);
    free(out);
    free(pos);
    wc_state_destroy(s);
    wc_model_free(&model);
    wc_source_mesh_free(&src);
    CHECK_EQ_INT(weft_cloth_destroy(ctx, cloth), WEFT_OK);
    weft_context_destroy(ctx);
    ag_free(&m);
}

/* A bone that translates and rotates: the pinned vertices sit on bone x local at every frame. */
static void test_moving_bone(void) {
    ag_mesh m;
    ag_grid(&m, N, SIZE, 1.0, 1, 0);
    weft_context* ctx = new_context(NULL, NULL);
    int top[N];
    for (int i = 0; i < N; ++i) top[i] = i + N * (N - 1);
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = top;
    att.n_vertices = N;
    ag_transform(att.bind_transform, 0, 1, 0, 0.3, 0.1, 1.0, 0.0);   /* the bone at bind time */
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    def.n_attachments = 1;
    def.attachments = &att;
    weft_cloth cloth;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    /* local binding of each top vertex: B^-1 (rest position), computed here independently */
    double local[N][3];
    for (int i = 0; i < N; ++i) {
        const float* B = att.bind_transform;
        double p[3] = {m.pos[3 * top[i]], m.pos[3 * top[i] + 1], m.pos[3 * top[i] + 2]};
        double d[3] = {p[0] - B[12], p[1] - B[13], p[2] - B[14]};
        for (int r = 0; r < 3; ++r) local[i][r] = B[4 * r] * d[0] + B[4 * r + 1] * d[1] + B[4 * r + 2] * d[2]; /* R^T d */
    }
    float* out = malloc(sizeof(float) * 3 * m.nv);
    double worst = 0.0;
    for (int f = 1; f <= 60; ++f) {
        float bone[16];
        double t = f * DT;
        ag_transform(bone, 0.6, 0.8, 0.0, 0.3 + 1.5 * t, 0.1 + 0.4 * t, 1.0 + 0.2 * sin(4 * t), 0.3 * t);
        weft_frame fr = weft_default_frame();
        fr.dt = DT;
        fr.attachment_transforms = bone;
        CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, NULL), WEFT_OK);
        int count;
        CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, out, NULL, m.nv, &count), WEFT_OK);
        for (int i = 0; i < N; ++i) {
            double want[3];
            ag_apply(bone, local[i], want);
            for (int k = 0; k < 3; ++k) worst = fmax(worst, fabs(out[3 * top[i] + k] - want[k]));
        }
    }
    printf("  moving bone: worst pinned-vertex error %.3g m\n", worst);
    CHECK(worst < 2e-6);
    free(out);
    weft_context_destroy(ctx);
    ag_free(&m);
}

/* Flat horizontal sheet: normals +Y (counter-clockwise from above), triangles as host indices. */
static void test_normals_triangles(void) {
    ag_mesh m;
    ag_grid(&m, N, SIZE, 0.0, 0, 0);
    weft_context* ctx = new_context(NULL, NULL);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    weft_cloth cloth;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    int count = -1;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, NULL, NULL, 0, &count), WEFT_OK);
    CHECK_EQ_INT(count, m.nv);
    float* p = malloc(sizeof(float) * 3 * m.nv);
    float* nrm = malloc(sizeof(float) * 3 * m.nv);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_OBJECT, p, nrm, m.nv, &count), WEFT_OK);
    int ok_p = 1, ok_n = 1;
    for (int i = 0; i < 3 * m.nv; ++i) ok_p = ok_p && p[i] == m.pos[i];
    for (int v = 0; v < m.nv; ++v) ok_n = ok_n && nrm[3 * v] == 0.0f && nrm[3 * v + 1] == 1.0f && nrm[3 * v + 2] == 0.0f;
    CHECK(ok_p);
    CHECK(ok_n);
    int nt = -1;
    CHECK_EQ_INT(weft_cloth_get_triangles(ctx, cloth, NULL, 0, &nt), WEFT_OK);
    CHECK_EQ_INT(nt, 2 * m.nf);
    int* tris = malloc(sizeof(int) * 3 * nt);
    CHECK_EQ_INT(weft_cloth_get_triangles(ctx, cloth, tris, nt, &nt), WEFT_OK);
    /* every triangle faces +Y in host positions, and covers SIZE^2 in total */
    double area = 0.0;
    int up = 1;
    for (int t = 0; t < nt; ++t) {
        const float* a = m.pos + 3 * tris[3 * t];
        const float* b = m.pos + 3 * tris[3 * t + 1];
        const float* c = m.pos + 3 * tris[3 * t + 2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double ny = e1[2] * e2[0] - e1[0] * e2[2];
        up = up && ny > 0;
        area += 0.5 * ny;
    }
    CHECK(up);
    CHECK_NEAR(area, SIZE * SIZE, 1e-6);
    free(p);
    free(nrm);
    free(tris);
    weft_context_destroy(ctx);
    ag_free(&m);
}


/* Per-quad vertices (UV seams everywhere): output in host order, welded twins identical, and the
 * same motion as the welded grid. */
static void test_uv_split_order(void) {
    ag_mesh split, plain;
    ag_grid(&split, N, SIZE, 1.0, 1, 1);
    ag_grid(&plain, N, SIZE, 1.0, 1, 0);
    weft_context* ctx = new_context(NULL, NULL);
    /* pin the top corners: quad (0, N-2) corner 3 and quad (N-2, N-2) corner 2 in the split mesh */
    int q0 = 0 + (N - 1) * (N - 2), q1 = (N - 2) + (N - 1) * (N - 2);
    int pins_split[2] = {4 * q0 + 3, 4 * q1 + 2};
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = pins_split;
    att.n_vertices = 2;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&split);
    def.n_attachments = 1;
    def.attachments = &att;
    weft_cloth cs, cp;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cs), WEFT_OK);
    cp = hanging(ctx, &plain, NULL);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cs, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_vertices, 4 * (N - 1) * (N - 1));
    CHECK_EQ_INT(info.n_particles, N * N);
    for (int f = 0; f < 30; ++f) {
        weft_frame fr = weft_default_frame();
        CHECK_EQ_INT(weft_cloth_step(ctx, cs, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(ctx, cp, &fr, NULL), WEFT_OK);
    }
    float* ps = malloc(sizeof(float) * 3 * split.nv);
    float* ns = malloc(sizeof(float) * 3 * split.nv);
    float* pp = malloc(sizeof(float) * 3 * plain.nv);
    int n;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cs, WEFT_SPACE_WORLD, ps, ns, split.nv, &n), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cp, WEFT_SPACE_WORLD, pp, NULL, plain.nv, &n), WEFT_OK);
    /* every split vertex: same position and normal as every twin, close to the welded grid's */
    int twins_same = 1;
    double worst = 0.0;
    for (int q = 0; q < split.nf; ++q) {
        int i = q % (N - 1), j = q / (N - 1);
        int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
        for (int k = 0; k < 4; ++k) {
            int v = 4 * q + k, g = ci[k] + N * cj[k];
            /* the twin in the first quad that holds grid point g */
            int tq = (ci[k] > 0 ? ci[k] - 1 : 0) + (N - 1) * (cj[k] > 0 ? cj[k] - 1 : 0);
            int tk = (ci[k] > 0 ? 1 : 0) + (cj[k] > 0 ? 2 : 0);
            int tk_map[4] = {0, 1, 3, 2};   /* (di, dj) -> corner index */
            int tv = 4 * tq + tk_map[tk];
            twins_same = twins_same && memcmp(ps + 3 * v, ps + 3 * tv, 3 * sizeof(float)) == 0 &&
                         memcmp(ns + 3 * v, ns + 3 * tv, 3 * sizeof(float)) == 0;
            for (int c = 0; c < 3; ++c) worst = fmax(worst, fabs((double)ps[3 * v + c] - pp[3 * g + c]));
        }
    }
    printf("  uv split: welded twins identical %d, gap to the welded grid %.3g m\n", twins_same, worst);
    CHECK(twins_same);
    CHECK(worst < 1e-6);
    free(ps);
    free(ns);
    free(pp);
    weft_context_destroy(ctx);
    ag_free(&split);
    ag_free(&plain);
}

/* Run a cloth for frames, return its snapshot (malloc'ed). */
static unsigned char* run_snapshot(weft_context* ctx, weft_cloth c, int frames, size_t* size) {
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, c, &info), WEFT_OK);
    for (int f = 0; f < frames; ++f) {
        weft_frame fr = weft_default_frame();
        CHECK_EQ_INT(weft_cloth_step(ctx, c, &fr, NULL), WEFT_OK);
    }
    unsigned char* buf = malloc(info.snapshot_size);
    CHECK_EQ_INT(weft_cloth_save(ctx, c, buf, info.snapshot_size), WEFT_OK);
    *size = info.snapshot_size;
    return buf;
}

/* Two contexts stepped alternately give exactly what each gives alone. */
static void test_two_contexts(void) {
    ag_mesh m1, m2;
    ag_grid(&m1, N, SIZE, 1.0, 1, 0);
    ag_grid(&m2, N + 3, 2 * SIZE, 2.0, 1, 0);
    size_t s1, s2, t1, t2;
    weft_context* a = new_context(NULL, NULL);
    unsigned char* alone1 = run_snapshot(a, hanging(a, &m1, NULL), 25, &s1);
    weft_context_destroy(a);
    a = new_context(NULL, NULL);
    unsigned char* alone2 = run_snapshot(a, hanging(a, &m2, NULL), 25, &s2);
    weft_context_destroy(a);

    weft_context* c1 = new_context(NULL, NULL);
    weft_context* c2 = new_context(NULL, NULL);
    weft_cloth h1 = hanging(c1, &m1, NULL), h2 = hanging(c2, &m2, NULL);
    /* a handle of one context is refused by the other */
    CHECK_EQ_INT(weft_cloth_step(c2, h1, NULL, NULL), WEFT_ERROR_INVALID_HANDLE);
    for (int f = 0; f < 25; ++f) {
        weft_frame fr = weft_default_frame();
        CHECK_EQ_INT(weft_cloth_step(c1, h1, &fr, NULL), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_step(c2, h2, &fr, NULL), WEFT_OK);
    }
    unsigned char* both1 = run_snapshot(c1, h1, 0, &t1);
    unsigned char* both2 = run_snapshot(c2, h2, 0, &t2);
    CHECK(s1 == t1 && memcmp(alone1, both1, s1) == 0);
    CHECK(s2 == t2 && memcmp(alone2, both2, s2) == 0);
    weft_context_destroy(c1);
    weft_context_destroy(c2);
    free(alone1);
    free(alone2);
    free(both1);
    free(both2);
    ag_free(&m1);
    ag_free(&m2);
}

/* A counting allocator: everything goes through it, a step allocates nothing (pins, colliders,
 * teleport, reset, wind included; and with BDF2, Newton iterations and line search), and
 * everything is freed. */
static void no_allocation_in_step(weft_integrator integrator, int newton, int line_search) {
    ag_alloc_counter counter = {0, 0, 0};
    ag_mesh m;
    ag_grid(&m, N, SIZE, 1.0, 1, 0);
    weft_context* ctx = new_context(NULL, &counter);
    long after_context = counter.allocs;
    CHECK(after_context >= 1);
    weft_collider_def col = weft_default_collider_def();
    col.radius = 0.1;
    static int corners[2] = {N * (N - 1), N * N - 1};
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = corners;
    att.n_vertices = 2;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    def.attachments = &att;
    def.n_attachments = 1;
    def.colliders = &col;
    def.n_colliders = 1;
    def.solver = WEFT_SOLVER_CHEBYSHEV;
    def.integrator = integrator;
    def.newton_iterations = newton;
    def.line_search = line_search;
    weft_cloth cloth;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    long before = counter.allocs, frees_before = counter.frees;
    CHECK(before > after_context);
    for (int f = 1; f <= 20; ++f) {
        float obj[16], bone[16], sphere[16];
        ag_transform(obj, 0, 1, 0, 0.1 * f, 0.01 * f, 0, 0);
        ag_transform(bone, 0, 1, 0, 0.05 * f, 0.01 * f, 0, 0);
        ag_transform(sphere, 1, 0, 0, 0.0, 0.0, 0.2 + 0.01 * f, 0.3);
        double wind[3] = {1.0, 0.0, 0.5 * f};
        weft_frame fr = weft_default_frame();
        fr.object_transform = obj;
        fr.attachment_transforms = bone;
        fr.collider_transforms = sphere;
        fr.wind = wind;
        fr.flags = f == 7 ? WEFT_FRAME_TELEPORT : f == 13 ? WEFT_FRAME_RESET : 0;
        weft_frame_stats st;
        CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, &st), WEFT_OK);
    }
    /* a refused step allocates nothing either */
    weft_frame bad = weft_default_frame();
    bad.dt = -1.0;
    CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &bad, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    printf("  allocations: %ld at create, %ld during 21 steps\n", before - after_context, counter.allocs - before);
    CHECK_EQ_INT(counter.allocs, before);
    CHECK_EQ_INT(counter.frees, frees_before);
    weft_context_destroy(ctx);
    CHECK_EQ_INT(counter.live, 0);
    CHECK(counter.frees == counter.allocs);
    ag_free(&m);
}

/* BDF2 and a teleport: a 1 km jump (rotated) resets the history, so the next substep does not
 * read the jump as a velocity: kinetic energy stays where it was, no rollback, and the cloth
 * continues (relative to the object) as a backward-Euler cloth carried the same way. Without
 * the reset, x_n - x_{n-1} = 1 km would be extrapolated. */
static void teleport_run(weft_integrator integrator) {
    ag_mesh m;
    ag_grid(&m, N, SIZE, 1.0, 0, 0);   /* horizontal: it swings down from its pins */
    static int corners[2] = {N * (N - 1), N * N - 1};
    weft_attachment_def att = weft_default_attachment_def();
    att.vertices = corners;
    att.n_vertices = 2;
    weft_context* ctx = new_context(NULL, NULL);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(&m);
    def.attachments = &att;
    def.n_attachments = 1;
    def.integrator = integrator;
    weft_cloth cloth;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    double ke_before = 0.0;
    for (int f = 1; f <= 20; ++f) {
        float obj[16];
        if (f < 12) ag_transform(obj, 0, 1, 0, 0.0, 0.0, 0.0, 0.0);
        else ag_transform(obj, 0, 1, 0, 0.7, 1000.0, 20.0, -500.0);
        weft_frame fr = weft_default_frame();
        fr.object_transform = obj;
        fr.attachment_transforms = obj;
        fr.flags = f == 12 ? WEFT_FRAME_TELEPORT : 0;
        weft_frame_stats st;
        CHECK_EQ_INT(weft_cloth_step(ctx, cloth, &fr, &st), WEFT_OK);
        CHECK_EQ_INT(st.rollbacks, 0);
        if (f == 11) ke_before = st.kinetic_energy;
        if (f == 11) CHECK(ke_before > 1e-4);   /* still swinging */
        if (f == 12) {
            printf("  kinetic energy %.3g J before the teleport, %.3g J after\n", ke_before, st.kinetic_energy);
            CHECK(st.kinetic_energy < 2.0 * ke_before + 1e-3);
        }
        CHECK(st.kinetic_energy < 1.0);
    }
    weft_context_destroy(ctx);
    ag_free(&m);
}

/* TR-BDF2 has no history: the same teleport is a plain carried jump for it too. */
static void test_bdf2_teleport(void) {
    teleport_run(WEFT_INTEGRATOR_BDF2);
    teleport_run(WEFT_INTEGRATOR_TRBDF2);
}

static void test_no_allocation_in_step(void) {
    no_allocation_in_step(WEFT_INTEGRATOR_BACKWARD_EULER, 1, 0);
    no_allocation_in_step(WEFT_INTEGRATOR_BDF2, 3, 1);
    no_allocation_in_step(WEFT_INTEGRATOR_TRBDF2, 2, 1);
}

/* Errors reach the logger at ERROR level with the last-error text; context-create errors reach
 * the def's logger. */
static void test_logger(void) {
    ag_log log;
    memset(&log, 0, sizeof log);
    weft_context* ctx = new_context(&log, NULL);
    weft_cloth_def def = weft_default_cloth_def();
    weft_cloth cloth;
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(log.count[WEFT_LOG_ERROR], 1);
    CHECK(strcmp(log.last, weft_context_last_error(ctx)) == 0);
    CHECK(strstr(log.last, "weft_cloth_create") != NULL && strstr(log.last, "def->mesh") != NULL);
    CHECK_EQ_INT(weft_context_last_status(ctx), WEFT_ERROR_INVALID_ARGUMENT);
    weft_context_destroy(ctx);

    memset(&log, 0, sizeof log);
    weft_context_def cd = weft_default_context_def();
    cd.log = ag_log_fn;
    cd.log_user = &log;
    cd.threads = -2;
    weft_context* none = (weft_context*)&log;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &none), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK(none == NULL);
    CHECK_EQ_INT(log.count[WEFT_LOG_ERROR], 1);
    CHECK(strstr(log.last, "def->threads") != NULL);
    /* log_level ERROR: errors still reach the logger, nothing below them does */
    memset(&log, 0, sizeof log);
    cd.threads = 0;
    cd.log_level = WEFT_LOG_ERROR;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_step(ctx, cloth, NULL, NULL), WEFT_ERROR_INVALID_HANDLE);
    CHECK_EQ_INT(log.count[WEFT_LOG_ERROR], 1);
    CHECK_EQ_INT(log.count[WEFT_LOG_WARN] + log.count[WEFT_LOG_INFO] + log.count[WEFT_LOG_DEBUG], 0);
    weft_context_destroy(ctx);
}

/* A mesh file through core's importer, in centimetres (unit_scale 0.01), placed by a transform:
 * OBJECT space gives the file's own coordinates back, WORLD the placed metres. */
static void test_file_mesh(void) {
    char path[512];
    snprintf(path, sizeof path, "%s/api_frame_quads.obj", WEFT_TEST_TMPDIR);
    FILE* o = fopen(path, "w");
    CHECK(o != NULL);
    if (!o) return;
    /* 3 x 2 vertices, two quads, in the XZ plane (cm) */
    fputs("v 0 0 0\nv 50 0 0\nv 100 0 0\nv 0 0 -50\nv 50 0 -50\nv 100 0 -50\nf 1 2 5 4\nf 2 3 6 5\n", o);
    fclose(o);
    weft_context* ctx = new_context(NULL, NULL);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.path = path;
    def.unit_scale = 0.01;
    ag_transform(def.transform, 0, 1, 0, 0.0, 1.0, 2.0, 3.0);
    weft_cloth cloth;
    weft_status st = weft_cloth_create(ctx, &def, &cloth);
    if (st != WEFT_OK) fprintf(stderr, "%s\n", weft_context_last_error(ctx));
    CHECK_EQ_INT(st, WEFT_OK);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    CHECK_EQ_INT(info.n_vertices, 6);
    CHECK_EQ_INT(info.n_triangles, 4);
    CHECK_NEAR(info.bbox_max[0] - info.bbox_min[0], 1.0, 1e-12);
    CHECK_NEAR(info.total_mass, 0.15 * 0.5, 1e-12);
    float obj[18], world[18];
    int n;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_OBJECT, obj, NULL, 6, &n), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, world, NULL, 6, &n), WEFT_OK);
    const float want[18] = {0, 0, 0, 50, 0, 0, 100, 0, 0, 0, 0, -50, 50, 0, -50, 100, 0, -50};
    /* the host order of a file is assimp's (source_mesh.h): match each vertex to the file's */
    double worst_obj = 0.0, worst_world = 0.0;
    int used[6] = {0, 0, 0, 0, 0, 0}, matched = 0;
    for (int v = 0; v < 6; ++v) {
        int best = -1;
        double bd = 1e30;
        for (int w = 0; w < 6; ++w) {
            double d = fabs(obj[3 * v] - want[3 * w]) + fabs(obj[3 * v + 1] - want[3 * w + 1]) +
                       fabs(obj[3 * v + 2] - want[3 * w + 2]);
            if (d < bd) {
                bd = d;
                best = w;
            }
        }
        matched += !used[best];
        used[best] = 1;
        worst_obj = fmax(worst_obj, bd);
        for (int k = 0; k < 3; ++k) {
            double placed = 0.01 * want[3 * best + k] + (k == 0 ? 1.0 : k == 1 ? 2.0 : 3.0);
            worst_world = fmax(worst_world, fabs(world[3 * v + k] - placed));
        }
    }
    printf("  file mesh: object gap %.3g cm, world gap %.3g m\n", worst_obj, worst_world);
    CHECK_EQ_INT(matched, 6);
    CHECK(worst_obj < 1e-4);      /* cm */
    CHECK(worst_world < 1e-6);    /* m */
    weft_context_destroy(ctx);
}

int main(void) {
    RUN_TEST(test_core_equivalence);
    RUN_TEST(test_moving_bone);
    RUN_TEST(test_normals_triangles);
    RUN_TEST(test_file_mesh);
    RUN_TEST(test_uv_split_order);
    RUN_TEST(test_two_contexts);
    RUN_TEST(test_no_allocation_in_step);
    RUN_TEST(test_bdf2_teleport);
    RUN_TEST(test_logger);
    return TEST_SUMMARY();
}
