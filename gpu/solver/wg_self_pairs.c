/* The self-contact pairs found on the GPU (wg_self_pairs.h). */
#include "wg_self_pairs.h"

#include <GL/glew.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_error.h"
#include "wg_passes.h"

#define ROOM 16         /* candidate slots per query (particle, edge), at least per pair of the list's room */
#define MARGIN 4e-6f    /* the boxes' growth for float's rounding, relative to the largest magnitude */

typedef struct cand {
    int q, key, elem;   /* query, its element's leaf (core's walk order), element */
} cand;

struct wg_self_pairs {
    wg_runner* run;
    wc_allocator alloc;
    wg_self_idle* own;          /* the idle proof's uploads made for this finder (no proof shared) */
    wg_self_trees tr;
    int n, nt, ne, cap;
    int motion, pad, rules;     /* 0: a test's mutation */
    wg_tex out, counter;
    float* rb;                  /* (cap x 2) the candidates read back */
    cand* order;                /* (cap) their sort */
    int* list;                  /* (cap x 2) sorted, for core */
    wg_self_pairs_io io;
};

const wg_self_pairs_io* wg_self_pairs_transfers(const wg_self_pairs* gp) { return &gp->io; }

wg_self_pairs_mode wg_self_pairs_env(int* known) {
    const char* e = getenv("WEFT_GPU_SELF_PAIRS");
    if (known) *known = 1;
    if (!e || !*e || strcmp(e, "gpu") == 0) return WG_SELF_PAIRS_GPU;
    if (strcmp(e, "host") != 0 && known) *known = 0;
    return WG_SELF_PAIRS_HOST;
}

void wg_self_pairs_destroy(wg_self_pairs* gp, int gl) {
    if (!gp) return;
    wc_allocator a = gp->alloc;
    if (gl) {
        wg_tex_destroy(&gp->out);
        wg_tex_destroy(&gp->counter);
    }
    wg_self_idle_destroy(gp->own, gl);
    wc_free(&a, gp->rb);
    wc_free(&a, gp->order);
    wc_free(&a, gp->list);
    wc_free(&a, gp);
}

size_t wg_self_pairs_bytes(const wg_self_pairs* gp) {
    if (!gp) return 0;
    size_t b = wg_self_idle_bytes(gp->own);
    if (gp->out.id) b += wg_tex_bytes(&gp->out);
    if (gp->counter.id) b += wg_tex_bytes(&gp->counter);
    return b;
}

int wg_self_pairs_create(wg_runner* run, const wc_self* sc, const wc_self_pairs* sp, const wc_model* m,
                         wg_self_idle* idle, wg_self_pairs** out, char* err, size_t err_len) {
    *out = NULL;
    wc_allocator a = sc->alloc;
    wg_self_pairs* gp = wc_calloc(&a, 1, sizeof *gp);
    if (!gp) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    gp->run = run;
    gp->alloc = a;
    gp->n = sc->n;
    gp->nt = sc->n_tris;
    gp->ne = sc->n_edges;
    const int queries = sc->n + sc->n_edges + 64;
    gp->cap = ROOM * (sp->list.cap > queries ? sp->list.cap : queries);
    const char* mu = getenv("WEFT_GPU_SELF_PAIRS_MUTATION");
    gp->motion = !(mu && strcmp(mu, "no-motion") == 0);
    gp->pad = !(mu && strcmp(mu, "no-pad") == 0);
    gp->rules = !(mu && strcmp(mu, "no-rules") == 0);
    gp->rb = wc_calloc(&a, 2 * (size_t)gp->cap, sizeof(float));
    gp->order = wc_calloc(&a, (size_t)gp->cap, sizeof(cand));
    gp->list = wc_calloc(&a, 2 * (size_t)gp->cap, sizeof(int));
    int ok = gp->rb && gp->order && gp->list;
    if (!ok) wg_errorf(err, err_len, "out of memory");
    if (ok && !idle) {
        ok = wg_self_idle_create(run, sc, m, WG_SELF_IDLE_OFF, 0, &gp->own, err, err_len);
        idle = gp->own;
    }
    ok = ok && wg_array_create(run->layout, &gp->out, GL_RGBA32F, gp->cap, NULL, err, err_len) &&
         wg_tex_create(&gp->counter, GL_R32I, 1, 1, NULL, err, err_len);
    if (!ok) {
        wg_self_pairs_destroy(gp, 1);
        return 0;
    }
    wg_self_idle_trees(idle, &gp->tr);
    *out = gp;
    return 1;
}

static int all_finite(const double* a, int n) {
    for (int k = 0; k < n; ++k)
        if (!isfinite(a[k])) return 0;
    return 1;
}

static int by_walk(const void* pa, const void* pb) {
    const cand *a = pa, *b = pb;
    if (a->q != b->q) return a->q < b->q ? -1 : 1;
    return a->key < b->key ? -1 : a->key > b->key;
}

