/* The idle proof of a GPU cloth's self-collision stage (wg_self_idle.h). */
#include "wg_self_idle.h"

#include <GL/glew.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_error.h"
#include "wg_passes.h"

#define WAIT_MAX 8   /* the most substeps the proof waits after failing (the back-off) */
#define REL 1e-3   /* the thresholds' relative margin (thickness, eta), and mu / thickness */

/* One tree on the GPU: its nodes (2 texels each, refitted every proof) and its nodes by height. */
typedef struct idle_tree {
    int n_nodes, n_heights;
    int* first;                 /* (n_heights + 1) the order's first node of each height */
    wg_tex node, order;
} idle_tree;

struct wg_self_idle {
    wg_runner* run;
    wc_allocator alloc;
    wg_self_idle_mode mode;
    int mutation;               /* MUTATE_*: tests only */
    int n, nt, ne;
    double thickness, eta;
    idle_tree tri, edge;
    wg_tex elem, part, seam, xs, counter;
    wg_tex list;                /* 13 texels a listed pair (the GPU's proximity pass), room cap */
    int cap;                    /* 0: no list */
    int tried;                  /* this substep's (stage's) start made the copy: the proof runs at its end */
    int failures, wait;         /* proofs failed in a row; substeps left before the next try */
};

/* the tests' mutations of the proof (WEFT_GPU_SELF_IDLE_MUTATION) */
enum { MUTATE_NONE, MUTATE_NO_DELTA, MUTATE_NO_SHARED, MUTATE_NO_MARGIN };

wg_self_idle_mode wg_self_idle_env(void) {
    const char* e = getenv("WEFT_GPU_SELF_IDLE");
    if (!e || !*e || strcmp(e, "on") == 0) return WG_SELF_IDLE_ON;
    return strcmp(e, "check") == 0 ? WG_SELF_IDLE_CHECK : WG_SELF_IDLE_OFF;
}

static int mutation_env(void) {
    const char* e = getenv("WEFT_GPU_SELF_IDLE_MUTATION");
    if (!e) return MUTATE_NONE;
    return strcmp(e, "no-delta") == 0    ? MUTATE_NO_DELTA
           : strcmp(e, "no-shared") == 0 ? MUTATE_NO_SHARED
           : strcmp(e, "no-margin") == 0 ? MUTATE_NO_MARGIN
                                         : MUTATE_NONE;
}

wg_self_idle_mode wg_self_idle_get_mode(const wg_self_idle* si) { return si->mode; }

static void tree_free(idle_tree* t, wc_allocator* a, int gl) {
    if (gl) {
        wg_tex_destroy(&t->node);
        wg_tex_destroy(&t->order);
    }
    wc_free(a, t->first);
}

void wg_self_idle_destroy(wg_self_idle* si, int gl) {
    if (!si) return;
    wc_allocator a = si->alloc;
    tree_free(&si->tri, &a, gl);
    tree_free(&si->edge, &a, gl);
    if (gl) {
        wg_tex_destroy(&si->elem);
        wg_tex_destroy(&si->part);
        wg_tex_destroy(&si->seam);
        wg_tex_destroy(&si->xs);
        wg_tex_destroy(&si->counter);
        wg_tex_destroy(&si->list);
    }
    wc_free(&a, si);
}

size_t wg_self_idle_bytes(const wg_self_idle* si) {
    if (!si) return 0;
    const wg_tex* t[] = {&si->tri.node, &si->tri.order, &si->edge.node, &si->edge.order, &si->elem,
                         &si->part,     &si->seam,      &si->xs,        &si->counter, &si->list};
    size_t bytes = 0;
    for (int k = 0; k < (int)(sizeof t / sizeof t[0]); ++k) bytes += t[k]->id ? wg_tex_bytes(t[k]) : 0;
    return bytes;
}

/* The tree b's nodes and their order by height (leaves 0; a node 1 + its children's highest:
 * a height's nodes depend only on lower ones), staged in o (room for 8 floats a node) and h
 * (an int a node). */
static int tree_upload(wg_self_idle* si, idle_tree* t, const wc_bvh* b, float* o, int* h, char* err, size_t err_len) {
    const wg_layout* L = si->run->layout;
    t->n_nodes = b->n_nodes;
    const int top = wc_bvh_heights(b, h);
    t->n_heights = top + 1;
    t->first = wc_calloc(&si->alloc, (size_t)t->n_heights + 2, sizeof(int));
    if (!t->first) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    for (int j = 0; j < b->n_nodes; ++j) ++t->first[h[j] + 1];
    for (int k = 0; k < t->n_heights; ++k) t->first[k + 1] += t->first[k];
    int* at = (int*)(o + 8 * (size_t)b->n_nodes);   /* past the nodes' texels: room for n ints */
    memcpy(at, t->first, (size_t)t->n_heights * sizeof(int));
    float* ord = o;   /* the order first (4 floats a node), then the nodes over it */
    for (int j = 0; j < b->n_nodes; ++j) {
        float* q = ord + 4 * (size_t)at[h[j]]++;
        q[0] = (float)j;
        q[1] = q[2] = q[3] = 0.0f;
    }
    int nn = b->n_nodes > 0 ? b->n_nodes : 1;
    if (!wg_array_create(L, &t->order, GL_RGBA32F, nn, ord, err, err_len)) return 0;
    memset(o, 0, 8 * (size_t)nn * sizeof(float));
    for (int j = 0; j < b->n_nodes; ++j) {
        o[8 * (size_t)j + 3] = (float)b->child[2 * j];
        o[8 * (size_t)j + 7] = (float)b->child[2 * j + 1];
    }
    return wg_array_create(L, &t->node, GL_RGBA32F, 2 * nn, o, err, err_len);
}

