/* The smoothed prolongator's lists (wg_amg.h, wg_amg.smoothed): per level below the coarsest,
 * from core's symbolic build with prolong_weight > 0 (core/amg_build.c: P's pattern p_start /
 * p_col, p_self, a_to_p, its transpose pt_*, T = A P's pattern t_*; the next level's pattern is
 * P^T A P's), the gathers the setup's passes read: each entry of P its blocks of A
 * (amg_prolongator.glsl), each entry of T its products A_ik P_(k, J) (amg_ap.glsl), each block
 * of the next level its products P^T T (amg_ptap.glsl), each next-level node its entries of P
 * (amg_restrict_p.glsl), each node its row of P (amg_prolong.glsl). Uploaded once per cloth,
 * two items a texel, with rotations one list per pair of coarse nodes (upload_keyed); the values
 * are made per solve on the device. */
#include <string.h>

#include "gpu_error.h"
#include "wg_amg.h"

/* A group's items borrowed from another group (its range's w; amg_blocks.glsl ld_item) */
#define ALIAS_A 1 /* its items are its source's with a + 1 */
#define ALIAS_B 2 /* ... with b + 1 */

/* Items (a, b) keyed by group, counting-sorted (in order within a group): range per group
 * (first item, count << 5 | gz << 2 | flags: RG32I, amg_blocks.glsl ld_range; gz < 8), list two
 * items a texel (a0, b0, a1, b1: RGBA32I, ld_item). With rotations the coarse nodes come in pairs (2a, 2a + 1) and so
 * do the entries of P and T, whose lists for the odd one are the even one's shifted by one: a
 * group K with src[K] (1 + its source group, which has none) and fl[K] (ALIAS_A | ALIAS_B) lists
 * no items of its own where its items are exactly its source's so shifted (checked here; else
 * it keeps its own): its range is its source's, its w the shifts. The same products in the same
 * order: the sums are the unshared lists' bit for bit. */
static int upload_keyed(const wg_layout* L, wg_tex* range, wg_tex* list, int n_groups, int n_items, const int* key,
                        const int* a, const int* b, const int* gz, const int* src, const int* fl, char* err,
                        size_t el) {
    const wc_allocator* al = &L->alloc;
    int cap = (n_groups > n_items ? n_groups : n_items) + 1;
    int* start = wc_calloc(al, 4 * ((size_t)n_groups + 2), sizeof(int));
    int* sorted = wc_calloc(al, 2 * (size_t)cap, sizeof(int));
    int* v = wc_calloc(al, 4u * (size_t)cap, sizeof(int));
    int ok = 0;
    if (!start || !sorted || !v) {
        wg_errorf(err, el, "out of memory");
        goto done;
    }
    int *cur = start + n_groups + 2, *rs = cur + n_groups + 2, *rf = rs + n_groups + 2;
    for (int k = 0; k < n_items; ++k) ++start[key[k] + 1];
    for (int K = 0; K < n_groups; ++K) start[K + 1] += start[K];
    memcpy(cur, start, sizeof(int) * (size_t)n_groups);
    for (int k = 0; k < n_items; ++k) {
        int at = cur[key[k]]++;
        sorted[2 * at] = a[k];
        sorted[2 * at + 1] = b ? b[k] : 0;
    }
    for (int K = 0; K < n_groups; ++K) {
        rs[K] = K;
        rf[K] = 0;
        if (!src || !src[K]) continue;
        const int S = src[K] - 1, len = start[K + 1] - start[K];
        const int da = (fl[K] & ALIAS_A) != 0, db = (fl[K] & ALIAS_B) != 0;
        int same = src[S] == 0 && len == start[S + 1] - start[S];
        for (int t = 0; same && t < len; ++t)
            same = sorted[2 * (start[K] + t)] == sorted[2 * (start[S] + t)] + da &&
                   sorted[2 * (start[K] + t) + 1] == sorted[2 * (start[S] + t) + 1] + db;
        if (same) rs[K] = S, rf[K] = fl[K];
    }
    /* the groups that keep their items, in order: cur = their new first item */
    int at = 0;
    for (int K = 0; K < n_groups; ++K) {
        cur[K] = at;
        if (rs[K] != K) continue;
        for (int t = start[K]; t < start[K + 1]; ++t, ++at) {
            v[2 * at] = sorted[2 * t];
            v[2 * at + 1] = sorted[2 * t + 1];
        }
    }
    if (!wg_array_create(L, list, GL_RGBA32I, at > 0 ? (at + 1) / 2 : 1, v, err, el)) goto done;
    memset(v, 0, 4u * sizeof(int) * (size_t)cap);
    for (int K = 0; K < n_groups; ++K) {
        const int S = rs[K];
        const int len = start[S + 1] - start[S], bits = gz ? gz[K] : 0;
        if (len >= 1 << 26 || bits >= 8) {
            wg_errorf(err, el, "multigrid: a list of %d items does not fit its range texel", len);
            goto done;
        }
        v[2 * K] = cur[S];
        v[2 * K + 1] = len << 5 | bits << 2 | rf[K];
    }
    ok = wg_array_create(L, range, GL_RG32I, n_groups, v, err, el);
done:
    wc_free(al, start);
    wc_free(al, sorted);
    wc_free(al, v);
    return ok;
}

