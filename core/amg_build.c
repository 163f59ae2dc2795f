/* The multigrid hierarchy's patterns, built once per model (amg.h): aggregates, the smoothed
 * prolongator's pattern and transpose, the patterns of T = A P and of the Galerkin operators. */
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "bsr_rows.h"

wc_amg_opts wc_default_amg_opts(void) {
    wc_amg_opts o;
    o.coarse_max = 96;
    o.sweeps = 2;
    o.smooth_weight = 1.0;
    o.prolong_weight = 4.0 / 3.0;
    o.power_iterations = 6;
    o.chebyshev = 1;
    o.chebyshev_ratio = 10.0;
    o.rotations = 1;
    o.pair_blocks = 1;
    o.aggressive = 0;
    o.current_positions = 1;
    o.lanczos = 1;
    o.coarse_iterations = 0;
    o.couplings = 1;
    o.cross_dense_dofs = WC_AMG_CROSS_DENSE_DOFS;
    o.bound_reuse = 1;
    o.bound_carry = 7;
    o.bound_margin = 1.05;
    o.values = 1;
    o.single = 1;
    o.single_x = 1;
    o.single_setup = 1;
    o.smooth_vector = 1;
    return o;
}

void wc_amg_start_vector(double* v, int n) { wc_amg_start_vector_rows(v, 0, n); }

void wc_amg_start_vector_rows(double* v, int lo, int hi) {
    for (int k = 3 * lo; k < 3 * hi; ++k)
        v[k] = (((unsigned)k * 2654435761u) >> 31 ? 1.0 : -1.0) * (1.0 + ((((unsigned)k * 40503u) >> 8) & 15) / 16.0);
}

static int cmp_int(const void* a, const void* b) {
    int x = *(const int*)a, y = *(const int*)b;
    return (x > y) - (x < y);
}

/* 1 when block k of a level is strong (the diagonal always is). */
static int is_strong(const wc_amg_level* L, int k) { return !L->strong || L->strong[k]; }

/* Vanek's greedy aggregation over the strong graph of units of g nodes (g = L->group: the pairs
 * of a rotation level are aggregated whole); agg gets each node's aggregate; returns the number
 * of aggregates. pending: n ints. */
static int aggregate(const wc_amg_level* L, int* agg, int* pending) {
    const int g = L->group, nu = L->n / g;
    int n_agg = 0;
#define UNIT_BLOCKS(u, k) \
    for (int i_ = g * (u); i_ < g * (u) + g; ++i_) \
        for (int k = L->row_start[i_]; k < L->row_start[i_ + 1]; ++k)
    for (int u = 0; u < nu; ++u) agg[u] = -1;
    /* 1: a unit whose strong neighbours are all free starts an aggregate of them all */
    for (int u = 0; u < nu; ++u) {
        if (agg[u] >= 0) continue;
        int free_all = 1;
        UNIT_BLOCKS(u, k) if (is_strong(L, k) && agg[L->col[k] / g] >= 0) free_all = 0;
        if (!free_all) continue;
        UNIT_BLOCKS(u, k) if (is_strong(L, k)) agg[L->col[k] / g] = n_agg;
        agg[u] = n_agg++;
    }
    /* 2: the rest join the aggregate they have most strong connections to (phase-1 ones only) */
    for (int u = 0; u < nu; ++u) {
        pending[u] = -1;
        if (agg[u] >= 0) continue;
        int best = -1, best_count = 0;
        UNIT_BLOCKS(u, k) {
            if (!is_strong(L, k) || agg[L->col[k] / g] < 0) continue;
            int a = agg[L->col[k] / g], count = 0;
            UNIT_BLOCKS(u, q) if (is_strong(L, q) && agg[L->col[q] / g] == a) ++count;
            if (count > best_count || (count == best_count && a < best)) {
                best = a;
                best_count = count;
            }
        }
        pending[u] = best;
    }
    for (int u = 0; u < nu; ++u)
        if (agg[u] < 0 && pending[u] >= 0) agg[u] = pending[u];
    /* 3: anything left (cannot happen on a connected graph; kept for safety) */
    for (int u = 0; u < nu; ++u) {
        if (agg[u] >= 0) continue;
        UNIT_BLOCKS(u, k) if (is_strong(L, k) && agg[L->col[k] / g] < 0) agg[L->col[k] / g] = n_agg;
        agg[u] = n_agg++;
    }
#undef UNIT_BLOCKS
    /* units to nodes, downwards (i / g <= i is read before it is overwritten) */
    for (int i = L->n - 1; i >= 0; --i) agg[i] = agg[i / g];
    return n_agg;
}