int wg_self_idle_create(wg_runner* run, const wc_self* sc, const wc_model* m, wg_self_idle_mode mode, int cap,
                        wg_self_idle** out, char* err, size_t err_len) {
    *out = NULL;
    wc_allocator a = sc->alloc;
    wg_self_idle* si = wc_calloc(&a, 1, sizeof *si);
    if (!si) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    si->run = run;
    si->alloc = a;
    si->mode = mode;
    si->mutation = mutation_env();
    si->n = sc->n;
    si->nt = sc->n_tris;
    si->ne = sc->n_edges;
    si->thickness = sc->thickness;
    si->eta = sc->eta;
    si->cap = cap > 0 ? cap : 0;
    const int n_seam = sc->seam_start ? sc->seam_start[sc->n] : 0;
    size_t room = 4 * ((size_t)si->nt + si->ne + si->n + n_seam + 4);
    size_t rt = 12 * ((size_t)sc->tri_bvh.n_nodes + sc->edge_bvh.n_nodes + 2);
    if (rt > room) room = rt;
    float* o = wc_calloc(&a, room, sizeof(float));
    int* h = wc_calloc(&a, (size_t)sc->tri_bvh.n_nodes + sc->edge_bvh.n_nodes + 2, sizeof(int));
    const wg_layout* L = run->layout;
    int ok = o && h;
    if (!ok) wg_errorf(err, err_len, "out of memory");
    ok = ok && tree_upload(si, &si->tri, &sc->tri_bvh, o, h, err, err_len) &&
         tree_upload(si, &si->edge, &sc->edge_bvh, o, h, err, err_len);
    if (ok) {
        for (int t = 0; t < si->nt; ++t)
            for (int c = 0; c < 4; ++c) o[4 * (size_t)t + c] = c < 3 ? (float)m->tris[3 * t + c] : 0.0f;
        for (int e = 0; e < si->ne; ++e) {
            float* q = o + 4 * ((size_t)si->nt + e);
            q[0] = (float)sc->edges[2 * e];
            q[1] = (float)sc->edges[2 * e + 1];
            q[2] = -1.0f;
            q[3] = 0.0f;
        }
        ok = wg_array_create(L, &si->elem, GL_RGBA32F, si->nt + si->ne > 0 ? si->nt + si->ne : 1, o, err, err_len);
    }
    if (ok) {
        for (int i = 0; i < si->n; ++i) {
            float* q = o + 4 * (size_t)i;
            q[0] = sc->seam_start ? (float)sc->seam_start[i] : 0.0f;
            q[1] = sc->seam_start ? (float)sc->seam_start[i + 1] : 0.0f;
            q[2] = sc->tangled[i] ? 1.0f : 0.0f;
            q[3] = 0.0f;
        }
        ok = wg_array_create(L, &si->part, GL_RGBA32F, si->n > 0 ? si->n : 1, o, err, err_len);
    }
    if (ok) {
        memset(o, 0, 4 * ((size_t)n_seam + 1) * sizeof(float));
        for (int k = 0; k < n_seam; ++k) o[4 * (size_t)k] = (float)sc->seam_nbr[k];
        ok = wg_array_create(L, &si->seam, GL_RGBA32F, n_seam > 0 ? n_seam : 1, o, err, err_len) &&
             wg_array_create(L, &si->xs, GL_RGBA32F, si->n > 0 ? si->n : 1, NULL, err, err_len) &&
             wg_tex_create(&si->counter, GL_R32I, 1, 1, NULL, err, err_len) &&
             wg_array_create(L, &si->list, GL_RGBA32F, si->cap > 0 ? 13 * si->cap : 1, NULL, err, err_len);
    }
    wc_free(&a, o);
    wc_free(&a, h);
    if (!ok) {
        wg_self_idle_destroy(si, 1);
        return 0;
    }
    *out = si;
    return 1;
}

int wg_self_idle_begin(wg_self_idle* si, const wg_tex* x) {
    si->tried = si->mode == WG_SELF_IDLE_CHECK || si->wait == 0;
    if (si->tried)
        wg_copy(si->run, &si->xs, x);
    else
        --si->wait;
    return si->tried;
}

