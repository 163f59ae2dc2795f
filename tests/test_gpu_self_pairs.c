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
 * candidates and the same lists (the host's rules decide). The fallbacks to core's detection
 * (test_fallbacks): more candidates than the room (the folded strip at thickness 16 mm), the
 * room's edge (room = candidates: none; one short: core's), a NaN or infinite v or x (nothing
 * read from the GPU), each with core's list; the walk's stack bound argued (test_deep) and the
 * deepest trees the test affords walked without a fallback. Compute passes only (fragment passes
 * keep core's detection on the host). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bvh.h"
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
    wg_runner run;
    CHECK(tg_runner_open(g_dev, &L, &run, err, sizeof err));
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
    tg_runner_close(&run, &L);
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


/* The fallbacks to core's wc_self_pairs_find (wg_self_pairs_io's by_core, *candidates -1). A rig:
 * one model's self stage, x, v and their textures. */
typedef struct rig {
    wc_model m;
    wc_self* sc;
    const wg_layout* L;
    int n;
    double *x, *v;
    float *x4, *v4;
    wg_tex xt, vt;
} rig;

/* r->m and r->x set: the rest at thickness th */
static void rig_open(rig* r, const wg_layout* L, double th) {
    char err[256];
    wc_diag d = {0};
    r->L = L;
    r->n = r->m.n_particles;
    r->sc = NULL;
    CHECK_EQ_INT(wc_self_create(&r->sc, &r->m, th, NULL, &d), WC_OK);
    r->v = calloc(3 * (size_t)r->n, sizeof(double));
    r->x4 = calloc(4 * (size_t)r->n, sizeof(float));
    r->v4 = calloc(4 * (size_t)r->n, sizeof(float));
    memset(&r->xt, 0, sizeof r->xt);
    memset(&r->vt, 0, sizeof r->vt);
    CHECK(wg_array_create(L, &r->xt, GL_RGBA32F, r->n, NULL, err, sizeof err));
    CHECK(wg_array_create(L, &r->vt, GL_RGBA32F, r->n, NULL, err, sizeof err));
}

static void rig_close(rig* r) {
    wg_tex_destroy(&r->xt);
    wg_tex_destroy(&r->vt);
    wc_self_destroy(r->sc);
    wc_model_free(&r->m);
    free(r->x), free(r->v), free(r->x4), free(r->v4);
}

/* x (float-rounded) and v = jit times seed's jitter, less fall in y, on both sides */
static void rig_set(rig* r, unsigned seed, double jit, double fall) {
    g_seed = seed;
    for (int i = 0; i < r->n; ++i)
        for (int c = 0; c < 3; ++c) {
            r->x[3 * i + c] = fr(r->x[3 * i + c]);
            r->v[3 * i + c] = fr(jit * jitter() - (c == 1 ? fall : 0.0));
        }
}

static void rig_upload(rig* r) {
    for (int i = 0; i < r->n; ++i)
        for (int c = 0; c < 3; ++c) {
            r->x4[4 * i + c] = (float)r->x[3 * i + c];
            r->v4[4 * i + c] = (float)r->v[3 * i + c];
        }
    wg_array_upload(r->L, &r->xt, r->n, r->x4);
    wg_array_upload(r->L, &r->vt, r->n, r->v4);
}

/* the finder's candidates (-1: core found) at r's x and v; pc (may be NULL) core's list: 1 when
 * the lists are the same (always 1 without pc) */
static int rig_find(rig* r, wg_self_pairs* gp, wc_self_pairs* pc, wc_self_pairs* pg, int* cand, size_t* bytes) {
    rig_upload(r);
    if (pc) wc_self_pairs_find(pc, r->sc, &r->m, NULL, r->x, r->v, H, H);
    *cand = 0;
    *bytes = 0;
    const int found = wg_self_pairs_find(gp, pg, r->sc, &r->m, NULL, &r->xt, &r->vt, r->x, r->v, H, H, bytes, cand);
    CHECK_EQ_INT(found, pg->list.n);
    return pc ? same_list(&pc->list, &pg->list) : 1;
}

/* a finder and core's list and its own, lists of capacity cap */
static wg_self_pairs* finder(rig* r, wg_runner* run, int cap, wc_self_pairs** pc, wc_self_pairs** pg) {
    char err[512];
    *pc = wc_self_pairs_create(cap, r->n, r->sc->n_edges, 1, 0, NULL);
    *pg = wc_self_pairs_create(cap, r->n, r->sc->n_edges, 1, 0, NULL);
    CHECK(*pc && *pg);
    wg_self_pairs* gp = NULL;
    CHECK(wg_self_pairs_create(run, r->sc, *pg, &r->m, NULL, &gp, err, sizeof err));
    if (!gp) printf("  wg_self_pairs_create: %s\n", err);
    return gp;
}

static void finder_free(wg_self_pairs* gp, wc_self_pairs* pc, wc_self_pairs* pg) {
    wg_self_pairs_destroy(gp, 1);
    wc_self_pairs_destroy(pc, NULL);
    wc_self_pairs_destroy(pg, NULL);
}

/* the folded heap strip (8 layers 4 mm apart) at thickness th */
static void crowded(rig* r, const wg_layout* L, double th) {
    wc_collider floor;
    heap_strip(&r->m, &floor);
    r->x = malloc(3 * (size_t)r->m.n_particles * sizeof(double));
    heap_strip_folded(&r->m, r->x);
    rig_open(r, L, th);
}

#define CROWD_TH 0.016   /* 2 thickness spans the 8 layers (28 mm): twice the room */
#define PROBES 400

/* More candidates than the room (16 a query: 16 (n + edges + 64), or 16 times the list's capacity
 * if more): core's detection, the same list. The folded strip at thickness 16 mm gives about 2
 * times the room. Then the room's edge: with the room (16 times the list's capacity) exactly the
 * candidates the finder keeps them all (no fallback); one short of them it falls back. */
static void test_overflow(wg_runner* run) {
    rig r;
    crowded(&r, run->layout, CROWD_TH);
    const int queries = r.n + r.sc->n_edges + 64;
    wc_self_pairs *pc, *pg;
    wg_self_pairs* gp = finder(&r, run, 300, &pc, &pg);
    int differ = 0, fell = 0, cand;
    size_t bytes;
    for (int s = 0; gp && s < STEPS; ++s) {
        rig_set(&r, 777u + (unsigned)s, 0.3, 0.0);
        differ += !rig_find(&r, gp, pc, pg, &cand, &bytes);
        fell += cand < 0;
        CHECK(bytes == 4);   /* the counter only */
        printf("  crowded substep %d: core %d pairs (%d over the cap), candidates %d (room %d): %s\n", s,
               pc->list.n, pc->list.overflow, cand, 16 * queries, differ ? "lists differ" : "the same list");
    }
    const wg_self_pairs_io* io = gp ? wg_self_pairs_transfers(gp) : NULL;
    CHECK_EQ_INT(differ, 0);
    CHECK_EQ_INT(fell, STEPS);
    CHECK(io && io->finds == STEPS && io->by_core == STEPS && io->over_room == STEPS && io->non_finite == 0);
    CHECK(pc->list.n == 300 && pc->list.overflow > 0);
    finder_free(gp, pc, pg);

    /* the candidates of PROBES seeds with room for all (a list of capacity 4 times the queries,
     * room 64 a query): one seed with a multiple of 16, one with one more */
    gp = finder(&r, run, 4 * queries, &pc, &pg);
    int at[2] = {-1, -1}, count[2] = {0, 0};
    for (int s = 0; gp && s < PROBES && (at[0] < 0 || at[1] < 0); ++s) {
        rig_set(&r, 4000u + (unsigned)s, 0.3, 0.0);
        rig_find(&r, gp, NULL, pg, &cand, &bytes);
        CHECK(cand >= 16 * queries && cand <= 64 * queries);
        const int rem = cand % 16;
        if (rem < 2 && at[rem] < 0) at[rem] = s, count[rem] = cand;
    }
    finder_free(gp, pc, pg);
    printf("  the room's edge: seed %d %d candidates (room %d: the same), seed %d %d (room %d: one short)\n",
           at[0], count[0], 16 * (count[0] / 16), at[1], count[1], 16 * (count[1] / 16));
    CHECK(at[0] >= 0 && at[1] >= 0);
    for (int k = 0; k < 2; ++k) {
        if (at[k] < 0) continue;
        gp = finder(&r, run, count[k] / 16, &pc, &pg);   /* room 16 (count / 16): count less k */
        rig_set(&r, 4000u + (unsigned)at[k], 0.3, 0.0);
        const int same = gp && rig_find(&r, gp, pc, pg, &cand, &bytes);
        printf("  room %d, %d candidates: %d found, core %d pairs (%d over the cap): %s\n", 16 * (count[k] / 16),
               count[k], cand, pc->list.n, pc->list.overflow, same ? "the same list" : "lists differ");
        CHECK(same);
        CHECK_EQ_INT(cand, k ? -1 : count[k]);
        CHECK(bytes == (k ? 4 : 4 + 8 * (size_t)count[k]));
        CHECK(gp && wg_self_pairs_transfers(gp)->over_room == k);
        finder_free(gp, pc, pg);
    }
    CHECK(glGetError() == GL_NO_ERROR);
    CHECK(run->fault[0] == '\0');
    rig_close(&r);
}

/* A non-finite x or v: core's detection, nothing run on or read from the GPU (bytes 0), the same
 * list as core's (which runs on them), no crash; the next finite substep on the GPU again. */
static void test_non_finite(wg_runner* run) {
    rig r;
    crowded(&r, run->layout, 0.005);
    wc_self_pairs *pc, *pg;
    wg_self_pairs* gp = finder(&r, run, r.n + r.sc->n_edges + 64, &pc, &pg);
    const int k = r.n / 2;
    const double bad[4] = {NAN, INFINITY, NAN, 0.0};   /* v, v, x, none */
    for (int s = 0; gp && s < 4; ++s) {
        rig_set(&r, 99u + (unsigned)s, 0.3, 0.0);
        const double keep = r.x[3 * k + 1];
        if (s < 2) r.v[3 * k + 1] = bad[s];
        if (s == 2) r.x[3 * k + 1] = bad[s];
        const long long read0 = wg_self_pairs_transfers(gp)->read_bytes;
        int cand;
        size_t bytes;
        const int same = rig_find(&r, gp, pc, pg, &cand, &bytes);
        const wg_self_pairs_io* io = wg_self_pairs_transfers(gp);
        printf("  %s: core %d pairs, the finder %d (candidates %d, %zu bytes read back): %s\n",
               s < 2 ? (s ? "an infinite velocity" : "a NaN velocity") : s == 2 ? "a NaN position" : "finite again",
               pc->list.n, pg->list.n, cand, bytes, same ? "the same list" : "lists differ");
        CHECK(same);
        if (s < 3) {
            CHECK_EQ_INT(cand, -1);
            CHECK(bytes == 0 && io->read_bytes == read0);
            CHECK(io->non_finite == s + 1 && io->by_core == s + 1 && io->over_room == 0);
        } else {
            CHECK(cand > 0 && pc->list.n > 0);
            CHECK(io->non_finite == 3 && io->by_core == 3 && io->finds == 4);
        }
        r.x[3 * k + 1] = keep;
    }
    CHECK(glGetError() == GL_NO_ERROR);
    CHECK(run->fault[0] == '\0');
    finder_free(gp, pc, pg);
    rig_close(&r);
}


static int ceil_log2(int n) {
    int k = 0;
    while ((1LL << k) < n) ++k;
    return k;
}

/* The walk's stack (64, self_walk_rules.glsl) is not reached by any model: core's trees split at
 * the median (core/bvh.c: halves of floor and ceil n / 2), so a tree of n elements has height
 * ceil(log2 n) <= 31 for n < 2^31 (an int). The walk pops a node at depth d with at most d
 * entries left (one pending right child an ancestor), pushing two needs d + 2 <= 64: an inner node
 * at depth 63, a tree of height 64, 2^63 elements at least. So the stack holds at most 32 and
 * too_deep never runs (its fallback is the room's, tested above). Here: the deepest trees of a
 * model the test affords (two 64 x 64 layers: 15876 triangles, height 14, and 24066 edges, 15),
 * their heights ceil(log2 n) and the finder's lists core's with no fallback. */
static void test_deep(wg_runner* run) {
    const int g = 64;
    rig r;
    CHECK(two_layers(&r.m, g, 1.6, 0.0, 0.012));   /* cells of 25 mm */
    r.x = malloc(3 * (size_t)r.m.n_particles * sizeof(double));
    two_layers_shifted(&r.m, g, 1.6, r.x);
    rig_open(&r, run->layout, 0.004);
    int* h = calloc((size_t)(r.sc->tri_bvh.n_nodes > r.sc->edge_bvh.n_nodes ? r.sc->tri_bvh.n_nodes
                                                                             : r.sc->edge_bvh.n_nodes),
                    sizeof(int));
    const int ht = wc_bvh_heights(&r.sc->tri_bvh, h), he = wc_bvh_heights(&r.sc->edge_bvh, h);
    free(h);
    printf("  two %d x %d layers: %d triangles (tree height %d), %d edges (height %d)\n", g, g, r.sc->n_tris, ht,
           r.sc->n_edges, he);
    CHECK_EQ_INT(ht, ceil_log2(r.sc->n_tris));
    CHECK_EQ_INT(he, ceil_log2(r.sc->n_edges));
    CHECK(ht >= 14 && he >= 14 && he + 2 <= 64);
    wc_self_pairs *pc, *pg;
    wg_self_pairs* gp = finder(&r, run, r.n + r.sc->n_edges + 64, &pc, &pg);
    long long pairs = 0;
    for (int s = 0; gp && s < 2; ++s) {
        rig_set(&r, 31u + (unsigned)s, 0.05, 0.0);
        for (int i = 0; i < r.n; ++i)   /* the upper layer falls at 0.6 m/s */
            if (r.m.rest_pos[3 * i + 1] > 0.006) r.v[3 * i + 1] = fr(r.v[3 * i + 1] - 0.6);
        int cand;
        size_t bytes;
        CHECK(rig_find(&r, gp, pc, pg, &cand, &bytes));
        printf("  substep %d: core %d pairs, %d candidates\n", s, pc->list.n, cand);
        CHECK(cand >= pc->list.n);
        pairs += pc->list.n;
        for (int i = 0; i < 3 * r.n; ++i) r.x[i] += H * r.v[i];
    }
    const wg_self_pairs_io* io = gp ? wg_self_pairs_transfers(gp) : NULL;
    printf("  %lld pairs, %lld substeps by core\n", pairs, io ? io->by_core : -1LL);
    CHECK(pairs > 0);
    CHECK(io && io->by_core == 0 && io->finds == 2);
    CHECK(run->fault[0] == '\0');
    finder_free(gp, pc, pg);
    rig_close(&r);
}

static void test_fallbacks(void) {
    if (!g_dev->compute) {
        printf("  fragment passes: core's detection on the host (nothing to compare)\n");
        return;
    }
    char err[512];
    wg_layout L;
    wg_runner run;
    CHECK(tg_runner_open(g_dev, &L, &run, err, sizeof err));
    test_overflow(&run);
    test_non_finite(&run);
    test_deep(&run);
    tg_runner_close(&run, &L);
}

int main(void) {
    if (!tg_gpu_open(&g_ctx, &g_dev)) return 1;
    RUN_TEST(test_pairs_against_core);
    RUN_TEST(test_fallbacks);
    tg_gpu_close(g_ctx, g_dev);
    return TEST_SUMMARY();
}