/* Sorted unique values of buf[0..len) in place; returns the new length. */
static int sort_unique(int* buf, int len) {
    if (len < 2) return len;
    qsort(buf, (size_t)len, sizeof *buf, cmp_int);
    int m = 1;
    for (int k = 1; k < len; ++k)
        if (buf[k] != buf[m - 1]) buf[m++] = buf[k];
    return m;
}

/* Aggressive coarsening (wc_amg_opts.aggressive): the aggregates of the aggregates' strong graph,
 * composed into agg (n); returns the number of aggregates, or -1 when out of memory. */
static int aggregate_again(wc_amg* a, const wc_amg_level* L, int* agg, int n_agg, int* pending) {
    const wc_allocator* al = &a->alloc;
    wc_amg_level G;
    memset(&G, 0, sizeof G);
    G.n = n_agg;
    G.group = 1;
    int* start = WC_NEW(al, int, n_agg + 1);
    int* col = WC_NEW(al, int, L->n_blocks + 1);
    int* fill = WC_NEW(al, int, n_agg + 1);
    int* agg2 = WC_NEW(al, int, n_agg + 1);
    int* pend2 = WC_NEW(al, int, n_agg + 1);
    int result = -1;
    if (!start || !col || !fill || !agg2 || !pend2) goto done;
    for (int i = 0; i < L->n; ++i)
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            if (is_strong(L, k)) ++start[agg[i] + 1];
    for (int g = 0; g < n_agg; ++g) start[g + 1] += start[g];
    for (int g = 0; g < n_agg; ++g) fill[g] = start[g];
    for (int i = 0; i < L->n; ++i)
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            if (is_strong(L, k)) col[fill[agg[i]]++] = agg[L->col[k]];
    int nnz = 0; /* sort and deduplicate each row, compacting in place */
    for (int g = 0; g < n_agg; ++g) {
        int lo = start[g], len = sort_unique(col + lo, start[g + 1] - lo);
        memmove(col + nnz, col + lo, sizeof(int) * (size_t)len);
        start[g] = nnz;
        nnz += len;
    }
    start[n_agg] = nnz;
    G.row_start = start;
    G.col = col;
    G.n_blocks = nnz;
    result = aggregate(&G, agg2, pend2);
    for (int i = 0; i < L->n; ++i) agg[i] = agg2[agg[i]];
done:
    wc_free(al, start);
    wc_free(al, col);
    wc_free(al, fill);
    wc_free(al, agg2);
    wc_free(al, pend2);
    (void)pending;
    return result;
}

#define TRY(p) \
    do {       \
        if (!(p)) goto oom; \
    } while (0)

/* The Galerkin products' gather lists of a pair level (cpa 2; amg.h, amg_setup.c): for T = A P,
 * each slot pair's products (A's block k, P's entry e) in the order the row walk over k, then e
 * meets them, from the row's first slot that P^T T reads on (t_read: the products there take the
 * blocks (I, J) with J >= I only, and P's row i has no column below its first); for P^T T, each
 * slot pair (I = 2a, J >= I) of the next level's rows 2a, its products (P's entry of (i, I), T's
 * slot (i, J)) in P^T's order; for the smoothed prolongator, each entry pair's strong blocks.
 * Counted, then filled in order (a stable counting sort). */