/* tree k (0 triangles, 1 edges) refitted over its elements' boxes at x and x + 1.5 h v */
static void refit(wg_self_pairs* gp, int k, const wg_tex* x, const wg_tex* v, double h, double thickness) {
    wg_runner* run = gp->run;
    WG_USE(run, WGP_SELF_PAIRS_REFIT_GROUPS, &(wg_self_pairs_refit_in){.order = gp->tr.order[k],
        .elem = gp->tr.elem, .x = x, .v = v});
    wg_u1i(run, "u_elem0", k ? gp->nt : 0);
    wg_u1i(run, "u_motion", gp->motion);
    wg_u1f(run, "u_h15", 1.5 * h);
    wg_u1f(run, "u_pad", gp->pad ? thickness : 0.0);
    wg_u1f(run, "u_margin", MARGIN);
    wg_run_by_height(run, gp->tr.first[k], gp->tr.n_heights[k], gp->tr.node[k]);
}

int wg_self_pairs_find(wg_self_pairs* gp, wc_self_pairs* sp, wc_self* sc, const wc_model* m, const wc_filter* f,
                       const wg_tex* x, const wg_tex* v, const double* xd, const double* vd, double h, double he,
                       size_t* bytes, int* candidates) {
    if (bytes) *bytes = 0;
    if (candidates) *candidates = 0;
    if (gp->nt == 0) return wc_self_pairs_from(sp, sc, m, f, xd, vd, h, he, NULL, 0);
    ++gp->io.finds;
    if (!all_finite(xd, 3 * gp->n) || !all_finite(vd, 3 * gp->n)) {   /* the GPU's boxes promise nothing */
        if (candidates) *candidates = -1;
        ++gp->io.by_core;
        ++gp->io.non_finite;
        return wc_self_pairs_find(sp, sc, m, f, xd, vd, h, he);
    }
    wg_runner* run = gp->run;
    refit(gp, 0, x, v, h, sc->thickness);
    if (gp->ne > 0) refit(gp, 1, x, v, h, sc->thickness);
    const GLint zero = 0;
    wg_tex_upload(&gp->counter, 0, 0, 1, 1, &zero);
    WG_USE(run, WGP_SELF_PAIRS_WALK_GROUPS, &(wg_self_pairs_walk_in){.tnode = gp->tr.node[0],
        .enode = gp->tr.node[1], .elem = gp->tr.elem, .x = x, .v = v, .part = gp->tr.part, .seam = gp->tr.seam});
    wg_u1i(run, "u_np", gp->n);
    wg_u1i(run, "u_nt", gp->nt);
    wg_u1i(run, "u_cap", gp->cap);
    wg_u1i(run, "u_motion", gp->motion);
    wg_u1i(run, "u_rules", gp->rules);
    wg_u1f(run, "u_th", sc->thickness);
    wg_u1f(run, "u_h15", 1.5 * h);
    wg_u1f(run, "u_margin", MARGIN);
    const int nq = gp->n + gp->ne;
    wg_run_groups_scratch(run, nq, (nq + 63) / 64, (const wg_tex* const[]){&gp->out}, 1, &gp->counter);
    GLint count = 0, prev = 0;   /* the counter: a synchronisation with the GPU */
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev);
    glBindTexture(GL_TEXTURE_2D, gp->counter.id);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_INT, &count);
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev);
    if (bytes) *bytes = sizeof(GLint);
    gp->io.read_bytes += sizeof(GLint);
    /* No room (or a walk past its stack of 64, which core's median-split trees, of height
     * ceil(log2 n) <= 31, never need: a walk holds at most height + 1 entries): core's detection */
    if (count < 0 || count > gp->cap) {
        if (candidates) *candidates = -1;
        ++gp->io.by_core;
        ++gp->io.over_room;
        return wc_self_pairs_find(sp, sc, m, f, xd, vd, h, he);
    }
    if (count > 0) wg_array_read_rg(run->layout, &gp->out, count, gp->rb);
    if (bytes) *bytes += 8 * (size_t)count;
    if (candidates) *candidates = count;
    gp->io.candidates += count;
    gp->io.read_bytes += 8 * (long long)count;
    const int* leaf[2] = {sc->tri_bvh.leaf_of, sc->edge_bvh.leaf_of};
    for (int j = 0; j < count; ++j) {
        const int q = (int)gp->rb[2 * j], e = (int)gp->rb[2 * j + 1];
        gp->order[j] = (cand){q, leaf[q >= gp->n][e], e};
    }
    qsort(gp->order, (size_t)count, sizeof(cand), by_walk);
    for (int j = 0; j < count; ++j) {
        gp->list[2 * j] = gp->order[j].q;
        gp->list[2 * j + 1] = gp->order[j].elem;
    }
    return wc_self_pairs_from(sp, sc, m, f, xd, vd, h, he, gp->list, count);
}
