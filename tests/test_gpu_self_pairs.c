/* The self-contact pairs found on the GPU (gpu/solver/wg_self_pairs.c: self_pairs_refit_groups.glsl,
 * self_pairs_walk_groups.glsl, then core's wc_self_pairs_from on the candidates) against core's
 * wc_self_pairs_find on the same float-rounded x and v: the lists equal bit for bit (pairs,
 * order, weights, normals, offsets, stiffnesses, overflow), both kinds of pair present. Three
 * models, four substeps each (x moved on by h v, v jittered): tests/two_layers.h's sheets 12 mm
 * apart, the upper one falling at 0.6 m/s (its pairs reached only through x + 1.5 h v), the heap
 * strip folded into 8 layers 4 mm apart (thickness 5 mm), and the overlapping panels apart (tangled
 * at rest) and sewn (seam links), moving at random; one list with room for a quarter of the
 * folded strip's pairs (its overflow counted the same). The mutations of the GPU's walk
 * (WEFT_GPU_SELF_PAIRS_MUTATION): x + 1.5 h v left out of its boxes, or the leaves not grown by
 * the thickness, lose pairs (the lists differ); its adjacency rules left out find more
 * candidates and the same lists (the host's rules decide). Compute passes only (fragment passes
 * keep core's detection on the host). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "gpu_test_device.h"
#include "heap_strip.h"
#include "overlap_panels.h"
#include "self_collide.h"
#include "self_pairs.h"
#include "test_support.h"
#include "two_layers.h"
#include "wg_device.h"
#include "wg_self_pairs.h"

static wg_gl_context* g_ctx;
static wg_device* g_dev;

#define H (1.0 / 120.0)
#define STEPS 4
#define MODELS 4

static double fr(double a) {
    volatile float f = (float)a;
    return (double)f;
}

static unsigned g_seed;
static double jitter(void) {   /* in [-1, 1) */
    g_seed = g_seed * 1103515245u + 12345u;
    return ((g_seed >> 8) & 0xffff) / 32768.0 - 1.0;
}

/* 1 when lists a and b hold the same pairs bit for bit, with the same counts */
static int same_list(const wc_penalty_pairs* a, const wc_penalty_pairs* b) {
    if (a->n != b->n || a->overflow != b->overflow) return 0;
    for (int j = 0; j < a->n; ++j)
        if (memcmp(&a->term[j], &b->term[j], sizeof a->term[j]) || a->off[j] != b->off[j] || a->k[j] != b->k[j])
            return 0;
    return 1;
}

typedef struct tally {
    int differ;             /* substeps whose lists differ */
    long long pairs, gpu_pairs, candidates, vt, ee, overflow;
    int fallback;           /* substeps with too many candidates */
    size_t bytes;
} tally;

/* model k: its positions x, thickness and velocities (the upper layer's fall, the jitter) */
static void model_of(int k, wc_model* m, double** x, double* th, double* down, double* jit) {
    *down = 0.0;
    *jit = 0.3;
    if (k == 0) {
        CHECK(two_layers(m, 12, 0.3, 0.0, 0.012));
        *x = malloc(3 * (size_t)m->n_particles * sizeof(double));
        two_layers_shifted(m, 12, 0.3, *x);
        *th = 0.004;
        *down = 0.6;
        *jit = 0.05;
    } else if (k == 1) {
        wc_collider floor;
        heap_strip(m, &floor);
        *x = malloc(3 * (size_t)m->n_particles * sizeof(double));
        heap_strip_folded(m, *x);
        *th = 0.005;
    } else {
        overlap_panels(m, k == 3);
        *x = malloc(3 * (size_t)m->n_particles * sizeof(double));
        memcpy(*x, m->rest_pos, 3 * (size_t)m->n_particles * sizeof(double));
        *th = 0.003;
    }
}