static int galerkin_lists(wc_amg* a, wc_amg_level* L, const wc_amg_level* N) {
    const wc_allocator* al = &a->alloc;
    const int n = L->n, n_tp = L->t_start[n] / 2, n_np = N->row_start[N->n] / 2;
    int* cursor = NULL;
    TRY(L->t_read = WC_NEW(al, int, n));
    TRY(L->ap_start = WC_NEW(al, int, n_tp + 1));
    TRY(L->ptap_start = WC_NEW(al, int, n_np + 1));
    TRY(cursor = WC_NEW(al, int, (n_tp > n_np ? n_tp : n_np) + 1));
    for (int i = 0; i < n; ++i) {
        int s = L->t_start[i];
        while (s < L->t_start[i + 1] && L->t_col[s] < L->p_col[L->p_start[i]]) s += 2;
        L->t_read[i] = s;
    }
    for (int pass = 0; pass < 2; ++pass) { /* T = A P */
        for (int i = 0; i < n; ++i)
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int j = L->col[k], slot = L->t_start[i];
                for (int e = L->p_start[j]; e < L->p_start[j + 1]; e += 2) {
                    while (L->t_col[slot] != L->p_col[e]) ++slot;
                    if (slot < L->t_read[i]) continue;
                    if (pass == 0) {
                        ++L->ap_start[slot / 2 + 1];
                    } else {
                        int m = cursor[slot / 2]++;
                        L->ap_src[2 * m] = k;
                        L->ap_src[2 * m + 1] = e;
                    }
                }
            }
        if (pass == 0) {
            for (int q = 0; q < n_tp; ++q) L->ap_start[q + 1] += L->ap_start[q];
            for (int q = 0; q < n_tp; ++q) cursor[q] = L->ap_start[q];
            TRY(L->ap_src = WC_NEW(al, int, 2 * (size_t)L->ap_start[n_tp] + 2));
        }
    }
    for (int pass = 0; pass < 2; ++pass) { /* P^T T, the blocks (I, J >= I) of rows I = 2a */
        for (int I = 0; I < N->n; I += 2) {
            int s0 = N->row_start[I];
            while (N->col[s0] < I) ++s0;
            for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
                int i = L->pt_row[s], slot = s0, k = L->t_start[i];
                while (k < L->t_start[i + 1] && L->t_col[k] < I) k += 2;
                for (; k < L->t_start[i + 1]; k += 2) {
                    while (N->col[slot] != L->t_col[k]) ++slot;
                    if (pass == 0) {
                        ++L->ptap_start[slot / 2 + 1];
                    } else {
                        int m = cursor[slot / 2]++;
                        L->ptap_src[2 * m] = L->pt_entry[s];
                        L->ptap_src[2 * m + 1] = k;
                    }
                }
            }
        }
        if (pass == 0) {
            for (int q = 0; q < n_np; ++q) L->ptap_start[q + 1] += L->ptap_start[q];
            for (int q = 0; q < n_np; ++q) cursor[q] = L->ptap_start[q];
            TRY(L->ptap_src = WC_NEW(al, int, 2 * (size_t)L->ptap_start[n_np] + 2));
        }
    }
    /* the prolongator's: each entry pair's strong blocks (a_to_p), ascending */
    const int n_pp = L->p_start[n] / 2;
    TRY(L->pr_start = WC_NEW(al, int, n_pp + 1));
    TRY(L->pr_src = WC_NEW(al, int, L->n_blocks + 1));
    for (int k = 0; k < L->n_blocks; ++k)
        if (L->a_to_p[k] >= 0) ++L->pr_start[L->a_to_p[k] / 2 + 1];
    for (int q = 0; q < n_pp; ++q) L->pr_start[q + 1] += L->pr_start[q];
    wc_free(al, cursor);
    TRY(cursor = WC_NEW(al, int, n_pp + 1));
    for (int q = 0; q < n_pp; ++q) cursor[q] = L->pr_start[q];
    for (int k = 0; k < L->n_blocks; ++k)
        if (L->a_to_p[k] >= 0) L->pr_src[cursor[L->a_to_p[k] / 2]++] = k;
    wc_free(al, cursor);
    return 1;
oom:
    wc_free(al, cursor);
    return 0;
}

/* The prolongator's pattern from level L to its coarse nodes (cpa per aggregate), its
 * transpose, T's pattern, and the next level's pattern (into N). mark: n_next ints; buf:
 * 2 (n + 1) ints. */
