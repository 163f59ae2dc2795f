/* Sewing on the GPU backend through the public API (real EGL: llvmpipe without a GPU), against the
 * CPU backend with the GPU's method (one backward-Euler step, PCG with block Jacobi, no
 * self-collision): the sewn tube (seams by sew_distance) and the host-pair sheets (their
 * rest-length ramp) over whole runs, the import report the same on both, bad seam inputs refused
 * the same way on both with the context intact, and bit-exact snapshot round trips mid-ramp. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "api_gpu_support.h"
#include "check.h"
#include "sew_sheets.h"
#include "sew_tube.h"
#include "weft/weft.h"

/* A scene's host arrays (floats, as the API takes them) and its seams. */
typedef struct sew_scene {
    int nv, nf;
    float* pos;
    int *sizes, *idx;
    double sew_distance;
    int n_pairs, pins[SHEET_N], n_pins;
    int sa[SHEET_N], sb[SHEET_N];
} sew_scene;

static void scene_from(sew_scene* sc, const double* pos, int nv, const int* sizes, const int* idx, int nf) {
    sc->nv = nv;
    sc->nf = nf;
    sc->pos = malloc(sizeof(float) * 3 * (size_t)nv);
    sc->sizes = malloc(sizeof(int) * (size_t)nf);
    sc->idx = malloc(sizeof(int) * 4 * (size_t)nf);
    for (int i = 0; i < 3 * nv; ++i) sc->pos[i] = (float)pos[i];
    memcpy(sc->sizes, sizes, sizeof(int) * (size_t)nf);
    memcpy(sc->idx, idx, sizeof(int) * 4 * (size_t)nf);
}

/* The tube sewn by distance, held at panel A's two top corners. */
static void tube_scene(sew_scene* sc) {
    memset(sc, 0, sizeof *sc);
    tube t;
    tube_make(&t);
    scene_from(sc, t.pos, t.nv, t.sizes, t.idx, t.nf);
    tube_free(&t);
    sc->sew_distance = SEW;
    sc->pins[0] = tube_vertex(0, 0, 0);
    sc->pins[1] = tube_vertex(0, 0, NW);
    sc->n_pins = 2;
}

/* The two sheets 0.3 m apart, A's top row held, B's top row sewn to it by host pairs. */
static void sheets_scene(sew_scene* sc) {
    enum { NV = 2 * SHEET_N * SHEET_N, NF = 2 * (SHEET_N - 1) * (SHEET_N - 1) };
    memset(sc, 0, sizeof *sc);
    double pos[3 * NV];
    int sizes[NF], idx[4 * NF];
    two_sheets(pos, sizes, idx, 0.3);
    scene_from(sc, pos, NV, sizes, idx, NF);
    sc->n_pairs = SHEET_N;
    for (int i = 0; i < SHEET_N; ++i) {
        sc->sa[i] = sc->pins[i] = i;
        sc->sb[i] = SHEET_N * SHEET_N + i;
    }
    sc->n_pins = SHEET_N;
}

static void scene_free(sew_scene* sc) {
    free(sc->pos);
    free(sc->sizes);
    free(sc->idx);
}

static weft_attachment_def g_att;

static weft_cloth_def scene_def(const sew_scene* sc) {
    g_att = weft_default_attachment_def();
    g_att.vertices = sc->pins;
    g_att.n_vertices = sc->n_pins;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = sc->pos;
    def.mesh.n_vertices = sc->nv;
    def.mesh.face_sizes = sc->sizes;
    def.mesh.n_faces = sc->nf;
    def.mesh.indices = sc->idx;
    def.attachments = &g_att;
    def.n_attachments = 1;
    def.sew_distance = sc->sew_distance;
    def.n_seams = sc->n_pairs;
    def.seam_a = sc->n_pairs ? sc->sa : NULL;
    def.seam_b = sc->n_pairs ? sc->sb : NULL;
    /* one linearised step with block Jacobi on both backends (the defaults add the multigrid,
       Newton with line search and, for a sewn cloth, self-collision) */
    def.solver = WEFT_SOLVER_PCG;
    def.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    def.newton_iterations = 1;
    def.line_search = 0;
    def.self_collision = 0;
    return def;
}

