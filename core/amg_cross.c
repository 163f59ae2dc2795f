/* The couplings outside the pattern (coupling.h) carried through the multigrid hierarchy
 * (amg.h, wc_amg_cross).
 *
 * Why: a self-contact pair couples particles of two layers that share no spring, so A's pattern
 * has no block between them and the hierarchy built on that pattern (aggregates follow the mesh)
 * never sees the pair's cross blocks: it preconditions A + diag(coupling) where PCG iterates on
 * A + coupling. Modes in which pressed layers move against each other, or together, are then off
 * by up to 1 + 2 c / m (c the penalty, m a particle's inertia; 100 m at the pairs' stiffness),
 * and PCG pays for it: 130-170 iterations on a layer resting on another (test_self_pairs) where a
 * free sheet takes 10.
 *
 * What: each active term c (J^T J) is kept per level as c v v^T, v one sparse vector (amg.h,
 * wc_amg_cross): level 0's v = S J^T (the filter applied as the V-cycle's projected operator
 * applies it), with the term's diagonal blocks taken out of level 0's BSR values (A holds them);
 * level l + 1's v = P_l^T v. With the BSR part's Galerkin product P^T B P that makes every level's
 * operator the Galerkin product of the level above's whole operator. The smoother's residuals,
 * its block diagonal (B's blocks plus the terms'), the eigenvalue estimates (so the Chebyshev
 * bound covers the coupled modes) and the coarsest level's dense factor use the whole operator;
 * the prolongator's smoothing uses B (its pattern is fixed per model) with the whole D.
 * One merged vector per term rather than one per particle: the triangle's three particles reach
 * the same coarse nodes, so a term takes about half the entries of its four pieces. A small coarse
 * level (at most wc_amg_opts.cross_dense_dofs unknowns) sums its terms into one dense matrix
 * instead: on the dance the third level's 174 nodes had 600k entries in 38k vectors, 7x the
 * dense matrix's 270k; the levels below a dense one take the dense Galerkin product P^T X P.
 *
 * The setup's restrictions run on the threads (a list level: over fixed ranges of terms, then its
 * block diagonal's part over nodes; a dense level: batches of terms restricted over ranges of
 * terms, then their upper blocks added over rows),
 * the products over terms and then over nodes (a gather through a per-setup index, no reduction);
 * every sum goes in term order, so the result is the same on any thread count; no allocation after
 * wc_amg_set_coupling. A coarse list level's terms overlap
 * (each reaches ~14 nodes of two layers' patches): each setup also sums them into one
 * block-sparse matrix, which its products read in one pass of BSR rows (sum_blocks, parallel over
 * rows). The V-cycle's residuals read neither on a list level: amg_merge.c merges B and X into one
 * float matrix after each setup (the terms stay for the restriction, the eigenvalue estimates and
 * the block diagonal). */
#include <stdatomic.h>
#include <string.h>
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif
#include "amg.h"
#include "bsr_rows.h"
#include "coupling.h"
#include "vec3.h"

/* entries per term a list level below the finest may hold (the finest: 4): a term's vector
 * reaches ~10-15 nodes there (two layers' patches of the smoothed prolongator's rows; the dance's
 * second level: 14.3 per term). The dance's 118k-term capacity gives 68 MB there (36 bytes an
 * entry with its gather index); its resident memory grew from 651 to 751 MB in all. */
#define WC_AMG_CROSS_PER_TERM 16
/* blocks per term of the capacity a coarse list level's summed form may hold (wc_amg_cross.n_blocks):
 * the dance's second level takes 171k blocks for 38k terms (4.5 a term; 1.45 a term of its 118k
 * capacity), 36 MB of room at 4; a setup whose blocks do not fit keeps the terms' products. */
#define WC_AMG_CROSS_BLOCKS_PER_TERM 4
/* blocks per term of the capacity the finest level's merged operator (amg_merge.c) may hold
 * beyond B's pattern: the dance's terms add 73-93k blocks to B's 500k (2.4 an active term, ~0.8 a
 * term of its 118k capacity); room for 3 a term is 34 MB with B's. A setup that does not fit keeps
 * B's rows and the terms. */
#define WC_AMG_MERGE_PER_TERM 3
/* restricted entries (node and 3 doubles) one batch of a dense level's restriction stages
 * (restrict_dense; two batches, 1.8 MB): n_terms / (this / n) barriers per setup. The dance's dense
 * level, 174 nodes: 188 terms a batch, ~200 batches for its ~38k terms. */
#define WC_AMG_CROSS_STAGE_ENTRIES 32768

void wc_amg_cross_destroy(wc_amg* a) {
    if (!a) return;
    for (int l = 0; l < WC_AMG_MAX_LEVELS; ++l) {
        wc_amg_cross* X = a->lev[l].cross;
        if (!X) continue;
        void* ptrs[] = {X->c, X->start, X->node, X->val, X->dense, X->gal, X->dadd, X->s, X->node_start,
                        X->node_val, X->entry_term, X->y, X->acc, X->touched, X->mark,
                        X->blk_start, X->blk_col, X->blk_val, X->blk_pos, X->blk_stage, X->blk_stage_at, X->m_start, X->m_col, X->reach,
                        X->m_val_f, X->m_pos, X->m_acc, X->stage_n, X->stage_node, X->stage_val};
        for (size_t k = 0; k < sizeof ptrs / sizeof ptrs[0]; ++k) wc_free(&a->alloc, ptrs[k]);
        wc_free(&a->alloc, X);
        a->lev[l].cross = NULL;
    }
}