/* Level G's prolongator to N from core's levels F (G's) and C (N's). */
static int level_smooth(const wg_layout* L, wg_amg_level* G, wg_amg_level* N, const wc_amg_level* F,
                        const wc_amg_level* C, char* err, size_t el) {
    const wc_allocator* al = &L->alloc;
    const int n = F->n, np = F->p_start[n], nt = F->t_start[n], cpa = F->cpa;
    G->np = np;
    G->nt = nt;
    /* the products' count: T's (A_ik P_(k, .)) and P^T T's */
    long n_ap = 0, n_ptap = 0;
    for (int i = 0; i < n; ++i)
        for (int k = F->row_start[i]; k < F->row_start[i + 1]; ++k) n_ap += F->p_start[F->col[k] + 1] - F->p_start[F->col[k]];
    for (int s = 0; s < np; ++s) n_ptap += F->t_start[F->pt_row[s] + 1] - F->t_start[F->pt_row[s]];
    long cap = n_ap > n_ptap ? n_ap : n_ptap;
    if (cap < np) cap = np;
    if (cap < (long)cpa * F->n_blocks) cap = (long)cpa * F->n_blocks;
    if (cap < C->n_blocks) cap = C->n_blocks;
    if (cap < nt) cap = nt;
    if (cap < 4L * 2 * n) cap = 4L * 2 * n; /* P_tent's rows as float texels (rotations) */
    if (cap < 4L * (n > np ? n : np)) cap = 4L * (n > np ? n : np);
    if (cap > 0x7fffffffL / 4) {
        wg_errorf(err, el, "multigrid: the smoothed prolongator's lists are too long");
        return 0;
    }
    int* key = wc_calloc(al, (size_t)cap + 1, sizeof(int));
    int* ia = wc_calloc(al, (size_t)cap + 1, sizeof(int));
    int* ib = wc_calloc(al, (size_t)cap + 1, sizeof(int));
    int* src = wc_calloc(al, 2 * (size_t)cap + 2, sizeof(int)); /* upload_keyed's aliases */
    int* fl = src ? src + cap + 1 : NULL;
    int ok = 0;
    if (!key || !ia || !ib || !src) {
        wg_errorf(err, el, "out of memory");
        goto done;
    }
    /* P's entries (row, column, own aggregate, its P_tent block 2i + q) and each row's entries;
       key is int4 scratch here. With rotations (cpa 2) a row's own aggregate is its entries
       p_self, p_self + 1 (coarse nodes 2 agg(i) + q). */
    int* v = key;
    memset(v, 0, sizeof(int) * (size_t)cap);
    for (int i = 0; i < n; ++i)
        for (int e = F->p_start[i]; e < F->p_start[i + 1]; ++e) {
            const int q = e - F->p_self[i], own = q >= 0 && q < cpa;
            v[4 * e] = i;
            v[4 * e + 1] = F->p_col[e];
            v[4 * e + 2] = own;
            v[4 * e + 3] = own ? cpa * i + q : 0;
        }
    if (!wg_array_create(L, &G->p_ent, GL_RGBA32I, np, v, err, el)) goto done;
    memset(v, 0, sizeof(int) * (size_t)cap);
    for (int i = 0; i < n; ++i) {
        v[4 * i] = F->p_start[i];
        v[4 * i + 1] = F->p_start[i + 1];
    }
    if (!wg_array_create(L, &G->p_rows, GL_RGBA32I, n, v, err, el)) goto done;
    /* each entry's blocks of A: the strong ones of its column's aggregate, the weak onto its own,
       each with the P_tent block it multiplies (column j's to coarse node cpa agg + q; a weak
       block's: row i's own, core's lumping) */
    for (int i = 0; i < n; ++i)
        for (int k = F->row_start[i]; k < F->row_start[i + 1]; ++k)
            for (int q = 0; q < cpa; ++q) {
                const int m2 = cpa * k + q, strong = F->a_to_p[k] >= 0;
                key[m2] = (strong ? F->a_to_p[k] : F->p_self[i]) + q;
                ia[m2] = k;
                ib[m2] = cpa * (strong ? F->col[k] : i) + q;
            }
    /* with rotations an entry (i, 2a + 1) takes entry (i, 2a)'s blocks, each P_tent block + 1 */
    memset(src, 0, sizeof(int) * (2 * (size_t)cap + 2));
    for (int i = 0; cpa == 2 && i < n; ++i)
        for (int e = F->p_start[i] + 1; e < F->p_start[i + 1]; ++e)
            if ((F->p_col[e] & 1) && F->p_col[e - 1] == F->p_col[e] - 1) src[e] = e, fl[e] = ALIAS_B;
    if (!upload_keyed(L, &G->p_range, &G->p_list, np, cpa * F->n_blocks, key, ia, ib, NULL, src, fl, err, el))
        goto done;
    if (F->tent) { /* P_tent's blocks by rows: texel 2i + q, row r of core's row-major 3x3 block */
        float* fv = (float*)v;
        for (int r = 0; r < 3; ++r) {
            memset(fv, 0, sizeof(float) * 4 * (size_t)cpa * n);
            for (int t = 0; t < cpa * n; ++t)
                for (int c = 0; c < 3; ++c) fv[4 * t + c] = (float)F->tent[9 * (size_t)t + 3 * r + c];
            if (!wg_array_create(L, &G->tent[r], GL_RGBA32F, cpa * n, fv, err, el)) goto done;
        }
    }
    /* T = A P: entry (i, J) sums A_ik P_e over k in row i and e in row col(k) with column J */
    long m = 0;
    for (int i = 0; i < n; ++i)
        for (int k = F->row_start[i]; k < F->row_start[i + 1]; ++k)
            for (int e = F->p_start[F->col[k]]; e < F->p_start[F->col[k] + 1]; ++e, ++m) {
                key[m] = wc_amg_find(F->t_col, F->t_start[i], F->t_start[i + 1], F->p_col[e]);
                ia[m] = k;
                ib[m] = e;
                if (key[m] < 0) {
                    wg_errorf(err, el, "multigrid: T = A P entry (%d, %d) missing from its pattern", i, F->p_col[e]);
                    goto done;
                }
            }
    /* with rotations T's entry (i, 2a + 1) takes entry (i, 2a)'s products, each entry of P + 1 */
    memset(src, 0, sizeof(int) * (2 * (size_t)cap + 2));
    for (int i = 0; cpa == 2 && i < n; ++i)
        for (int q = F->t_start[i] + 1; q < F->t_start[i + 1]; ++q)
            if ((F->t_col[q] & 1) && F->t_col[q - 1] == F->t_col[q] - 1) src[q] = q, fl[q] = ALIAS_B;
    if (!upload_keyed(L, &G->t_range, &G->t_list, nt, (int)n_ap, key, ia, ib, NULL, src, fl, err, el)) goto done;
    /* the next level's block (I, J) sums P_(i, I)^T T_(i, J); with rotations block (I, J) takes
       block (I & ~1, J & ~1)'s products, its entry of P + (I & 1), of T + (J & 1) (core's slot
       pairs, core/amg_build.c ptap_*). Not kept: the blocks left of the diagonal as their mirrors'
       transposes (core's galerkin_pairs_ptap): 0.8 of 63 MiB at 10k particles, and the exactly
       symmetric levels took a little more iterations (docs/bench/gpu_solve.md). dz: the next level's
       dead unknowns (rotations: core's dead), a bit per row of its diagonal blocks (amg_ptap.glsl) */
    int* dz = wc_calloc(al, (size_t)C->n_blocks + 1, sizeof(int));
    if (!dz) {
        wg_errorf(err, el, "out of memory");
        goto done;
    }
    memset(src, 0, sizeof(int) * (2 * (size_t)cap + 2));
    for (int I = 0; cpa == 2 && I < C->n; ++I)
        for (int k = C->row_start[I]; k < C->row_start[I + 1]; ++k) {
            const int J = C->col[k];
            if (!(I & 1) && !(J & 1)) continue;
            const int k0 = wc_amg_find(C->col, C->row_start[I & ~1], C->row_start[(I & ~1) + 1], J & ~1);
            if (k0 < 0) continue; /* keeps its own products */
            src[k] = 1 + k0;
            fl[k] = ((I & 1) ? ALIAS_A : 0) | ((J & 1) ? ALIAS_B : 0);
        }
    if (C->dead)
        for (int I = 0; I < C->n; ++I)
            for (int r = 0; r < 3; ++r)
                if (C->dead[3 * I + r]) dz[C->diag[I]] |= 1 << r;
    m = 0;
    for (int I = 0; I < C->n; ++I)
        for (int s = F->pt_start[I]; s < F->pt_start[I + 1]; ++s) {
            const int e = F->pt_entry[s], i = F->pt_row[s];
            for (int q = F->t_start[i]; q < F->t_start[i + 1]; ++q, ++m) {
                key[m] = wc_amg_find(C->col, C->row_start[I], C->row_start[I + 1], F->t_col[q]);
                ia[m] = e;
                ib[m] = q;
                if (key[m] < 0) {
                    wg_errorf(err, el, "multigrid: block (%d, %d) missing from the level's pattern", I, F->t_col[q]);
                    wc_free(al, dz);
                    goto done;
                }
            }
        }
    int up = upload_keyed(L, &N->gal_range, &N->gal_list, C->n_blocks, (int)n_ptap, key, ia, ib, dz, src, fl, err, el);
    wc_free(al, dz);
    if (!up) goto done;
    /* the restriction: each next-level node's entries of P (P^T's rows) */
    for (int I = 0; I < C->n; ++I)
        for (int s = F->pt_start[I]; s < F->pt_start[I + 1]; ++s) {
            key[s] = I;
            ia[s] = F->pt_entry[s];
            ib[s] = F->pt_row[s];
        }
    /* with rotations node 2a + 1 takes node 2a's, each entry of P + 1 */
    memset(src, 0, sizeof(int) * (2 * (size_t)cap + 2));
    for (int I = 1; cpa == 2 && I < C->n; I += 2) src[I] = I, fl[I] = ALIAS_A;
    if (!upload_keyed(L, &G->pt_range, &G->pt_list, C->n, np, key, ia, ib, NULL, src, fl, err, el)) goto done;
    for (int c = 0; c < 3; ++c) {
        if (!wg_array_create(L, &G->p[c], GL_RGBA32F, np, NULL, err, el)) goto done;
        if (!wg_array_create(L, &G->t[c], GL_RGBA32F, nt, NULL, err, el)) goto done;
    }
    ok = wg_array_create(L, &G->res, GL_RGBA32F, n, NULL, err, el);
done:
    wc_free(al, key);
    wc_free(al, ia);
    wc_free(al, ib);
    wc_free(al, src);
    return ok;
}

int wg_amg_smooth_create(wg_amg* a, const wc_amg* ca, char* err, size_t el) {
    for (int l = 0; l + 1 < ca->n_levels; ++l)
        if (!level_smooth(a->run->layout, &a->lev[l], &a->lev[l + 1], &ca->lev[l], &ca->lev[l + 1], err, el)) return 0;
    return 1;
}