/* Step `frames` frames of 1/60 s; returns the rollbacks, or -1 when a step fails. strain (may be
 * NULL): the largest stretch-spring strain at the end of the last frame. */
static int step_strain(weft_context* ctx, weft_cloth cloth, int frames, double* strain) {
    weft_frame fr = weft_default_frame();
    fr.dt = 1.0 / 60.0;
    int rollbacks = 0;
    for (int f = 0; f < frames; ++f) {
        weft_frame_stats st;
        if (weft_cloth_step(ctx, cloth, &fr, &st) != WEFT_OK) {
            fprintf(stderr, "frame %d: %s\n", f, weft_context_last_error(ctx));
            return -1;
        }
        rollbacks += st.rollbacks;
        if (strain) *strain = st.max_strain;
    }
    return rollbacks;
}

static int step(weft_context* ctx, weft_cloth cloth, int frames) { return step_strain(ctx, cloth, frames, NULL); }

static float* positions(weft_context* ctx, weft_cloth cloth, int nv) {
    float* p = calloc((size_t)nv * 3, sizeof(float));
    int n = 0;
    CHECK_EQ_INT(weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, p, NULL, nv, &n), WEFT_OK);
    return p;
}

/* Largest distance between the seam pairs' vertices (host pairs only). */
static double pair_gap(const sew_scene* sc, const float* p) {
    double g = 0.0;
    for (int k = 0; k < sc->n_pairs; ++k) {
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) d2 += pow((double)p[3 * sc->sa[k] + c] - p[3 * sc->sb[k] + c], 2);
        g = fmax(g, sqrt(d2));
    }
    return g;
}

/* The import report (what `weft inspect` prints) field by field, its wall times left out. */
static int same_report(const weft_import_report* a, const weft_import_report* b) {
    size_t ints = offsetof(weft_import_report, panels) + sizeof a->panels;
    size_t from = offsetof(weft_import_report, bbox_min), to = offsetof(weft_import_report, ms_weld);
    int same = memcmp(a, b, ints) == 0 && memcmp((const char*)a + from, (const char*)b + from, to - from) == 0 &&
               a->n_warnings == b->n_warnings && a->warnings_dropped == b->warnings_dropped;
    for (int k = 0; same && k < a->n_warnings; ++k) same = strcmp(a->warnings[k], b->warnings[k]) == 0;
    return same;
}

/* The scene on both backends for `frames` frames: the largest vertex distance over the cloth's
 * rest bounding-box diagonal must be under `bound`, with no more rollbacks and crossing
 * edge-triangle pairs at the end (weft_cloth_check_collisions) on the GPU than on the CPU, and
 * the largest strain at the end within `strain_bound` of the CPU's. */