wc_status wc_amg_set_coupling(wc_amg* a, const wc_coupling* c, int capacity, wc_diag* diag) {
    if (!a) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "wc_amg_set_coupling: NULL hierarchy");
    wc_amg_cross_destroy(a);
    a->coupling = NULL;
    if (!c || !a->opts.couplings) return WC_OK;
    if (capacity < 1) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "wc_amg_set_coupling: capacity %d", capacity);
    const wc_allocator* al = &a->alloc;
    for (int l = 0; l < a->n_levels; ++l) {
        wc_amg_level* L = &a->lev[l];
        wc_amg_cross* X = WC_NEW(al, wc_amg_cross, 1);
        if (!X) goto oom;
        L->cross = X;
        X->cap_terms = capacity;
        const size_t d = 3 * (size_t)L->n;
        const int above_dense = l > 0 && a->lev[l - 1].cross->dense;
        if (l > 0 && d <= (size_t)a->opts.cross_dense_dofs) {
            X->dense = WC_NEW(al, double, d * d);
            if (!X->dense) goto oom;
            if (above_dense && !(X->gal = WC_NEW(al, double, 3 * (size_t)a->lev[l - 1].n * d))) goto oom;
        } else {
            size_t entries = (size_t)capacity * (l == 0 ? 4 : WC_AMG_CROSS_PER_TERM);
            if (entries > (size_t)1 << 28) entries = (size_t)1 << 28;
            X->cap_entries = (int)entries;
            X->start = WC_NEW(al, int, (size_t)capacity + 1);
            X->node = WC_NEW(al, int, entries);
            X->val = WC_NEW(al, double, 3 * entries);
            X->node_start = WC_NEW(al, int, (size_t)L->n + 1);
            X->node_val = WC_NEW(al, double, 3 * entries);
            X->entry_term = WC_NEW(al, int, entries);
            if (!X->start || !X->node || !X->val || !X->node_start || !X->node_val || !X->entry_term) goto oom;
        }
        if (l > 0 && !X->dense) { /* the summed form (sum_blocks) */
            size_t blocks = (size_t)capacity * WC_AMG_CROSS_BLOCKS_PER_TERM;
            if (blocks > (size_t)1 << 26) blocks = (size_t)1 << 26;
            X->cap_blocks = (int)blocks;
            X->blk_start = WC_NEW(al, int, (size_t)L->n + 1);
            X->blk_col = WC_NEW(al, int, blocks);
            X->blk_val = WC_NEW(al, double, 9 * blocks);
            const size_t pos = (size_t)WC_PAR_MAX_THREADS * L->n; /* a row of n per thread */
            X->blk_pos = WC_NEW(al, int, pos);
            X->blk_stage = WC_NEW(al, int, blocks);
            X->blk_stage_at = WC_NEW(al, int, (size_t)L->n);
            if (!X->blk_start || !X->blk_col || !X->blk_val || !X->blk_pos || !X->blk_stage || !X->blk_stage_at) goto oom;
            for (size_t i = 0; i < pos; ++i) X->blk_pos[i] = -1;
        }
        if (!X->dense && a->opts.single) { /* the merged operator (amg_merge.c) */
            size_t room = (size_t)L->n_blocks + (l == 0 ? (size_t)capacity * WC_AMG_MERGE_PER_TERM : (size_t)X->cap_blocks);
            if (room > (size_t)1 << 27) room = (size_t)1 << 27;
            X->cap_merged = (int)room;
            X->m_start = WC_NEW(al, int, (size_t)L->n + 1);
            X->m_col = WC_NEW(al, int, room);
            X->m_val_f = WC_NEW(al, float, 9 * room + WC_BSR_F_PAD);
            if (!X->m_start || !X->m_col || !X->m_val_f) goto oom;
            if (l == 0) {
                const size_t pos = (size_t)WC_PAR_MAX_THREADS * L->n;
                X->m_pos = WC_NEW(al, int, pos);
                X->m_acc = WC_NEW(al, double, (size_t)WC_PAR_MAX_THREADS * WC_AMG_MERGE_ROW * 9);
                if (!X->m_pos || !X->m_acc) goto oom;
                for (size_t i = 0; i < pos; ++i) X->m_pos[i] = -1;
            }
        }
        X->c = WC_NEW(al, double, capacity);
        X->s = WC_NEW(al, double, capacity);
        X->dadd = WC_NEW(al, double, 9 * (size_t)L->group * L->n);
        X->y = WC_NEW(al, double, d);
        if (l > 0 && !above_dense) { /* the restriction's scratch, one per thread */
            X->acc = WC_NEW(al, double, WC_PAR_MAX_THREADS * d);
            X->touched = WC_NEW(al, int, (size_t)WC_PAR_MAX_THREADS * L->n);
            X->mark = WC_NEW(al, unsigned char, (size_t)WC_PAR_MAX_THREADS * L->n);
            if (!X->acc || !X->touched || !X->mark) goto oom;
            if (!X->dense && !(X->reach = WC_NEW(al, int, capacity))) goto oom;
            if (X->dense) { /* restrict_dense's two batches */
                const int per = WC_AMG_CROSS_STAGE_ENTRIES / L->n;
                X->stage_cap = X->stage_terms = per > 1 ? per : 1;
                const size_t slots = 2 * (size_t)X->stage_cap * L->n;
                X->stage_n = WC_NEW(al, int, 2 * (size_t)X->stage_cap);
                X->stage_node = WC_NEW(al, int, slots);
                X->stage_val = WC_NEW(al, double, 3 * slots);
                if (!X->stage_n || !X->stage_node || !X->stage_val) goto oom;
            }
        }
        if (!X->c || !X->s || !X->dadd || !X->y) goto oom;
    }
    a->coupling = c;
    return WC_OK;