static int build_transfer(wc_amg* a, wc_amg_level* L, wc_amg_level* N, int n_next, int* mark, int* buf) {
    const wc_allocator* al = &a->alloc;
    int n = L->n, cpa = L->cpa;
    /* unsmoothed aggregation (prolong_weight 0): P = P_tent, row i = its own aggregate's nodes
       only, so T and the next level keep no blocks that would stay zero (the GPU's multigrid) */
    const int smoothed = a->opts.prolong_weight > 0.0;
    /* P: row i = the coarse nodes of the aggregates of i and its strong neighbours */
    TRY(L->p_start = WC_NEW(al, int, n + 1));
    for (int pass = 0; pass < 2; ++pass) {
        int nnz = 0;
        for (int i = 0; i < n; ++i) {
            int len = 0;
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
                if (smoothed && (is_strong(L, k) || L->col[k] == i))
                    for (int q = 0; q < cpa; ++q) buf[len++] = cpa * L->agg[L->col[k]] + q;
            for (int q = 0; q < cpa; ++q) buf[len++] = cpa * L->agg[i] + q;
            len = sort_unique(buf, len);
            if (pass == 0) L->p_start[i] = nnz;
            else memcpy(L->p_col + nnz, buf, (size_t)len * sizeof *buf);
            nnz += len;
        }
        if (pass == 0) {
            L->p_start[n] = nnz;
            TRY(L->p_col = WC_NEW(al, int, nnz));
            if (a->opts.values) TRY(L->p_val = WC_NEW(al, double, 9 * (size_t)nnz));
            if (a->opts.values && a->opts.single) TRY(L->p_val_f = WC_NEW(al, float, 9 * (size_t)nnz + WC_BSR_F_PAD));
        }
    }
    int nnz_p = L->p_start[n];
    TRY(L->p_self = WC_NEW(al, int, n));
    TRY(L->a_to_p = WC_NEW(al, int, L->n_blocks));
    for (int i = 0; i < n; ++i) {
        L->p_self[i] = wc_amg_find(L->p_col, L->p_start[i], L->p_start[i + 1], cpa * L->agg[i]);
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            L->a_to_p[k] = smoothed && (is_strong(L, k) || L->col[k] == i)
                               ? wc_amg_find(L->p_col, L->p_start[i], L->p_start[i + 1], cpa * L->agg[L->col[k]])
                               : -1;
    }
    /* P^T by counting sort (rows ascending within each aggregate) */
    TRY(L->pt_start = WC_NEW(al, int, n_next + 1));
    TRY(L->pt_entry = WC_NEW(al, int, nnz_p));
    TRY(L->pt_row = WC_NEW(al, int, nnz_p));
    for (int e = 0; e < nnz_p; ++e) ++L->pt_start[L->p_col[e] + 1];
    for (int c = 0; c < n_next; ++c) L->pt_start[c + 1] += L->pt_start[c];
    for (int c = 0; c < n_next; ++c) mark[c] = L->pt_start[c];
    for (int i = 0; i < n; ++i)
        for (int e = L->p_start[i]; e < L->p_start[i + 1]; ++e) {
            int slot = mark[L->p_col[e]]++;
            L->pt_entry[slot] = e;
            L->pt_row[slot] = i;
        }
    /* T = A P: row i = union of P's rows of i's columns */
    for (int c = 0; c < n_next; ++c) mark[c] = -1;
    TRY(L->t_start = WC_NEW(al, int, n + 1));
    for (int pass = 0; pass < 2; ++pass) {
        int nnz = 0;
        for (int i = 0; i < n; ++i) {
            int len = 0;
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int j = L->col[k];
                for (int e = L->p_start[j]; e < L->p_start[j + 1]; ++e)
                    if (mark[L->p_col[e]] != i + pass * n) {
                        mark[L->p_col[e]] = i + pass * n;
                        buf[len++] = L->p_col[e];
                    }
            }
            len = sort_unique(buf, len);
            if (pass == 0) L->t_start[i] = nnz;
            else memcpy(L->t_col + nnz, buf, (size_t)len * sizeof *buf);
            nnz += len;
        }
        if (pass == 0) {
            L->t_start[n] = nnz;
            TRY(L->t_col = WC_NEW(al, int, nnz));
            if (a->opts.values) TRY(L->t_val = WC_NEW(al, double, 9 * (size_t)nnz));
            if (a->opts.values && a->opts.single && cpa == 2) TRY(L->t_val_f = WC_NEW(al, float, 9 * (size_t)nnz + WC_BSR_F_PAD));
        }
    }
    /* next level: row I = union of T's rows of the fine rows in aggregate... of P^T's row I */
    for (int c = 0; c < n_next; ++c) mark[c] = -1;
    N->n = n_next;
    TRY(N->own_row_start = WC_NEW(al, int, n_next + 1));
    for (int pass = 0; pass < 2; ++pass) {
        int nnz = 0;
        for (int I = 0; I < n_next; ++I) {
            int len = 0;
            for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
                int i = L->pt_row[s];
                for (int k = L->t_start[i]; k < L->t_start[i + 1]; ++k)
                    if (mark[L->t_col[k]] != I + pass * n_next) {
                        mark[L->t_col[k]] = I + pass * n_next;
                        buf[len++] = L->t_col[k];
                    }
            }
            len = sort_unique(buf, len);
            if (pass == 0) N->own_row_start[I] = nnz;
            else memcpy(N->own_col + nnz, buf, (size_t)len * sizeof *buf);
            nnz += len;
        }
        if (pass == 0) {
            N->own_row_start[n_next] = nnz;
            TRY(N->own_col = WC_NEW(al, int, nnz));
        }
    }
    N->n_blocks = N->own_row_start[n_next];
    TRY(N->own_diag = WC_NEW(al, int, n_next));
    for (int I = 0; I < n_next; ++I)
        N->own_diag[I] = wc_amg_find(N->own_col, N->own_row_start[I], N->own_row_start[I + 1], I);
    N->row_start = N->own_row_start;
    N->col = N->own_col;
    N->diag = N->own_diag;
    if (cpa == 2 && a->opts.values && !galerkin_lists(a, L, N)) goto oom;
    return 1;
