/* The penalty pairs' cross terms in the GPU multigrid's levels (wg_amg.h, "cross terms"): each
 * level's lists, built on the host after each wg_pairs_find and uploaded: the terms c u_k u_j^T
 * (slots k != j of a pair) grouped per pair of nodes into blocks, which amg_cross_blocks.glsl sums
 * per setup and amg_level_inputs.glsl reads, so that a product costs a few blocks a node where
 * the slots of an aggregate's pairs are hundreds (docs/bench/gpu_amg_cross.md). */
#include <string.h>

#include "gpu_error.h"
#include "wg_amg.h"
#include "wg_pairs.h"

/* A pair's slot k couples with its 3 others: at most this many terms c u_k u_j^T per pair. */
#define TERMS_PER_PAIR 12
/* The finest level's room for blocks: this many a pair of the capacity (the two layers of
 * tests/test_gpu_amg_cross.c: 3.9 terms a block); a substep that needs more leaves the terms out
 * of the levels (cross_dropped), as core drops the terms its entries cannot hold. */
#define BLOCKS_PER_PAIR 3

int wg_amg_pairs_create(wg_amg* a, int cap, char* err, size_t el) {
    const wg_layout* L0 = a->run->layout;
    const int n0 = a->lev[0].n;
    const size_t terms = (size_t)TERMS_PER_PAIR * (size_t)cap;
    a->cross_buf = wc_calloc(&L0->alloc, 4u * ((size_t)n0 + terms + terms / 4u + 1u), sizeof(int));
    a->cross_cnt = wc_calloc(&L0->alloc, (size_t)n0 + 1, sizeof(int));
    a->cross_scratch = wc_calloc(&L0->alloc, (size_t)n0 + 8u * terms + 1u, sizeof(int));
    if (!a->cross_buf || !a->cross_cnt || !a->cross_scratch) {
        wg_errorf(err, el, "out of memory");
        return 0;
    }
    if (!wg_array_create(L0, &a->cross_u, GL_RGBA32F, 4 * cap, NULL, err, el)) return 0;
    size_t items = terms, bcap = (size_t)BLOCKS_PER_PAIR * (size_t)cap;
    for (int l = 0; l < a->n_levels; ++l) {
        /* a level's blocks: at most n^2, and at most the finer level's (each sums one or more) */
        wg_amg_level* G = &a->lev[l];
        const size_t nn = (size_t)G->n * (size_t)G->n;
        if (nn < bcap) bcap = nn;
        G->cross_bcap = (int)bcap;
        if (!wg_array_create(L0, &G->cross_i, GL_RGBA32I, G->n + (int)bcap + (int)((items + 3) / 4), NULL, err, el) ||
            !wg_array_create(L0, &G->cross_a, GL_RGBA32F, 3 * (int)bcap, NULL, err, el))
            return 0;
        items = bcap; /* the next level's items: this level's blocks */
    }
    a->cross_cap = cap;
    return 1;
}

/* The scratch's arrays (wg_amg_pairs_create): per item to group (a term on the finest level, a
 * finer level's block below) its row and column particles (any particle of the node: node_of
 * maps it on each level) and its code in the list (slot k's 4 q + k times 4 plus j's offset m,
 * slot j = 4 q + (k + m) mod 4; or the finer block); the same sorted by row; per item its block;
 * per block its items' start; a row's block of each column. */
typedef struct scratch {
    int *row, *col, *code, *s_row, *s_col, *s_code, *bid, *bst, *mark;
} scratch;

static scratch scratch_of(const wg_amg* a) {
    const size_t T = (size_t)TERMS_PER_PAIR * (size_t)a->cross_cap;
    int* m = a->cross_scratch;
    scratch s = {m, m + T, m + 2 * T, m + 3 * T, m + 4 * T, m + 5 * T, m + 6 * T, m + 7 * T, m + 8 * T + 1};
    return s;
}

/* Level l's list from its ni items (s.row ..), into v (amg_level_inputs.glsl, amg_cross_blocks.glsl):
 * per node (first block entry, end, its diagonal block or -1, n: the block of entry h is h - n);
 * per block entry (column node, its items' first, end, the items' first texel); the items' codes,
 * 4 a texel. Returns the texels of v, or -1 where the blocks are more than the level's room;
 * the level's blocks into cross_nb, and leaves them as the next level's items. */