oom:
    wc_amg_cross_destroy(a);
    return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "AMG: room for %d couplings", capacity);
}

/* A list level's gather index: each node's entries in entry (so term) order, by a counting sort,
 * with their values. */
static void index_nodes(wc_amg_cross* X, int n) {
    memset(X->node_start, 0, sizeof(int) * ((size_t)n + 1));
    for (int e = 0; e < X->n_entries; ++e) ++X->node_start[X->node[e] + 1];
    for (int i = 0; i < n; ++i) X->node_start[i + 1] += X->node_start[i];
    for (int q = 0; q < X->n_terms; ++q)
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) {
            int slot = X->node_start[X->node[e]]++;
            v3_copy(X->node_val + 3 * (size_t)slot, X->val + 3 * (size_t)e);
            X->entry_term[slot] = q;
        }
    for (int i = n; i > 0; --i) X->node_start[i] = X->node_start[i - 1]; /* back to the starts */
    X->node_start[0] = 0;
}

/* How many distinct columns row i of a list level's terms has (the nodes of the terms holding i),
 * marking them in pos with -2 - i (the caller sets them back to -1); columns already marked so are
 * not counted (amg_merge.c marks B's first). */
int wc_amg_cross_count_row(const wc_amg_cross* X, int i, int* pos) {
    const int stamp = -2 - i;
    int nb = 0;
    for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j) {
        const int q = X->entry_term[j];
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) {
            const int k = X->node[e];
            if (pos[k] == stamp) continue;
            pos[k] = stamp;
            ++nb;
        }
    }
    return nb;
}

/* Row i's columns (the nodes of the terms holding i), ascending, into cols (room for n); pos (the
 * thread's: -1 on entry) marks them meanwhile and is left at -1; returns how many. */
static int row_columns(const wc_amg_cross* X, int i, int* pos, int* cols) {
    const int *start = X->start, *node = X->node, *entry_term = X->entry_term;
    int nb = 0;
    for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j) {
        const int q = entry_term[j], e1 = start[q + 1];
        for (int e = start[q]; e < e1; ++e) {
            const int k = node[e];
            if (pos[k] >= 0) continue;
            pos[k] = 0;
            cols[nb++] = k;
        }
    }
    for (int b = 1; b < nb; ++b) { /* ascending (insertion sort: ~45 a row) */
        const int k = cols[b];
        int u = b;
        for (; u > 0 && cols[u - 1] > k; --u) cols[u] = cols[u - 1];
        cols[u] = k;
    }
    for (int b = 0; b < nb; ++b) pos[cols[b]] = -1;
    return nb;
}

/* Row i's blocks from blk_start[i] on: its columns (cols, ascending, from row_columns) and the
 * blocks (i, k >= i) summed, in term order, each entry c (a_r b_s); pos (the thread's: -1 on
 * entry) left at -1. The arrays are read through locals: the blocks' stores would otherwise make
 * the compiler reload X's fields and the row's vector after each one. */
static void sum_row(wc_amg_cross* X, int i, const int* cols, int* pos) {
    const int first = X->blk_start[i], end = X->blk_start[i + 1];
    const int *start = X->start, *node = X->node, *entry_term = X->entry_term;
    const double *val = X->val, *node_val = X->node_val, *cq = X->c;
    double* blk = X->blk_val;
    for (int b = first; b < end; ++b) {
        const int k = cols[b - first];
        X->blk_col[b] = k;
        pos[k] = b;
    }
    memset(blk + 9 * (size_t)first, 0, 9 * sizeof(double) * (size_t)(end - first));
    for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j) { /* the blocks (i, k >= i) */
        const int q = entry_term[j], e1 = start[q + 1];
        const double c = cq[q], a0 = node_val[3 * (size_t)j], a1 = node_val[3 * (size_t)j + 1],
                     a2 = node_val[3 * (size_t)j + 2];
        for (int e = start[q]; e < e1; ++e) {
            const int k = node[e];
            if (k < i) continue;
            const double v0 = val[3 * (size_t)e], v1 = val[3 * (size_t)e + 1], v2 = val[3 * (size_t)e + 2];
            double* o = blk + 9 * (size_t)pos[k];
            o[0] += c * (a0 * v0);
            o[1] += c * (a0 * v1);
            o[2] += c * (a0 * v2);
            o[3] += c * (a1 * v0);
            o[4] += c * (a1 * v1);
            o[5] += c * (a1 * v2);
            o[6] += c * (a2 * v0);
            o[7] += c * (a2 * v1);
            o[8] += c * (a2 * v2);
        }
    }
    for (int b = first; b < end; ++b) pos[cols[b - first]] = -1;
}

/* Row i's blocks (i, k < i) = (k, i)^T, from row k's summed blocks. */
static void mirror_row(wc_amg_cross* X, int i) {
    for (int b = X->blk_start[i]; b < X->blk_start[i + 1] && X->blk_col[b] < i; ++b) {
        const int k = X->blk_col[b];
        int lo = X->blk_start[k], hi = X->blk_start[k + 1] - 1;
        while (lo < hi) { /* column i in row k (there: the pattern is symmetric) */
            const int mid = (lo + hi) / 2;
            if (X->blk_col[mid] < i) lo = mid + 1;
            else hi = mid;
        }
        const double* t = X->blk_val + 9 * (size_t)lo;
        double* o = X->blk_val + 9 * (size_t)b;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) o[3 * r + c] = t[3 * c + r];
    }
}