static void gpu_vs_cpu(const char* what, sew_scene* sc, int frames, double bound, double strain_bound) {
    weft_context* ctx[2] = {ap_context(WEFT_BACKEND_CPU), ap_context(WEFT_BACKEND_GPU)};
    if (!ctx[0] || !ctx[1]) return;
    weft_cloth_def def = scene_def(sc);
    weft_cloth cl[2];
    weft_import_report rep[2];
    weft_cloth_info info[2];
    float* p[2];
    int rollbacks[2], crossings[2] = {-1, -1};
    double strain[2] = {0.0, 0.0};
    for (int b = 0; b < 2; ++b) {
        weft_status st = weft_cloth_create(ctx[b], &def, &cl[b]);
        CHECK_EQ_INT(st, WEFT_OK);
        if (st != WEFT_OK) {
            fprintf(stderr, "%s: %s\n", b ? "GPU" : "CPU", weft_context_last_error(ctx[b]));
            return;
        }
        CHECK_EQ_INT(weft_cloth_get_report(ctx[b], cl[b], &rep[b]), WEFT_OK);
        CHECK_EQ_INT(weft_cloth_get_info(ctx[b], cl[b], &info[b]), WEFT_OK);
        CHECK_EQ_INT(info[b].backend, b ? WEFT_BACKEND_GPU : WEFT_BACKEND_CPU); /* the comparison is across backends */
        rollbacks[b] = step_strain(ctx[b], cl[b], frames, &strain[b]);
        p[b] = positions(ctx[b], cl[b], sc->nv);
        weft_collision_check chk;
        CHECK_EQ_INT(weft_cloth_check_collisions(ctx[b], cl[b], &chk), WEFT_OK);
        crossings[b] = chk.self_intersections;
    }
    /* what `weft inspect` prints is the import report: the same on either backend */
    CHECK(same_report(&rep[0], &rep[1]));
    CHECK_EQ_INT(rep[1].seams, info[0].n_seams);
    CHECK_EQ_INT(info[1].n_seams, info[0].n_seams);
    CHECK_EQ_INT(info[1].n_panels, 1);
    CHECK(info[0].n_seams > 0);
    double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30}, diag = 0.0, most = 0.0;
    for (int i = 0; i < sc->nv; ++i)
        for (int c = 0; c < 3; ++c) {
            lo[c] = fmin(lo[c], sc->pos[3 * i + c]);
            hi[c] = fmax(hi[c], sc->pos[3 * i + c]);
        }
    for (int c = 0; c < 3; ++c) diag += (hi[c] - lo[c]) * (hi[c] - lo[c]);
    diag = sqrt(diag);
    int finite = 1;
    double moved = 0.0;
    for (int i = 0; i < sc->nv; ++i) {
        double d2 = 0.0, m2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            finite = finite && isfinite(p[1][3 * i + c]);
            d2 += pow((double)p[1][3 * i + c] - p[0][3 * i + c], 2);
            m2 += pow((double)p[0][3 * i + c] - sc->pos[3 * i + c], 2);
        }
        most = fmax(most, sqrt(d2));
        moved = fmax(moved, sqrt(m2));
    }
    printf("  %s, %d frames: %d seams, moved up to %.3g m; GPU vs CPU largest distance %.3g m = %.3g of the diagonal (bound %g); "
           "rollbacks CPU %d, GPU %d", what, frames, info[0].n_seams, moved, most, most / diag, bound, rollbacks[0],
           rollbacks[1]);
    if (sc->n_pairs) printf("; pair gap CPU %.3g m, GPU %.3g m", pair_gap(sc, p[0]), pair_gap(sc, p[1]));
    printf("\n    largest strain at the end CPU %.6g, GPU %.6g; crossings CPU %d, GPU %d\n", strain[0], strain[1],
           crossings[0], crossings[1]);
    CHECK(finite);
    CHECK(moved > 0.02);
    CHECK(most / diag < bound);
    CHECK(rollbacks[0] >= 0 && rollbacks[1] >= 0);
    CHECK(rollbacks[1] <= rollbacks[0]);
    CHECK(crossings[1] >= 0 && crossings[1] <= crossings[0]);
    CHECK(fabs(strain[1] - strain[0]) <= strain_bound);
    if (sc->n_pairs) CHECK(fabs(pair_gap(sc, p[1]) - pair_gap(sc, p[0])) < bound * diag);
    for (int b = 0; b < 2; ++b) {
        free(p[b]);
        weft_context_destroy(ctx[b]);
    }
}

static void test_tube_run(void) {
    sew_scene sc;
    tube_scene(&sc);
    /* strain 7.9e-4 on both, 5e-7 apart (1.7e-7 with fragment passes) */
    gpu_vs_cpu("sewn tube", &sc, 30, 1e-4, 1e-5);
    scene_free(&sc);
}

static void test_host_pairs_run(void) {
    sew_scene sc;
    sheets_scene(&sc);
    /* strain 1.06e-4 on the CPU, 2.1e-6 apart (6.6e-7 with fragment passes) */
    gpu_vs_cpu("host-pair sheets (ramp 0.5 s)", &sc, 45, 2e-3, 2e-5);
    scene_free(&sc);
}