static int level_entries(wg_amg* a, int l, int ni, int* v) {
    wg_amg_level* G = &a->lev[l];
    const int nl = G->n;
    const int* node = a->node_of + (size_t)l * a->lev[0].n;
    const scratch s = scratch_of(a);
    int* cnt = a->cross_cnt; /* nl + 1: items per row, then the rows' ends */
    memset(cnt, 0, sizeof(int) * ((size_t)nl + 1));
    for (int t = 0; t < ni; ++t) ++cnt[node[s.row[t]] + 1];
    for (int I = 0; I < nl; ++I) cnt[I + 1] += cnt[I];
    for (int t = 0; t < ni; ++t) {
        const int u = cnt[node[s.row[t]]]++;
        s.s_row[u] = s.row[t];
        s.s_col[u] = s.col[t];
        s.s_code[u] = s.code[t];
    }
    /* blocks: a row's distinct columns, in the order met */
    for (int I = 0; I < nl; ++I) s.mark[I] = -1;
    int nb = 0;
    for (int I = 0, t0 = 0; I < nl; t0 = cnt[I++]) {
        v[4 * (size_t)I] = nl + nb;
        for (int t = t0; t < cnt[I]; ++t) {
            const int J = node[s.s_col[t]];
            if (s.mark[J] < 0) {
                s.mark[J] = nb;
                s.bst[nb + 1] = 0;
                s.row[nb] = s.s_row[t];   /* the block's particles (s.row, s.col: read no more) */
                s.col[nb] = s.s_col[t];
                ++nb;
            }
            s.bid[t] = s.mark[J];
            ++s.bst[s.mark[J] + 1];
        }
        for (int t = t0; t < cnt[I]; ++t) s.mark[node[s.s_col[t]]] = -1;
        v[4 * (size_t)I + 1] = nl + nb;
    }
    G->cross_nb = 0;
    if (nb > G->cross_bcap) return -1;
    const int t_at = nl + nb; /* the items' first texel */
    for (int I = 0; I < nl; ++I) {
        int* head = v + 4 * (size_t)I;
        head[2] = -1;
        head[3] = nl;
        for (int h = head[0]; h < head[1]; ++h)
            if (node[s.col[h - nl]] == I) head[2] = h - nl;
    }
    s.bst[0] = 0;
    for (int b = 0; b < nb; ++b) s.bst[b + 1] += s.bst[b];
    for (int b = 0; b < nb; ++b) {
        int* en = v + 4 * ((size_t)nl + (size_t)b);
        en[0] = node[s.col[b]];
        en[1] = s.bst[b];
        en[2] = s.bst[b + 1];
        en[3] = t_at;
    }
    int* code = v + 4 * (size_t)t_at;
    for (int t = 0; t < ni; ++t) code[s.bst[s.bid[t]]++] = s.s_code[t];
    for (int t = ni; t < ((ni + 3) & ~3); ++t) code[t] = 0;
    for (int b = 0; b < nb; ++b) s.code[b] = b;
    G->cross_nb = nb;
    return t_at + (ni + 3) / 4;
}

/* The finest level's items: the terms c u_k u_j^T, slots k != j of a pair, both used (weight not
 * 0); returns their count. */
static int pair_terms(const wg_amg* a, int np, const int* ip, const float* w) {
    const scratch s = scratch_of(a);
    int ni = 0;
    for (int e = 0; e < 4 * np; ++e) {
        if (w[e] == 0.0f) continue;
        for (int m = 1; m < 4; ++m) {
            const int j = (e & ~3) + (((e & 3) + m) & 3);
            if (w[j] == 0.0f) continue;
            s.row[ni] = ip[e];
            s.col[ni] = ip[j];
            s.code[ni++] = 4 * e + m;
        }
    }
    return ni;
}

void wg_amg_set_pairs(wg_amg* a, const struct wg_pairs* p) {
    a->cross_n = 0;
    a->cross_levels = 0;
    a->pairs = p;
    if (!a->cross_cap || !wg_pairs_on(p)) return;
    const int* ip = NULL;
    const float* w = NULL;
    const int np = wg_pairs_debug_list(p, &ip, &w, NULL);
    if (np <= 0 || np > a->cross_cap) return;
    int ni = pair_terms(a, np, ip, w);
    for (int l = 0; l < a->n_levels; ++l) {
        const int texels = level_entries(a, l, ni, a->cross_buf);
        if (texels < 0) { /* more blocks than the room: the terms out of the levels this substep */
            ++a->cross_dropped;
            return;
        }
        wg_array_upload(a->run->layout, &a->lev[l].cross_i, texels, a->cross_buf);
        ni = a->lev[l].cross_nb;
    }
    /* which levels take them: those whose cross blocks are a large enough share of their blocks */
    a->cross_levels = 0;
    for (int l = 0; l < a->n_levels; ++l) {
        wg_amg_level* G = &a->lev[l];
        /* a smoothed prolongator does not restrict a pair's vector to the same u_k at its coarse
           nodes: its terms stay on the finest level */
        G->cross_use = G->cross_nb > 0 && G->cross_nb >= a->cross_share[l > 0] * G->nb && !(a->smoothed && l > 0);
        a->cross_levels += G->cross_use;
    }
    a->cross_n = np;
}

const int* wg_amg_debug_cross_lists(wg_amg* a, int l, int* texels) {
    *texels = 0;
    if (!a->cross_n || l < 0 || l >= a->n_levels) return NULL;
    const int* ip = NULL;
    const float* w = NULL;
    const int np = wg_pairs_debug_list(a->pairs, &ip, &w, NULL);
    int ni = pair_terms(a, np, ip, w);
    for (int k = 0; k <= l; ++k) {
        *texels = level_entries(a, k, ni, a->cross_buf);
        ni = a->lev[k].cross_nb;
    }
    return a->cross_buf;
}