/* A coarse list level's summed form (wc_amg_cross.n_blocks): row i's block (i, k) = sum over the
 * terms holding both nodes, in term order, of c_q v_q(i) v_q(k)^T, each entry c (a_r b_c) so that
 * (k, i) is its transpose to the bit: so the blocks left of the diagonal are copied from the rows
 * above, transposed. Left at 0 blocks when they would be more than the entries (the terms' two
 * passes then cost less) or than cap_blocks. Not on the finest level: its terms (4 particles)
 * overlap little (the dance: 150k blocks for 153k entries), and summing them gained nothing there
 * (docs/bench/dance_frame.md). On the threads, in one region over fixed rows (FOR_THREAD_ROWS),
 * each thread with its own blk_pos and row of columns (the restriction's touched, free by then):
 * each row's columns found once, sorted and staged (blk_stage, at an offset claimed atomically:
 * the offsets vary from run to run, the columns do not), the rows' prefix sum (thread 0), each
 * row's columns copied from the stage and its upper blocks summed, then the lower ones. A block is
 * summed by one thread in term order, so the bits do not depend on the thread count. */
/* A thread's rows of a list level's summed form: blocks of WC_AMG_CROSS_SUM_ROWS rows dealt in
 * turn (block c to thread c mod nt), so that both threads get rows of every part of the level (the
 * work per row varies along it: halves of the rows took 0.58 and 0.35 G, docs/bench/threads.md). */
#define WC_AMG_CROSS_SUM_ROWS 32
#define FOR_THREAD_ROWS(i, n, t, nt)                                                           \
    for (int c_ = (t); c_ * WC_AMG_CROSS_SUM_ROWS < (n); c_ += (nt))                          \
        for (int i = c_ * WC_AMG_CROSS_SUM_ROWS, e_ = i + WC_AMG_CROSS_SUM_ROWS < (n) ? i + WC_AMG_CROSS_SUM_ROWS : (n); \
             i < e_; ++i)

static void sum_blocks(wc_amg_cross* X, int n, wc_par* par) {
    X->n_blocks = 0;
    if (!X->blk_val || !X->touched || X->n_terms == 0) return; /* touched: a list level below a list one */
    const int limit = X->cap_blocks < X->n_entries ? X->cap_blocks : X->n_entries;
    int fits = 0;
    atomic_llong staged; /* the stage's blocks claimed (all rows': past cap_blocks when they do not fit) */
    atomic_init(&staged, 0);
    WC_PAR_REGION(par)
    {
        const int t = wc_par_tid(), nt = wc_par_nt();
        int *pos = X->blk_pos + (size_t)n * t, *cols = X->touched + (size_t)n * t;
        FOR_THREAD_ROWS(i, n, t, nt) {
            const int nb = row_columns(X, i, pos, cols);
            const long long at = atomic_fetch_add_explicit(&staged, nb, memory_order_relaxed);
            const int kept = at + nb <= X->cap_blocks; /* a row out of the stage: they do not fit */
            X->blk_stage_at[i] = kept ? (int)at : -1;
            if (kept) memcpy(X->blk_stage + at, cols, sizeof(int) * (size_t)nb);
            X->blk_start[i + 1] = nb;
        }
        WC_PAR_BARRIER();
        if (t == 0) {
            X->blk_start[0] = 0;
            int i = 0;
            for (; i < n && X->blk_start[i + 1] <= limit - X->blk_start[i]; ++i) X->blk_start[i + 1] += X->blk_start[i];
            fits = i == n;
        }
        WC_PAR_BARRIER();
        if (fits) { /* then every row is staged: the stage's total is blk_start[n] <= cap_blocks */
            FOR_THREAD_ROWS(i, n, t, nt) sum_row(X, i, X->blk_stage + X->blk_stage_at[i], pos);
            WC_PAR_BARRIER();
            FOR_THREAD_ROWS(i, n, t, nt) mirror_row(X, i);
        }
    }
    X->n_blocks = fits ? X->blk_start[n] : 0;
}

/* o += s a b^T (3x3) */
static inline void outer_add(double* o, double s, const double* a, const double* b) {
    for (int r = 0; r < 3; ++r)
        for (int k = 0; k < 3; ++k) o[3 * r + k] += s * a[r] * b[k];
}

void wc_amg_cross_fine(wc_amg* a, const wc_filter* f) {
    wc_amg_level* L = &a->lev[0];
    wc_amg_cross* X = L->cross;
    if (!X) return;
    const wc_coupling* cp = a->coupling;
    if (X->n_terms > 0) memset(X->dadd, 0, 9 * sizeof(double) * (size_t)L->n);
    X->m_blocks = 0; /* merged again after the float copies (amg_merge.c) */
    int q = 0, e = 0;
    X->start[0] = 0;
    for (int k = 0; cp && k < cp->n; ++k) {
        const wc_coupling_term* t = &cp->t[k];
        if (!(t->c > 0.0)) continue;
        if (q == X->cap_terms) {
            ++a->cross_dropped;
            continue;
        }
        X->c[q] = t->c;
        for (int p = 0; p < t->cnt; ++p) { /* distinct particles (coupling.h): one entry each */
            double w[3], *u = X->val + 3 * (size_t)e;
            v3_scale(w, t->n, t->w[p]);
            wc_filter_apply(f, t->p[p], w, u);
            if (u[0] == 0.0 && u[1] == 0.0 && u[2] == 0.0) continue;
            int i = t->p[p];
            X->node[e++] = i;
            /* the diagonal block c u u^T moves from the BSR values (A holds it) to dadd */
            outer_add(L->val + 9 * (size_t)L->diag[i], -t->c, u, u);
            outer_add(X->dadd + 9 * (size_t)i, t->c, u, u);
        }
        X->start[++q] = e;
    }
    X->n_terms = q;
    X->n_entries = e;
    a->cross_terms[0] = q;
    index_nodes(X, L->n);
}

