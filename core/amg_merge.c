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

/* row i of F from the terms (its room counted by count_terms), summed in acc (the thread's) */
static void merge_terms(const wc_amg_level* L, wc_amg_cross* X, int i, int* pos, double* acc) {
    const int o = X->m_start[i];
    if (X->node_start[i] == X->node_start[i + 1]) { /* no term: B's row, as 0 + B_ik (+0 for -0) */
        const int a = L->row_start[i], nb = L->row_start[i + 1] - a;
        memcpy(X->m_col + o, L->col + a, (size_t)nb * sizeof(int));
        const double* v = L->val + 9 * (size_t)a;
        float* f = X->m_val_f + 9 * (size_t)o;
        for (size_t q = 0; q < 9 * (size_t)nb; ++q) f[q] = (float)(0.0 + v[q]);
        return;
    }
    int nb = 0;
    int* cols = X->m_col + o;
    for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) { /* B's columns, ascending */
        pos[L->col[k]] = nb;
        cols[nb++] = L->col[k];
    }
    for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j) { /* then the terms' new ones */
        const int q = X->entry_term[j];
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) {
            const int k = X->node[e];
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
    for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
        double* s = acc + 9 * (size_t)pos[L->col[k]];
        for (int q = 0; q < 9; ++q) s[q] += L->val[9 * (size_t)k + q];
    }
    for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j) { /* c v(i) v(k)^T, term order */
        const int q = X->entry_term[j];
        const double c = X->c[q], *u = X->node_val + 3 * (size_t)j;
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) {
            const double* v = X->val + 3 * (size_t)e;
            double* s = acc + 9 * (size_t)pos[X->node[e]];
            for (int r = 0; r < 3; ++r)
                for (int k = 0; k < 3; ++k) s[3 * r + k] += c * (u[r] * v[k]);
        }
    }
    float* f = X->m_val_f + 9 * (size_t)o;
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