void wg_self_idle_trees(const wg_self_idle* si, wg_self_trees* out) {
    const idle_tree* t[2] = {&si->tri, &si->edge};
    for (int k = 0; k < 2; ++k) {
        out->node[k] = &t[k]->node;
        out->order[k] = &t[k]->order;
        out->first[k] = t[k]->first;
        out->n_heights[k] = t[k]->n_heights;
    }
    out->elem = &si->elem;
    out->part = &si->part;
    out->seam = &si->seam;
}

const wg_tex* wg_self_idle_start(const wg_self_idle* si) { return &si->xs; }

/* One tree refitted over the boxes of its elements (elements from elem0 in elem). */
static void refit(wg_self_idle* si, const idle_tree* t, int elem0, const wg_tex* x, double pad) {
    wg_runner* run = si->run;
    WG_USE(run, WGP_SELF_IDLE_REFIT_GROUPS, &(wg_self_idle_refit_in){.order = &t->order, .elem = &si->elem, .x = x,
        .xs = &si->xs});
    wg_u1i(run, "u_elem0", elem0);
    wg_u1f(run, "u_pad", pad);
    wg_run_by_height(run, t->first, t->n_heights, &t->node);
}

/* The walk of the proof (listing the pairs that may act when list, the refined test when
 * refined, too_far with margin to spare); returns the counter. */
static int walk(wg_self_idle* si, const wg_tex* x, const wg_tex* v, int list, int refined, double margin_m,
                long long* bytes) {
    wg_runner* run = si->run;
    const int margin = si->mutation != MUTATE_NO_MARGIN;
    const double rel = margin ? REL : 0.0, pad = si->thickness * (1.0 + rel);
    /* the mutation without delta: the end positions taken as the start's */
    const wg_tex* xe = si->mutation == MUTATE_NO_DELTA ? &si->xs : x;
    refit(si, &si->tri, 0, xe, pad);
    if (si->ne > 0) refit(si, &si->edge, si->nt, xe, pad);
    const GLint zero = 0;
    wg_tex_upload(&si->counter, 0, 0, 1, 1, &zero);
    WG_USE(run, WGP_SELF_IDLE_WALK_GROUPS, &(wg_self_idle_walk_in){.tnode = &si->tri.node, .enode = &si->edge.node,
        .elem = &si->elem, .x = xe, .xs = &si->xs, .v = v, .part = &si->part, .seam = &si->seam});
    wg_u1i(run, "u_cap", list ? si->cap : 0);
    wg_u1i(run, "u_refined", refined);
    wg_u1i(run, "u_np", si->n);
    wg_u1i(run, "u_nt", si->nt);
    wg_u1i(run, "u_shared", si->mutation != MUTATE_NO_SHARED);
    wg_u1f(run, "u_th", si->thickness);
    wg_u1f(run, "u_eta", si->eta);
    wg_u1f(run, "u_rel", rel);
    wg_u1f(run, "u_mu", rel * si->thickness);
    wg_u1f(run, "u_ulp", margin ? 1.0 : 0.0);
    wg_u1f(run, "u_margin", margin_m);
    const int nq = si->n + si->ne;
    wg_run_groups_scratch(run, nq, (nq + 63) / 64, (const wg_tex* const[]){&si->list}, 1, &si->counter);
    GLint count = 0, prev = 0;   /* the counter: a synchronisation with the GPU */
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev);
    glBindTexture(GL_TEXTURE_2D, si->counter.id);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED_INTEGER, GL_INT, &count);
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev);
    *bytes += (long long)sizeof(GLint);
    return count;
}

int wg_self_idle_count(wg_self_idle* si, const wg_tex* x, long long* bytes) {
    if (si->nt == 0) return 0;   /* core's stage does nothing without triangles */
    const int count = walk(si, x, x, 0, 0, 0.0, bytes);
    wg_self_idle_outcome(si, count > 0);
    return count;
}

int wg_self_idle_list(wg_self_idle* si, const wg_tex* x, const wg_tex* v, int refined, float* out, long long* bytes) {
    if (si->nt == 0) return 0;
    const int count = walk(si, x, v, 1, refined, refined ? 0.0 : wg_self_idle_margin(si), bytes);
    if (count > 0 && count <= si->cap) {
        wg_array_read(si->run->layout, &si->list, 13 * count, out);
        *bytes += 13LL * 16 * count;
    }
    return count;
}

int wg_self_idle_cap(const wg_self_idle* si) { return si->cap; }

double wg_self_idle_margin(const wg_self_idle* si) {
    /* at most (thickness - eta)(1 + rel): the walk's culling (d0 > max_rel + thickness (1 + rel))
       keeps proving too_far with it */
    return si->cap > 0 ? WG_SELF_IDLE_MARGIN * si->thickness : 0.0;
}

void wg_self_idle_outcome(wg_self_idle* si, int acted) {
    /* the back-off: after k >= 2 failures in a row, the next min(2^(k-2), WAIT_MAX) substeps untried */
    si->failures = acted ? si->failures + 1 : 0;
    si->wait = si->failures < 2 ? 0 : si->failures > 5 ? WAIT_MAX : 1 << (si->failures - 2);
}