/* A dense level's block diagonal part (dadd) from its matrix. */
static void dense_diagonal(const wc_amg_level* C, wc_amg_cross* Y) {
    const size_t d = 3 * (size_t)C->n;
    const int g = C->group;
    for (int J = 0; J < C->n; ++J)
        for (int q = 0; q < g; ++q) {
            int K = g == 1 ? J : (J & ~1) + q; /* Dinv's layout: node J's blocks to J & ~1, J | 1 */
            double* Da = Y->dadd + 9 * ((size_t)g * J + q);
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) Da[3 * r + c] = Y->dense[(3 * (size_t)J + r) * d + 3 * (size_t)K + c];
        }
}

/* Y->dense = P^T X P, X the level above's dense matrix (3 n_L x 3 n_L), P its prolongator. */
static void dense_galerkin(const wc_amg_level* L, const wc_amg_cross* X, const wc_amg_level* C, wc_amg_cross* Y) {
    const size_t dl = 3 * (size_t)L->n, dc = 3 * (size_t)C->n;
    double* T = Y->gal; /* T = X P (dl x dc) */
    memset(T, 0, sizeof(double) * dl * dc);
    for (int i = 0; i < L->n; ++i)
        for (int e = L->p_start[i]; e < L->p_start[i + 1]; ++e) {
            const double* P = L->p_val + 9 * (size_t)e;
            const size_t J = 3 * (size_t)L->p_col[e];
            for (size_t row = 0; row < dl; ++row) {
                const double* x = X->dense + row * dl + 3 * (size_t)i;
                double* t = T + row * dc + J;
                for (int c = 0; c < 3; ++c) t[c] += x[0] * P[c] + x[1] * P[3 + c] + x[2] * P[6 + c];
            }
        }
    memset(Y->dense, 0, sizeof(double) * dc * dc);
    for (int i = 0; i < L->n; ++i) /* dense += P^T T, row block i of T per entry of P's row i */
        for (int e = L->p_start[i]; e < L->p_start[i + 1]; ++e) {
            const double* P = L->p_val + 9 * (size_t)e;
            const size_t J = 3 * (size_t)L->p_col[e];
            for (int r = 0; r < 3; ++r) {
                double* o = Y->dense + (J + r) * dc;
                const double *t0 = T + (3 * (size_t)i) * dc, *t1 = t0 + dc, *t2 = t1 + dc;
                const double p0 = P[r], p1 = P[3 + r], p2 = P[6 + r];
                for (size_t k = 0; k < dc; ++k) o[k] += p0 * t0[k] + p1 * t1[k] + p2 * t2[k];
            }
        }
}

/* One thread's restriction scratch on level Y (n nodes): an accumulator zero between terms, the
 * nodes it touched, their marks. */
typedef struct restrict_scratch {
    double* acc;
    int* touched;
    unsigned char* mark;
} restrict_scratch;

static restrict_scratch scratch_of(const wc_amg_cross* Y, int n, int t) {
    restrict_scratch w = {Y->acc + 3 * (size_t)n * t, Y->touched + (size_t)n * t, Y->mark + (size_t)n * t};
    return w;
}

/* w->acc = P^T v_q (level L's term q into the level below); returns how many nodes it touched
 * (w->touched, in the order first touched; clear_term zeroes them again). Read through locals:
 * the accumulator's stores would otherwise make the compiler reload the arrays and v. */
static int restrict_term(const wc_amg_level* L, const wc_amg_cross* X, int q, restrict_scratch* w) {
    const int *p_start = L->p_start, *p_col = L->p_col;
    const double *p_val = L->p_val, *val = X->val;
    double* acc = w->acc;
    int* touched = w->touched;
    unsigned char* mark = w->mark;
    int nt = 0;
    for (int s = X->start[q], s1 = X->start[q + 1]; s < s1; ++s) {
        const int i = X->node[s], pe1 = p_start[i + 1];
        const double v0 = val[3 * (size_t)s], v1 = val[3 * (size_t)s + 1], v2 = val[3 * (size_t)s + 2];
        for (int pe = p_start[i]; pe < pe1; ++pe) {
            const int J = p_col[pe];
            const double* P = p_val + 9 * (size_t)pe;
            double* o = acc + 3 * (size_t)J;
            if (!mark[J]) {
                mark[J] = 1;
                touched[nt++] = J;
            }
            o[0] += P[0] * v0 + P[3] * v1 + P[6] * v2;
            o[1] += P[1] * v0 + P[4] * v1 + P[7] * v2;
            o[2] += P[2] * v0 + P[5] * v1 + P[8] * v2;
        }
    }
    return nt;
}

static void clear_term(restrict_scratch* w, int nt) {
    for (int u = 0; u < nt; ++u) {
        v3_zero(w->acc + 3 * (size_t)w->touched[u]);
        w->mark[w->touched[u]] = 0;
    }
}

static int nonzero3(const double* o) { return o[0] != 0.0 || o[1] != 0.0 || o[2] != 0.0; }

/* Rows of a dense level owned by a thread: chunks of WC_AMG_CROSS_DENSE_ROWS nodes dealt in turn,
 * so that both halves of the upper triangle's uneven rows spread over the threads. */