/* Bad seams: the same status and message on both backends, and the context still makes cloths. */
static void test_bad_seams(void) {
    sew_scene sc;
    sheets_scene(&sc);
    int out[1] = {sc.nv}, self[1] = {0}, a[1] = {0};
    struct { double sew; int n; const int *a, *b; } cases[] = {
        {-1e-3, 0, NULL, NULL},    /* negative sew_distance */
        {NAN, 0, NULL, NULL},      /* non-finite sew_distance */
        {0.0, 1, a, out},          /* seam_b out of range */
        {0.0, 1, a, self},         /* a vertex to itself */
        {0.0, 1, a, NULL},         /* seam_b NULL */
    };
    weft_context* ctx[2] = {ap_context(WEFT_BACKEND_CPU), ap_context(WEFT_BACKEND_GPU)};
    if (!ctx[0] || !ctx[1]) return;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        weft_status st[2];
        char msg[2][512];
        for (int b = 0; b < 2; ++b) {
            weft_cloth_def def = scene_def(&sc);
            def.sew_distance = cases[k].sew;
            def.n_seams = cases[k].n;
            def.seam_a = cases[k].a;
            def.seam_b = cases[k].b;
            weft_cloth cloth = {777};
            st[b] = weft_cloth_create(ctx[b], &def, &cloth);
            CHECK(cloth.id == 0);
            snprintf(msg[b], sizeof msg[b], "%s", weft_context_last_error(ctx[b]));
        }
        printf("  bad seams %zu: %s / %s\n", k, weft_status_string(st[1]), msg[1]);
        CHECK(st[0] != WEFT_OK);
        CHECK_EQ_INT(st[1], st[0]);
        CHECK(strcmp(msg[0], msg[1]) == 0);
        CHECK(strstr(msg[1], "sew") != NULL || strstr(msg[1], "seam") != NULL);
    }
    for (int b = 0; b < 2; ++b) {
        weft_cloth_def def = scene_def(&sc);
        weft_cloth cloth = {0};
        CHECK_EQ_INT(weft_cloth_create(ctx[b], &def, &cloth), WEFT_OK);
        CHECK(step(ctx[b], cloth, 2) >= 0);
        weft_context_destroy(ctx[b]);
    }
    scene_free(&sc);
}

/* save mid-ramp, step 5, restore, step 5: the same vertices bit for bit (the ramp's time comes
 * back with the state); the GPU snapshot restores on the CPU backend too. */
static void test_snapshot_mid_ramp(void) {
    sew_scene sc;
    sheets_scene(&sc);
    weft_context* ctx = ap_context(WEFT_BACKEND_GPU);
    if (!ctx) return;
    weft_cloth_def def = scene_def(&sc);
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    CHECK(step(ctx, cloth, 10) >= 0);
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    unsigned char* snap = malloc(info.snapshot_size);
    unsigned char* snap2 = malloc(info.snapshot_size);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, snap, info.snapshot_size), WEFT_OK);
    CHECK(step(ctx, cloth, 5) >= 0);
    float* a = positions(ctx, cloth, sc.nv);
    CHECK_EQ_INT(weft_cloth_restore(ctx, cloth, snap, info.snapshot_size), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, snap2, info.snapshot_size), WEFT_OK);
    CHECK(memcmp(snap, snap2, info.snapshot_size) == 0);
    CHECK(step(ctx, cloth, 5) >= 0);
    float* b = positions(ctx, cloth, sc.nv);
    CHECK(memcmp(a, b, (size_t)sc.nv * 3 * sizeof(float)) == 0);
    printf("  snapshot mid-ramp: pair gap %.3g m after 15 frames, replayed bit-exactly\n", pair_gap(&sc, b));
    weft_context* cpu = ap_context(WEFT_BACKEND_CPU);
    weft_cloth cc = {0};
    CHECK_EQ_INT(weft_cloth_create(cpu, &def, &cc), WEFT_OK);
    CHECK_EQ_INT(weft_cloth_restore(cpu, cc, snap, info.snapshot_size), WEFT_OK);
    weft_context_destroy(cpu);
    free(a), free(b), free(snap), free(snap2);
    weft_context_destroy(ctx);
    scene_free(&sc);
}

int main(void) {
    RUN_TEST(test_tube_run);
    RUN_TEST(test_host_pairs_run);
    RUN_TEST(test_bad_seams);
    RUN_TEST(test_snapshot_mid_ramp);
    return TEST_SUMMARY();
}