oom:
    return 0;
}

static int alloc_level_values(wc_amg* a, wc_amg_level* L, int own_val) {
    const wc_allocator* al = &a->alloc;
    if (!a->opts.values) return 1;
    if (own_val) TRY(L->val = WC_NEW(al, double, 9 * (size_t)L->n_blocks));
    TRY(L->Dinv = WC_NEW(al, double, 9 * (size_t)L->group * L->n));
    TRY(L->DinvT = WC_NEW(al, double, 12 * (size_t)L->group * L->n));
    if (a->opts.single) TRY(L->val_f = WC_NEW(al, float, 9 * (size_t)L->n_blocks + WC_BSR_F_PAD));
    if (L->group == 2) {
        TRY(L->pair_blk = WC_NEW(al, int, L->n));
        for (int i = 0; i < L->n; ++i) {
            L->pair_blk[i] = wc_amg_find(L->col, L->row_start[i], L->row_start[i + 1], i ^ 1);
            int j = i ^ 1, len = L->row_start[i + 1] - L->row_start[i];
            /* the pairs' rows share their columns (P's columns 2a, 2a + 1 come together) */
            if (L->pair_blk[i] < 0 || len != L->row_start[j + 1] - L->row_start[j] ||
                memcmp(L->col + L->row_start[i], L->col + L->row_start[j], sizeof(int) * (size_t)len) != 0)
                goto oom;
        }
        if (a->opts.single && a->opts.single_setup) { /* each block's transpose, for the float P^T T */
            TRY(L->mirror = WC_NEW(al, int, L->n_blocks));
            for (int i = 0; i < L->n; ++i)
                for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                    const int j = L->col[k];
                    L->mirror[k] = wc_amg_find(L->col, L->row_start[j], L->row_start[j + 1], i);
                    if (L->mirror[k] < 0) goto oom; /* the pattern is symmetric (P^T A P) */
                }
        }
    }
    TRY(L->x = WC_NEW(al, double, 3 * (size_t)L->n));
    if (a->opts.single && a->opts.single_x) TRY(L->xf = WC_NEW(al, float, 4 * (size_t)L->n));
    TRY(L->r = WC_NEW(al, double, 3 * (size_t)L->n));
    TRY(L->t = WC_NEW(al, double, 3 * (size_t)L->n));
    TRY(L->ev = WC_NEW(al, double, 3 * (size_t)L->n));
    TRY(L->ev_scratch = WC_NEW(al, double, 3 * (size_t)L->n));
    TRY(L->partial = WC_NEW(al, double, 3 * (size_t)(L->n / WC_AMG_CHUNK + 1)));
    return 1;
oom:
    return 0;
}