#define WC_AMG_CROSS_DENSE_ROWS 4
static inline int dense_owner(int I, int nt) { return (I / WC_AMG_CROSS_DENSE_ROWS) % nt; }

/* Y->dense = sum_q c_q (P^T v_q)(P^T v_q)^T from the level above's term lists, on the threads in
 * batches of Y->stage_terms terms: each thread restricts a fixed range of the batch's terms, their
 * touched nodes sorted, into the batch's stage; after a barrier each thread adds, term by term in
 * order, the upper triangle's blocks of the rows it owns (dense_owner). Each entry is summed by one
 * thread in term order from the same restricted values, so the bits do not depend on the thread
 * count or the batch size; two stages, so a thread staging the next batch never overwrites one
 * another still reads: one barrier a batch. Then the lower triangle by symmetry, by rows. */
static void restrict_dense(const wc_amg_level* L, const wc_amg_cross* X, const wc_amg_level* C, wc_amg_cross* Y,
                           wc_par* par) {
    const size_t d = 3 * (size_t)C->n;
    const int n = C->n, B = Y->stage_terms;
    double* dense = Y->dense;
    memset(dense, 0, sizeof(double) * d * d);
    WC_PAR_REGION(par)
    {
        const int t = wc_par_tid(), nth = wc_par_nt();
        restrict_scratch w = scratch_of(Y, C->n, t);
        for (int b0 = 0, k = 0; b0 < X->n_terms; b0 += B, k ^= 1) {
            const int nb = X->n_terms - b0 < B ? X->n_terms - b0 : B;
            int* stage_n = Y->stage_n + (size_t)k * B;
            int* stage_node = Y->stage_node + (size_t)k * B * n;
            double* stage_val = Y->stage_val + 3 * (size_t)k * B * n;
            int lo, hi;
            wc_par_range(nb, t, nth, &lo, &hi);
            for (int j = lo; j < hi; ++j) {
                const int nt = restrict_term(L, X, b0 + j, &w);
                int* nodes = stage_node + (size_t)j * n;
                double* vals = stage_val + 3 * (size_t)j * n;
                for (int b = 1; b < nt; ++b) { /* ascending (insertion), so a row's blocks J >= I follow it */
                    const int key = w.touched[b];
                    int u = b;
                    for (; u > 0 && w.touched[u - 1] > key; --u) w.touched[u] = w.touched[u - 1];
                    w.touched[u] = key;
                }
                for (int u = 0; u < nt; ++u) {
                    nodes[u] = w.touched[u];
                    v3_copy(vals + 3 * (size_t)u, w.acc + 3 * (size_t)w.touched[u]);
                }
                stage_n[j] = nt;
                clear_term(&w, nt);
            }
            WC_PAR_BARRIER();
            for (int j = 0; j < nb; ++j) { /* through locals: the stores would reload them */
                const int nt = stage_n[j];
                const int* nodes = stage_node + (size_t)j * n;
                const double c = X->c[b0 + j], *vals = stage_val + 3 * (size_t)j * n;
                for (int u = 0; u < nt; ++u) {
                    const int I = nodes[u];
                    if (dense_owner(I, nth) != t) continue;
                    const double cv0 = c * vals[3 * (size_t)u], cv1 = c * vals[3 * (size_t)u + 1], cv2 = c * vals[3 * (size_t)u + 2];
                    double* row = dense + 3 * (size_t)I * d;
                    for (int v = u; v < nt; ++v) {
                        const size_t J3 = 3 * (size_t)nodes[v];
                        const double vj0 = vals[3 * (size_t)v], vj1 = vals[3 * (size_t)v + 1], vj2 = vals[3 * (size_t)v + 2];
                        double *o0 = row + J3, *o1 = o0 + d, *o2 = o1 + d;
                        o0[0] += cv0 * vj0;
                        o0[1] += cv0 * vj1;
                        o0[2] += cv0 * vj2;
                        o1[0] += cv1 * vj0;
                        o1[1] += cv1 * vj1;
                        o1[2] += cv1 * vj2;
                        o2[0] += cv2 * vj0;
                        o2[1] += cv2 * vj1;
                        o2[2] += cv2 * vj2;
                    }
                }
            }
        }
        WC_PAR_BARRIER();
        for (size_t I = 0; I < (size_t)C->n; ++I) { /* the lower triangle's blocks by symmetry */
            if (dense_owner((int)I, nth) != t) continue;
            for (size_t J = 0; J <= I; ++J)
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) {
                        if (J == I && c >= r) continue;
                        Y->dense[(3 * I + r) * d + 3 * J + c] = Y->dense[(3 * J + c) * d + 3 * I + r];
                    }
        }
    }
}

/* Term q's entry at node J on list level Y, or NULL. */
static const double* term_entry(const wc_amg_cross* Y, int q, int J) {
    for (int e = Y->start[q]; e < Y->start[q + 1]; ++e)
        if (Y->node[e] == J) return Y->val + 3 * (size_t)e;
    return NULL;
}

/* Y's terms = P^T v_q of the level above's, on the threads in fixed ranges of terms: each term's
 * touched nodes and live entries counted (reach, start), their offsets and the terms that fit
 * (thread 0), then each term restricted again into its place; a dead unknown's column (an entry
 * exactly 0) is left out. The block diagonal's part (dadd) is then summed per node over its
 * entries in term order (the gather index), on the threads in fixed ranges of nodes: each block
 * gets the terms' contributions in the order the serial loop over terms gave them (a term
 * missing a pair level's partner node adds exact zeros there), so the bits do not depend on the
 * thread count. */
