/* A coupled level's whole operator F = B + X as one float BSR matrix (amg.h, wc_amg_cross.m_blocks).
 *
 * Why: with the couplings as terms (amg_cross.c) every V-cycle residual on a list level is B's
 * float rows plus a second pass over X: on the finest level the terms' dots, a barrier, then each
 * node's gather (scalar code, an index and a random read an entry); on a summed level a second
 * BSR pass in double. The dance's solve spent 3.3 G of 15.2 G instructions in the finest level's
 * terms (docs/bench/dance_frame.md). Merged, a residual is one pass of float rows over B's pattern
 * and X's extra blocks: no scaling pass, no barrier, half the bytes of a double block.
 *
 * What: after each setup's float copies (amg_setup.c), row by row: the columns of B's row and of
 * X's row, ascending; each block B_ik + X_ik summed in double and rounded once. X's row is read
 * from the summed form where the level has one (n_blocks > 0, a sorted merge), else from the terms
 * through the node index (the finest level: for row i every term holding i, c v(i) v(k)^T for
 * each of its entries k, in term order, summed in a per-thread row of doubles; a row that no term
 * holds is B's row rounded straight from 0 + B_ik: the same bits without the marks, the sort and
 * the accumulator). Only the V-cycle's residuals read it (amg_cycle.c); the eigenvalue estimates,
 * the block diagonal (dadd), the restriction of the terms and PCG's own product keep B and X
 * apart, as before. Rows are
 * independent and each is summed by one thread in a fixed order: the same bits on any thread
 * count. Not bit-identical to B's rows plus X's (X_ik is rounded to float with B_ik, the sums go
 * in another order). No allocation: the room is set with the couplings (wc_amg_set_coupling); a
 * level that does not fit, or a row longer than WC_AMG_MERGE_ROW, is left unmerged. */
#include <limits.h>
#include <string.h>
#include "amg.h"
#include "bsr_rows.h"

/* blocks of row i of F: B's row and X's summed row, both ascending (the summed form) */
static int count_summed(const wc_amg_level* L, const wc_amg_cross* X, int i) {
    int a = L->row_start[i], ae = L->row_start[i + 1], b = X->blk_start[i], be = X->blk_start[i + 1], n = 0;
    while (a < ae && b < be) {
        const int ca = L->col[a], cb = X->blk_col[b];
        a += ca <= cb;
        b += cb <= ca;
        ++n;
    }
    return n + (ae - a) + (be - b);
}

static void merge_summed(const wc_amg_level* L, wc_amg_cross* X, int i) {
    int a = L->row_start[i], ae = L->row_start[i + 1], b = X->blk_start[i], be = X->blk_start[i + 1];
    for (int o = X->m_start[i]; a < ae || b < be; ++o) {
        const int ca = a < ae ? L->col[a] : INT_MAX, cb = b < be ? X->blk_col[b] : INT_MAX;
        const int k = ca < cb ? ca : cb;
        double s[9] = {0};
        if (ca == k) {
            for (int q = 0; q < 9; ++q) s[q] += L->val[9 * (size_t)a + q];
            ++a;
        }
        if (cb == k) {
            for (int q = 0; q < 9; ++q) s[q] += X->blk_val[9 * (size_t)b + q];
            ++b;
        }
        X->m_col[o] = k;
        float* f = X->m_val_f + 9 * (size_t)o;
        for (int q = 0; q < 9; ++q) f[q] = (float)s[q];
    }
}

/* blocks of row i of F from the terms: B's columns marked in pos (the thread's, -1 on entry) with
 * stamp, then the terms' columns not yet marked; pos left marked (the fill resets it) */
static int count_terms(const wc_amg_level* L, const wc_amg_cross* X, int i, int* pos) {
    if (X->node_start[i] == X->node_start[i + 1]) return L->row_start[i + 1] - L->row_start[i]; /* no term */
    for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) pos[L->col[k]] = -2 - i;
    return L->row_start[i + 1] - L->row_start[i] + wc_amg_cross_count_row(X, i, pos);
}

/* row i of F from the terms (its room counted by count_terms), summed in acc (the thread's). Read
 * through locals: the int stores (pos, cols) and the double ones (acc) would otherwise make the
 * compiler reload the arrays, the bounds and the blocks' values after each; every sum the same
 * expression in the same order. */