/* every model's substeps, core's list against the GPU's (mutation: WEFT_GPU_SELF_PAIRS_MUTATION) */
static tally run_models(const char* mutation, int verbose) {
    tally t = {0};
    if (mutation) setenv("WEFT_GPU_SELF_PAIRS_MUTATION", mutation, 1);
    else unsetenv("WEFT_GPU_SELF_PAIRS_MUTATION");
    char err[512];
    wg_layout L;
    CHECK(wg_layout_init(&L, 10, g_dev->max_texture_size, (wc_allocator){0}, err, sizeof err));
    wg_runner run;
    wg_runner_init(&run, g_dev, &L);
    for (int k = 0; k < MODELS; ++k) {
        g_seed = 12345u + (unsigned)k;
        wc_model m;
        double *x, th, down, jit;
        model_of(k, &m, &x, &th, &down, &jit);
        const int n = m.n_particles;
        wc_self* sc = NULL;
        wc_diag d = {0};
        CHECK_EQ_INT(wc_self_create(&sc, &m, th, NULL, &d), WC_OK);
        /* the folded strip's list with room for about a quarter of its pairs: the overflow too */
        const int cap = k == 1 ? 300 : n + sc->n_edges + 64;
        wc_self_pairs* pc = wc_self_pairs_create(cap, n, sc->n_edges, 1, 0, NULL);
        wc_self_pairs* pg = wc_self_pairs_create(cap, n, sc->n_edges, 1, 0, NULL);
        CHECK(pc && pg);
        wg_self_pairs* gp = NULL;
        CHECK(wg_self_pairs_create(&run, sc, pg, &m, NULL, &gp, err, sizeof err));
        if (!gp) printf("  wg_self_pairs_create: %s\n", err);
        double* v = malloc(3 * (size_t)n * sizeof(double));
        float* x4 = calloc(4 * (size_t)n, sizeof(float));
        float* v4 = calloc(4 * (size_t)n, sizeof(float));
        wg_tex xt = {0}, vt = {0};
        CHECK(wg_array_create(&L, &xt, GL_RGBA32F, n, NULL, err, sizeof err));
        CHECK(wg_array_create(&L, &vt, GL_RGBA32F, n, NULL, err, sizeof err));
        for (int s = 0; gp && s < STEPS; ++s) {
            for (int i = 0; i < n; ++i) {
                /* the two layers: the upper one (above 6 mm) falls */
                const double fall = k == 0 && m.rest_pos[3 * i + 1] > 0.006 ? down : 0.0;
                for (int c = 0; c < 3; ++c) {
                    x[3 * i + c] = fr(x[3 * i + c]);
                    v[3 * i + c] = fr(jit * jitter() - (c == 1 ? fall : 0.0));
                    x4[4 * i + c] = (float)x[3 * i + c];
                    v4[4 * i + c] = (float)v[3 * i + c];
                }
            }
            wg_array_upload(&L, &xt, n, x4);
            wg_array_upload(&L, &vt, n, v4);
            wc_self_pairs_find(pc, sc, &m, NULL, x, v, H, H);
            size_t bytes = 0;
            int cand = 0;
            int found = wg_self_pairs_find(gp, pg, sc, &m, NULL, &xt, &vt, x, v, H, H, &bytes, &cand);
            CHECK_EQ_INT(found, pg->list.n);
            const int same = same_list(&pc->list, &pg->list);
            int vtn = 0, een = 0;
            for (int j = 0; j < pc->list.n; ++j) {
                if (pc->list.term[j].w[0] == 1.0) ++vtn;
                else ++een;
            }
            if (verbose)
                printf("  model %d substep %d: core %d pairs (%d vertex-triangle, %d edge-edge, %d over the cap), "
                       "GPU %d, %d candidates, %zu bytes read back: %s\n",
                       k, s, pc->list.n, vtn, een, pc->list.overflow, pg->list.n, cand, bytes,
                       same ? "the same list" : "lists differ");
            t.differ += !same;
            t.pairs += pc->list.n;
            t.gpu_pairs += pg->list.n;
            t.vt += vtn;
            t.ee += een;
            t.overflow += pc->list.overflow;
            t.candidates += cand > 0 ? cand : 0;
            t.fallback += cand < 0;
            t.bytes += bytes;
            if (cand >= 0) CHECK(bytes == 4 + 8 * (size_t)cand);
            for (int i = 0; i < 3 * n; ++i) x[i] += H * v[i];
        }
        CHECK(glGetError() == GL_NO_ERROR);
        CHECK(run.fault[0] == '\0');
        wg_tex_destroy(&xt);
        wg_tex_destroy(&vt);
        wg_self_pairs_destroy(gp, 1);
        wc_self_pairs_destroy(pc, NULL);
        wc_self_pairs_destroy(pg, NULL);
        wc_self_destroy(sc);
        wc_model_free(&m);
        free(x), free(v), free(x4), free(v4);
    }
    wg_runner_destroy(&run);
    wg_layout_destroy(&L);
    unsetenv("WEFT_GPU_SELF_PAIRS_MUTATION");
    return t;
}

static void test_pairs_against_core(void) {
    if (!g_dev->compute) {
        printf("  fragment passes: core's detection on the host (nothing to compare)\n");
        return;
    }
    tally t = run_models(NULL, 1);
    printf("  %lld pairs (%lld vertex-triangle, %lld edge-edge, %lld over the cap) from %lld candidates; %d "
           "substeps' lists differ, %d fell back\n",
           t.pairs, t.vt, t.ee, t.overflow, t.candidates, t.differ, t.fallback);
    CHECK_EQ_INT(t.differ, 0);
    CHECK_EQ_INT(t.fallback, 0);
    CHECK(t.vt > 100 && t.ee > 100);
    CHECK(t.overflow > 0);
    CHECK(t.candidates >= t.pairs);
    const char* lose[] = {"no-motion", "no-pad"};
    for (int k = 0; k < 2; ++k) {
        tally mt = run_models(lose[k], 0);
        printf("  mutation %s: %d of %d substeps' lists differ (GPU %lld pairs, core's %lld)\n", lose[k], mt.differ,
               MODELS * STEPS, mt.gpu_pairs, mt.pairs);
        CHECK(mt.differ > 0);
    }
    tally mr = run_models("no-rules", 0);
    printf("  mutation no-rules: %lld candidates (%lld kept), %d lists differ\n", mr.candidates, t.candidates, mr.differ);
    CHECK_EQ_INT(mr.differ, 0);
    CHECK(mr.candidates > t.candidates);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_pairs_against_core);
    tg_gpu_close(g_ctx, g_dev);
    return TEST_SUMMARY();
}