static void restrict_lists(wc_amg* a, const wc_amg_level* L, const wc_amg_cross* X, const wc_amg_level* C,
                           wc_amg_cross* Y, wc_par* par) {
    const int g = C->group;
    int held = 0;
    if (X->n_terms == 0) { /* none: the level's lists empty, its block diagonal's part zero */
        if (Y->n_terms > 0) memset(Y->dadd, 0, 9 * sizeof(double) * (size_t)g * C->n);
        Y->n_terms = Y->n_entries = 0;
        Y->start[0] = 0;
        index_nodes(Y, C->n);
        return;
    }
    WC_PAR_REGION(par)
    {
        const int t = wc_par_tid(), nth = wc_par_nt();
        restrict_scratch w = scratch_of(Y, C->n, t);
        int lo, hi;
        wc_par_range(X->n_terms, t, nth, &lo, &hi);
        for (int q = lo; q < hi; ++q) {
            const int nt = restrict_term(L, X, q, &w);
            int live = 0;
            for (int u = 0; u < nt; ++u) live += nonzero3(w.acc + 3 * (size_t)w.touched[u]);
            Y->reach[q] = nt;
            Y->start[q + 1] = live;
            clear_term(&w, nt);
        }
        WC_PAR_BARRIER();
        if (t == 0) { /* the terms that fit: a term and the later ones stay out of this level and below */
            int q = 0, e = 0;
            Y->start[0] = 0;
            for (; q < X->n_terms && e + Y->reach[q] <= Y->cap_entries; ++q) Y->start[q + 1] = e += Y->start[q + 1];
            held = q;
        }
        WC_PAR_BARRIER();
        if (hi > held) hi = held;
        for (int q = lo; q < hi; ++q) {
            const int nt = restrict_term(L, X, q, &w);
            int e = Y->start[q];
            for (int u = 0; u < nt; ++u) {
                const int J = w.touched[u];
                const double* o = w.acc + 3 * (size_t)J;
                if (!nonzero3(o)) continue;
                Y->node[e] = J;
                v3_copy(Y->val + 3 * (size_t)e, o);
                ++e;
            }
            clear_term(&w, nt);
            Y->c[q] = X->c[q];
        }
    }
    if (held < X->n_terms) a->cross_dropped += X->n_terms - held;
    Y->n_terms = held;
    Y->n_entries = Y->start[held];
    index_nodes(Y, C->n);
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(C->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        memset(Y->dadd + 9 * (size_t)g * lo, 0, 9 * sizeof(double) * (size_t)g * (hi - lo));
        for (int J = lo; J < hi; ++J) { /* (J, J), and (J, J ^ 1) on a pair level */
            double* Da = Y->dadd + 9 * (size_t)g * J;
            for (int j = Y->node_start[J]; j < Y->node_start[J + 1]; ++j) {
                const int q = Y->entry_term[j];
                const double c = Y->c[q], *o = Y->node_val + 3 * (size_t)j;
                if (g == 1) {
                    outer_add(Da, c, o, o);
                    continue;
                }
                outer_add(Da + 9 * (J & 1), c, o, o);
                const double* p = term_entry(Y, q, J ^ 1);
                if (p) outer_add(Da + 9 * ((J & 1) ^ 1), c, o, p);
            }
        }
    }
}

void wc_amg_cross_restrict(wc_amg* a, int l, wc_par* par) {
    const wc_amg_level* L = &a->lev[l];
    const wc_amg_level* C = &a->lev[l + 1];
    const wc_amg_cross* X = L->cross;
    wc_amg_cross* Y = C->cross;
    if (!X || !Y) return;
    Y->m_blocks = 0;
    if (Y->dense) {
        Y->n_terms = X->n_terms;
        Y->n_entries = 0;
        a->cross_terms[l + 1] = Y->n_terms;
        if (Y->n_terms == 0) return;
        Y->dense_sym = !X->dense; /* restrict_dense's lower triangle is its upper one's copy */
        if (X->dense) dense_galerkin(L, X, C, Y);
        else restrict_dense(L, X, C, Y, par);
        dense_diagonal(C, Y);
        return;
    }
    restrict_lists(a, L, X, C, Y, par);
    a->cross_terms[l + 1] = Y->n_terms;
    sum_blocks(Y, C->n, par);
}

void wc_amg_cross_scale(const wc_amg_cross* X, double alpha, const double* x, int q0, int q1) {
    for (int q = q0; q < q1; ++q) { /* s_k = alpha c_k (v_k . x) */
        double acc = 0.0;
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) acc += v3_dot(X->val + 3 * (size_t)e, x + 3 * (size_t)X->node[e]);
        X->s[q] = alpha * X->c[q] * acc;
    }
}

/* y_r += alpha sum_k M_rk x_k, k ascending, for rows [r0, r1) of a d x d matrix. */
static void dense_rows(const double* M, int d, double alpha, const double* x, double* y, int r0, int r1) {
    for (int r = r0; r < r1; ++r) {
        const double* row = M + (size_t)r * d;
        double acc = 0.0;
        for (int k = 0; k < d; ++k) acc += row[k] * x[k];
        y[r] += alpha * acc;
    }
}

/* The same sums for a bit-symmetric M read by columns (a panel of rows is a stretch of each row
 * k): each register lane does one row's recurrence acc += M_kr x_k, k ascending, multiply then
 * add (no FMA): dense_rows' bits without its serial chain (16 rows a pass, then 4, then 1). */
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
int wc_amg_cross_dense_vec(void) { return __builtin_cpu_supports("avx"); }