/* Level 0's strong blocks: the diagonal and the blocks of stretch and shear springs. */
static int mark_strong(wc_amg* a, wc_amg_level* L, const wc_model* m) {
    const wc_bsr_pattern* p = &m->pattern;
    TRY(L->strong = WC_NEW(&a->alloc, unsigned char, L->n_blocks));
    for (int i = 0; i < p->n_rows; ++i) {
        L->strong[p->diag[i]] = 1;
        for (int e = p->row_spring_start[i]; e < p->row_spring_start[i + 1]; ++e)
            if (m->springs[p->row_spring[e]].type != WC_SPRING_BEND) L->strong[p->row_spring_block[e]] = 1;
    }
    return 1;
oom:
    return 0;
}

wc_status wc_amg_create(wc_amg** out, const wc_model* m, const wc_amg_opts* opts, const wc_allocator* alloc,
                          wc_diag* diag) {
    if (!out || !m) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "wc_amg_create: NULL argument");
    *out = NULL;
    wc_amg_opts o = opts ? *opts : wc_default_amg_opts();
    if (o.coarse_max < 1 || o.sweeps < 1 || o.power_iterations < 1 || o.coarse_iterations < 0 || o.bound_reuse < 0 || o.bound_carry < 0 || !(o.bound_margin >= 1.0 && o.bound_margin < 100.0) || o.cross_dense_dofs < 0 || o.cross_dense_dofs > 4096 || !(o.chebyshev_ratio > 1) || !(o.smooth_weight > 0 && o.smooth_weight < 2) ||
        !(o.prolong_weight >= 0 && o.prolong_weight < 2))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "AMG options: coarse_max, sweeps and power_iterations >= 1, coarse_iterations, bound_reuse and bound_carry >= 0, bound_margin in [1, 100), cross_dense_dofs in [0, 4096], smooth_weight in (0, 2), prolong_weight in [0, 2)");
    wc_amg* a = WC_NEW(alloc, wc_amg, 1);
    if (!a) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "AMG hierarchy");
    if (alloc) a->alloc = *alloc;
    a->opts = o;
    a->fine_bound_scale = 1.0;
    for (int s = 0; s < m->n_seams; ++s)
        if (m->seams[s].q0 != m->seams[s].q1) a->fine_bound_scale = WC_AMG_SEAM_BOUND;
    int n = m->n_particles;
    const wc_bsr_pattern* p = &m->pattern;
    int* mark = WC_NEW(&a->alloc, int, n + 1);
    int* pending = WC_NEW(&a->alloc, int, n + 1);
    /* rows are deduplicated before they reach buf (P's rows: at most cpa x (a row of A plus one)) */
    int* buf = WC_NEW(&a->alloc, int, 2 * (size_t)n + 2);
    wc_amg_level* L = &a->lev[0];
    L->n = n;
    L->n_blocks = p->n_blocks;
    L->row_start = p->row_start;
    L->col = p->col;
    L->diag = p->diag;
    L->group = 1;
    if (!mark || !pending || !buf || !mark_strong(a, L, m) || !alloc_level_values(a, L, 1)) goto oom;
    if (o.rotations) {
        TRY(L->nns = WC_NEW(&a->alloc, double, 18 * (size_t)n));
        wc_amg_rigid_modes(L, m->rest_pos);
    }
    a->n_levels = 1;
    while (a->n_levels < WC_AMG_MAX_LEVELS && L->n > o.coarse_max) {
        TRY(L->agg = WC_NEW(&a->alloc, int, L->n));
        L->cpa = o.rotations ? 2 : 1;
        int n_agg = aggregate(L, L->agg, pending);
        if (a->n_levels == 1 && o.aggressive && n_agg > o.coarse_max) n_agg = aggregate_again(a, L, L->agg, n_agg, pending);
        if (n_agg < 0) goto oom;
        int n_next = L->cpa * n_agg;
        if (n_next >= L->n || n_agg < 1) break; /* no coarsening: stop here */
        wc_amg_level* N = &a->lev[a->n_levels];
        N->group = L->cpa;
        if (!build_transfer(a, L, N, n_next, mark, buf) || !alloc_level_values(a, N, 1)) goto oom;
        if (o.rotations) { /* the aggregates' node lists (ascending), P_tent, N's near-null rows */
            TRY(L->agg_start = WC_NEW(&a->alloc, int, n_agg + 1));
            TRY(L->agg_node = WC_NEW(&a->alloc, int, L->n));
            TRY(L->tent = WC_NEW(&a->alloc, double, 18 * (size_t)L->n));
            if (o.values && o.single && o.single_setup && L->cpa == 2)
                TRY(L->tent_f = WC_NEW(&a->alloc, float, 18 * (size_t)L->n + WC_BSR_F_PAD));
            TRY(N->nns = WC_NEW(&a->alloc, double, 18 * (size_t)n_next));
            TRY(N->dead = WC_NEW(&a->alloc, unsigned char, 3 * (size_t)n_next));
            for (int i = 0; i < L->n; ++i) ++L->agg_start[L->agg[i] + 1];
            for (int g = 0; g < n_agg; ++g) L->agg_start[g + 1] += L->agg_start[g];
            for (int g = 0; g < n_agg; ++g) mark[g] = L->agg_start[g];
            for (int i = 0; i < L->n; ++i) L->agg_node[mark[L->agg[i]]++] = i;
            wc_amg_tentative(L, N, n_agg, NULL);
        }
        ++a->n_levels;
        L = N;
    }
    if (L->agg) { /* the coarsest level keeps no prolongator */
        wc_free(&a->alloc, L->agg);
        L->agg = NULL;
    }
    if (o.rotations && o.current_positions && a->n_levels > 1) TRY(a->tent_pos = WC_NEW(&a->alloc, double, 3 * (size_t)n));
    a->coarse_dense = L->n <= 8 * o.coarse_max;
    if (a->coarse_dense && o.values) {
        a->coarse_dofs = 3 * L->n;
        TRY(a->coarse_L = WC_NEW(&a->alloc, double, (size_t)a->coarse_dofs * a->coarse_dofs));
        TRY(a->coarse_y = WC_NEW(&a->alloc, double, a->coarse_dofs));
    }
    wc_free(&a->alloc, mark);
    wc_free(&a->alloc, pending);
    wc_free(&a->alloc, buf);
    *out = a;
    return WC_OK;