static void merge_terms(const wc_amg_level* L, wc_amg_cross* X, int i, int* pos, double* acc) {
    const int o = X->m_start[i], a0 = L->row_start[i], a1 = L->row_start[i + 1];
    const int j0 = X->node_start[i], j1 = X->node_start[i + 1];
    const int *col = L->col, *entry_term = X->entry_term, *start = X->start, *node = X->node;
    const double *bval = L->val, *cq = X->c, *node_val = X->node_val, *tval = X->val;
    int* cols = X->m_col + o;
    float* f = X->m_val_f + 9 * (size_t)o;
    if (j0 == j1) { /* no term: B's row, as 0 + B_ik (+0 for -0) */
        const int nb = a1 - a0;
        memcpy(cols, col + a0, (size_t)nb * sizeof(int));
        const double* v = bval + 9 * (size_t)a0;
        for (size_t q = 0; q < 9 * (size_t)nb; ++q) f[q] = (float)(0.0 + v[q]);
        return;
    }
    int nb = 0;
    for (int k = a0; k < a1; ++k) { /* B's columns, ascending */
        const int c = col[k];
        pos[c] = nb;
        cols[nb++] = c;
    }
    for (int j = j0; j < j1; ++j) { /* then the terms' new ones */
        const int q = entry_term[j], e1 = start[q + 1];
        for (int e = start[q]; e < e1; ++e) {
            const int k = node[e];
            if (pos[k] >= 0) continue;
            pos[k] = nb;
            cols[nb++] = k;
        }
    }
    for (int b = 1; b < nb; ++b) { /* ascending (insertion: the few new ones into B's) */
        const int k = cols[b];
        int u = b;
        for (; u > 0 && cols[u - 1] > k; --u) cols[u] = cols[u - 1];
        cols[u] = k;
    }
    for (int b = 0; b < nb; ++b) pos[cols[b]] = b;
    memset(acc, 0, 9 * sizeof(double) * (size_t)nb);
    for (int k = a0; k < a1; ++k) {
        double* s = acc + 9 * (size_t)pos[col[k]];
        const double* v = bval + 9 * (size_t)k;
        const double v0 = v[0], v1 = v[1], v2 = v[2], v3 = v[3], v4 = v[4], v5 = v[5], v6 = v[6], v7 = v[7], v8 = v[8];
        s[0] += v0;
        s[1] += v1;
        s[2] += v2;
        s[3] += v3;
        s[4] += v4;
        s[5] += v5;
        s[6] += v6;
        s[7] += v7;
        s[8] += v8;
    }
    for (int j = j0; j < j1; ++j) { /* c v(i) v(k)^T, term order */
        const int q = entry_term[j], e1 = start[q + 1];
        const double c = cq[q], u0 = node_val[3 * (size_t)j], u1 = node_val[3 * (size_t)j + 1], u2 = node_val[3 * (size_t)j + 2];
        for (int e = start[q]; e < e1; ++e) {
            const double v0 = tval[3 * (size_t)e], v1 = tval[3 * (size_t)e + 1], v2 = tval[3 * (size_t)e + 2];
            double* s = acc + 9 * (size_t)pos[node[e]];
            s[0] += c * (u0 * v0);
            s[1] += c * (u0 * v1);
            s[2] += c * (u0 * v2);
            s[3] += c * (u1 * v0);
            s[4] += c * (u1 * v1);
            s[5] += c * (u1 * v2);
            s[6] += c * (u2 * v0);
            s[7] += c * (u2 * v1);
            s[8] += c * (u2 * v2);
        }
    }
    for (size_t q = 0; q < 9 * (size_t)nb; ++q) f[q] = (float)acc[q];
    for (int b = 0; b < nb; ++b) pos[cols[b]] = -1;
}

void wc_amg_cross_merge(wc_amg* a, int l, wc_par* par) {
    const wc_amg_level* L = &a->lev[l];
    wc_amg_cross* X = L->cross;
    if (!X) return;
    X->m_blocks = 0;
    if (!X->m_val_f || X->dense || X->n_terms == 0 || !a->opts.single || !L->val_f) return;
    const int summed = X->n_blocks > 0;
    if (!summed && !X->m_acc) return;
    const int n = L->n;
    int fits = 0;
    WC_PAR_REGION(par)
    {
        const int t = wc_par_tid(), nt = wc_par_nt();
        int lo, hi;
        wc_par_range(n, t, nt, &lo, &hi);
        int* pos = X->m_pos ? X->m_pos + (size_t)n * t : NULL;
        for (int i = lo; i < hi; ++i) X->m_start[i + 1] = summed ? count_summed(L, X, i) : count_terms(L, X, i, pos);
        WC_PAR_BARRIER();
        if (t == 0) {
            int i = 0;
            X->m_start[0] = 0;
            for (; i < n; ++i) {
                const int len = X->m_start[i + 1];
                if ((!summed && len > WC_AMG_MERGE_ROW) || len > X->cap_merged - X->m_start[i]) break;
                X->m_start[i + 1] += X->m_start[i];
            }
            fits = i == n;
        }
        WC_PAR_BARRIER();
        if (fits) {
            double* acc = X->m_acc ? X->m_acc + 9 * (size_t)WC_AMG_MERGE_ROW * t : NULL;
            for (int i = lo; i < hi; ++i) {
                if (summed) merge_summed(L, X, i);
                else merge_terms(L, X, i, pos, acc); /* leaves the row's marks at -1 */
            }
        } else if (!summed) { /* the count's marks back to -1 */
            for (int i = lo; i < hi; ++i) {
                for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) pos[L->col[k]] = -1;
                for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j) {
                    const int q = X->entry_term[j];
                    for (int e = X->start[q]; e < X->start[q + 1]; ++e) pos[X->node[e]] = -1;
                }
            }
        }
    }
    if (!fits) return;
    X->m_blocks = X->m_start[n];
    memset(X->m_val_f + 9 * (size_t)X->m_blocks, 0, WC_BSR_F_PAD * sizeof(float));
}