__attribute__((target("avx"))) static void dense_cols_avx(const double* M, int d, double alpha, const double* x,
                                                          double* y, int r0, int r1) {
    int r = r0;
    for (; r + 16 <= r1; r += 16) {
        __m256d a0 = _mm256_setzero_pd(), a1 = _mm256_setzero_pd(), a2 = _mm256_setzero_pd(),
                a3 = _mm256_setzero_pd();
        const double* m = M + r;
        for (int k = 0; k < d; ++k, m += d) {
            const __m256d xk = _mm256_broadcast_sd(x + k);
            a0 = _mm256_add_pd(a0, _mm256_mul_pd(_mm256_loadu_pd(m), xk));
            a1 = _mm256_add_pd(a1, _mm256_mul_pd(_mm256_loadu_pd(m + 4), xk));
            a2 = _mm256_add_pd(a2, _mm256_mul_pd(_mm256_loadu_pd(m + 8), xk));
            a3 = _mm256_add_pd(a3, _mm256_mul_pd(_mm256_loadu_pd(m + 12), xk));
        }
        const __m256d g = _mm256_set1_pd(alpha);
        double* o = y + r;
        _mm256_storeu_pd(o, _mm256_add_pd(_mm256_loadu_pd(o), _mm256_mul_pd(g, a0)));
        _mm256_storeu_pd(o + 4, _mm256_add_pd(_mm256_loadu_pd(o + 4), _mm256_mul_pd(g, a1)));
        _mm256_storeu_pd(o + 8, _mm256_add_pd(_mm256_loadu_pd(o + 8), _mm256_mul_pd(g, a2)));
        _mm256_storeu_pd(o + 12, _mm256_add_pd(_mm256_loadu_pd(o + 12), _mm256_mul_pd(g, a3)));
    }
    for (; r + 4 <= r1; r += 4) {
        __m256d a0 = _mm256_setzero_pd();
        const double* m = M + r;
        for (int k = 0; k < d; ++k, m += d) a0 = _mm256_add_pd(a0, _mm256_mul_pd(_mm256_loadu_pd(m), _mm256_broadcast_sd(x + k)));
        _mm256_storeu_pd(y + r, _mm256_add_pd(_mm256_loadu_pd(y + r), _mm256_mul_pd(_mm256_set1_pd(alpha), a0)));
    }
    dense_rows(M, d, alpha, x, y, r, r1);
}
#else
int wc_amg_cross_dense_vec(void) { return 0; }
#endif

/* y_r += alpha (X x)_r over a dense level's rows [r0, r1): by columns where X is symmetric to the
 * bit and AVX is there (vec: wc_amg_cross_dense_vec()), else by rows; the same bits either way. */
void wc_amg_cross_dense_rows(const wc_amg_cross* X, int d, double alpha, const double* x, double* y, int r0, int r1,
                             int vec) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (vec && X->dense_sym) {
        dense_cols_avx(X->dense, d, alpha, x, y, r0, r1);
        return;
    }
#else
    (void)vec;
#endif
    dense_rows(X->dense, d, alpha, x, y, r0, r1);
}

void wc_amg_cross_rows_add(const wc_amg_cross* X, double alpha, const double* x, double* y, int n, int lo, int hi) {
    if (X->dense) { /* y_r += alpha (X x)_r over the nodes' rows */
        wc_amg_cross_dense_rows(X, 3 * n, alpha, x, y, 3 * lo, 3 * hi, wc_amg_cross_dense_vec());
        return;
    }
    if (X->n_blocks > 0) { /* y_i += alpha sum_k X_ik x_k, the summed form */
        wc_bsr_rows(X->blk_start, X->blk_col, X->blk_val, lo, hi, y, alpha, x, y);
        return;
    }
    for (int i = lo; i < hi; ++i) { /* y_i += sum over i's entries of s_k v_k(i), in term order */
        if (X->node_start[i] == X->node_start[i + 1]) continue;
        double acc[3] = {0, 0, 0};
        for (int j = X->node_start[i]; j < X->node_start[i + 1]; ++j)
            v3_axpy(acc, X->s[X->entry_term[j]], X->node_val + 3 * (size_t)j);
        v3_add(y + 3 * (size_t)i, y + 3 * (size_t)i, acc);
    }
}

void wc_amg_cross_mul_add(const wc_amg_cross* X, double alpha, const double* x, double* y, int n, wc_par* par) {
    if (!X || X->n_terms == 0) return;
    if (wc_amg_cross_as_terms(X)) {
        WC_PAR_REGION(par)
        {
            int lo, hi;
            wc_par_range(X->n_terms, wc_par_tid(), wc_par_nt(), &lo, &hi);
            wc_amg_cross_scale(X, alpha, x, lo, hi);
        }
    }
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        wc_amg_cross_rows_add(X, alpha, x, y, n, lo, hi);
    }
}

void wc_amg_cross_dense(const wc_amg_cross* X, double* M, int d) {
    if (!X || X->n_terms == 0) return;
    if (X->dense) {
        for (size_t k = 0; k < (size_t)d * d; ++k) M[k] += X->dense[k];
        return;
    }
    for (int q = 0; q < X->n_terms; ++q)
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) {
            const double* u = X->val + 3 * (size_t)e;
            for (int g = X->start[q]; g < X->start[q + 1]; ++g) {
                const double* v = X->val + 3 * (size_t)g;
                double* o = M + (size_t)3 * X->node[e] * d + 3 * X->node[g];
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j) o[(size_t)i * d + j] += X->c[q] * u[i] * v[j];
            }
        }
}