oom:
    wc_free(&a->alloc, mark);
    wc_free(&a->alloc, pending);
    wc_free(&a->alloc, buf);
    wc_amg_destroy(a);
    return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "AMG hierarchy for %d particles", n);
}

void wc_amg_destroy(wc_amg* a) {
    if (!a) return;
    wc_allocator al = a->alloc;
    for (int l = 0; l < WC_AMG_MAX_LEVELS; ++l) {
        wc_amg_level* L = &a->lev[l];
        void* ptrs[] = {L->own_row_start, L->own_col, L->own_diag, L->strong, L->val, L->Dinv, L->DinvT, L->x, L->r, L->t,
                        L->ev, L->ev_scratch, L->partial, L->agg, L->p_start, L->p_col, L->p_self, L->a_to_p, L->p_val, L->pt_start, L->pt_entry,
                        L->pt_row, L->t_start, L->t_col, L->t_val, L->t_read, L->ap_start, L->ap_src, L->ptap_start, L->ptap_src, L->pr_start, L->pr_src, L->nns, L->dead, L->agg_start, L->agg_node, L->tent, L->tent_f, L->pair_blk, L->mirror, L->val_f, L->p_val_f, L->t_val_f, L->xf};
        for (size_t k = 0; k < sizeof ptrs / sizeof ptrs[0]; ++k) wc_free(&al, ptrs[k]);
    }
    wc_amg_cross_destroy(a);
    wc_free(&al, a->coarse_L);
    wc_free(&al, a->coarse_y);
    wc_free(&al, a->tent_pos);
    wc_free(&al, a);
}

double wc_amg_operator_complexity(const wc_amg* a) {
    if (!a || a->lev[0].n_blocks == 0) return 0.0;
    double sum = 0.0;
    for (int l = 0; l < a->n_levels; ++l) sum += a->lev[l].n_blocks;
    return sum / a->lev[0].n_blocks;
}

double wc_amg_grid_complexity(const wc_amg* a) {
    if (!a || a->lev[0].n == 0) return 0.0;
    double sum = 0.0;
    for (int l = 0; l < a->n_levels; ++l) sum += a->lev[l].n;
    return sum / a->lev[0].n;
}
