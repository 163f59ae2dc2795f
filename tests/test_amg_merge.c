/* The merged operators F = B + X of the multigrid's coupled levels (core/amg_merge.c,
 * wc_amg_cross.m_blocks) on a real system: two 21 x 21 layers, the top one falling onto the
 * bottom one, the substep's couplings found by the self-contact pairs (the system of
 * test_amg_cross.c). Checked:
 *   - every merged block of every level against a plain serial sum computed here, bit for bit:
 *     each row's blocks in a dense row of doubles, 0 + B_ik, then on the finest level each term
 *     q holding i (ascending q, its entries of i in order) adding c_q (v_i[r] v_k[s]) for every
 *     entry k of the term, on a summed level the summed block; rounded to float once. Rows with
 *     couplings and rows without, on 1 and 3 threads; then with B_ik planted to cancel the
 *     couplings' block but for its last bits, so that one double rounding more or less in the sum
 *     (a product regrouped, B added after the terms) shows in the floats;
 *   - the finest level's rows without a term (the short path) are (float)(0 + B_ik) bit for bit,
 *     zeros of either sign and a tiny value planted in B included; the layout after the re-merge.
 * (The products against B + X, the same bits on 1, 2 and 3 threads, the V-cycle's use and a level
 * out of room: test_amg_cross.c's test_merged.) */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "check.h"
#include "coupling.h"
#include "self_pairs.h"
#include "solve_kernels.h"
#include "step.h"
#include "test_support.h"
#include "amg_coupled.h"
#include "two_layers.h"

enum { N = 21 };
static const double SIZE = 0.6;

static wc_state* coupled_system(wc_model* m) { return amg_coupled_layers(m, N, SIZE); }

/* Level l's merged blocks against a plain serial sum (the file's comment), bit for bit; counts
 * the blocks checked in rows with couplings and without (*coupled, *plain); returns the
 * mismatching entries, plus one per row whose columns differ. */
static int merged_value_errors(const wc_amg_level* L, int* coupled, int* plain) {
    const wc_amg_cross* X = L->cross;
    const int n = L->n;
    double* row = malloc(9 * sizeof(double) * (size_t)n);
    unsigned char* has = calloc((size_t)n, 1);
    int bad = 0;
    for (int i = 0; i < n; ++i) {
        int with = 0;
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
            double* s = row + 9 * (size_t)L->col[k];
            if (!has[L->col[k]]) memset(s, 0, 9 * sizeof(double));
            has[L->col[k]] = 1;
            for (int q = 0; q < 9; ++q) s[q] = s[q] + L->val[9 * (size_t)k + q];
        }
        if (X->n_blocks > 0) { /* a summed level: the summed row's blocks */
            for (int b = X->blk_start[i]; b < X->blk_start[i + 1]; ++b) {
                double* s = row + 9 * (size_t)X->blk_col[b];
                if (!has[X->blk_col[b]]) memset(s, 0, 9 * sizeof(double));
                has[X->blk_col[b]] = 1;
                for (int q = 0; q < 9; ++q) s[q] = s[q] + X->blk_val[9 * (size_t)b + q];
                with = 1;
            }
        } else { /* the finest: the terms holding i, in term order */
            for (int q = 0; q < X->n_terms; ++q)
                for (int ei = X->start[q]; ei < X->start[q + 1]; ++ei) {
                    if (X->node[ei] != i) continue;
                    const double c = X->c[q], *u = X->val + 3 * (size_t)ei;
                    with = 1;
                    for (int e = X->start[q]; e < X->start[q + 1]; ++e) {
                        const double* v = X->val + 3 * (size_t)e;
                        double* s = row + 9 * (size_t)X->node[e];
                        if (!has[X->node[e]]) memset(s, 0, 9 * sizeof(double));
                        has[X->node[e]] = 1;
                        for (int r = 0; r < 3; ++r)
                            for (int k = 0; k < 3; ++k) s[3 * r + k] = s[3 * r + k] + c * (u[r] * v[k]);
                    }
                }
        }
        int nb = 0;
        for (int k = 0; k < n; ++k) nb += has[k];
        bad += X->m_start[i + 1] - X->m_start[i] != nb;
        for (int b = X->m_start[i]; b < X->m_start[i + 1]; ++b) {
            const int k = X->m_col[b];
            if (k < 0 || k >= n || !has[k]) {
                ++bad;
                continue;
            }
            for (int q = 0; q < 9; ++q) {
                const float want = (float)row[9 * (size_t)k + q];
                bad += memcmp(&want, X->m_val_f + 9 * (size_t)b + q, sizeof want) != 0;
            }
            *(with ? coupled : plain) += 1;
        }
        memset(has, 0, (size_t)n);
    }
    free(row);
    free(has);
    return bad;
}

/* x to 40 significant bits (-x: a cancelling B_ik leaves the sum's last bits) */
static double coarse(double x) {
    int e;
    const double m = frexp(x, &e);
    return ldexp(nearbyint(ldexp(m, 40)), e - 40);
}

/* Every B_ik of a row with couplings set to minus the couplings' block X_ik rounded to 40 bits
 * (where X_ik != 0), so that F_ik is X_ik's lowest bits: an error of one double rounding in the
 * sum (a regrouped product, another order) moves it by far more than a float's rounding and shows
 * in the merged floats. Returns the entries planted. */
static int plant_cancelling(wc_amg_level* L) {
    const wc_amg_cross* X = L->cross;
    const int n = L->n;
    double* row = calloc(9 * (size_t)n, sizeof(double));
    int planted = 0;
    for (int i = 0; i < n; ++i) {
        if (X->n_blocks > 0) {
            for (int b = X->blk_start[i]; b < X->blk_start[i + 1]; ++b)
                memcpy(row + 9 * (size_t)X->blk_col[b], X->blk_val + 9 * (size_t)b, 9 * sizeof(double));
        } else {
            for (int q = 0; q < X->n_terms; ++q)
                for (int ei = X->start[q]; ei < X->start[q + 1]; ++ei) {
                    if (X->node[ei] != i) continue;
                    const double *u = X->val + 3 * (size_t)ei;
                    for (int e = X->start[q]; e < X->start[q + 1]; ++e)
                        for (int r = 0; r < 3; ++r)
                            for (int k = 0; k < 3; ++k)
                                row[9 * (size_t)X->node[e] + 3 * r + k] += X->c[q] * (u[r] * X->val[3 * (size_t)e + k]);
                }
        }
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            for (int q = 0; q < 9; ++q) {
                const double x = row[9 * (size_t)L->col[k] + q];
                if (x == 0.0) continue;
                L->val[9 * (size_t)k + q] = -coarse(x);
                ++planted;
            }
        memset(row, 0, 9 * sizeof(double) * (size_t)n);
    }
    free(row);
    return planted;
}

/* Every level's merged blocks against the plain serial sum, bit for bit, merged on 1 and 3 threads
 * (term lists on every level: level 0 merged from its terms, the others from their summed blocks);
 * then again with B cancelling the couplings (plant_cancelling), each level merged anew. */
static void test_merged_values(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    for (int t = 1; t <= 3; t += 2)
        for (int cancel = 0; cancel < 2; ++cancel) {
            wc_par par;
            wc_par_init(&par, t);
            wc_amg* a = amg_coupled_hierarchy(s, 0, &par);
            if (!a) break;
            for (int l = 0; l < a->n_levels; ++l) {
                wc_amg_level* L = &a->lev[l];
                int coupled = 0, plain = 0, planted = 0;
                CHECK(L->cross->m_blocks > 0);
                CHECK_EQ_INT(l > 0, L->cross->n_blocks > 0); /* level 0 from the terms, the others summed */
                if (cancel) {
                    planted = plant_cancelling(L);
                    wc_amg_cross_merge(a, l, &par);
                    CHECK(planted > 0);
                }
                const int bad = L->cross->m_blocks > 0 ? merged_value_errors(L, &coupled, &plain) : -1;
                printf("  %d thread%s, level %d (%s%s): %d merged blocks (%d in rows with couplings, %d without), "
                       "%d entries differ from the serial sum\n", t, t > 1 ? "s" : "", l, l ? "summed" : "terms",
                       cancel ? ", B cancelling" : "", L->cross->m_blocks, coupled, plain, bad);
                CHECK_EQ_INT(bad, 0);
                CHECK(coupled > 0);
                CHECK_EQ_INT(coupled + plain, L->cross->m_blocks);
            }
            wc_amg_destroy(a);
        }
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Level 0's merged rows that hold no term (amg_merge.c's short path) are B's row as floats of
 * 0 + B_ik, bit for bit (a -0 entry becomes +0, as the summed rows give it), in B's columns; the
 * rows with terms keep their layout. Zeros of either sign and a tiny value are planted in a term-free
 * row of B before the level is merged again. */
static void test_merged_rows(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    wc_par one;
    wc_par_init(&one, 1);
    wc_amg* a = amg_coupled_hierarchy(s, 0, &one);
    if (!a) return;
    wc_amg_level* L = &a->lev[0];
    const wc_amg_cross* X = L->cross;
    int plain = -1, plain_rows = 0, term_rows = 0;
    for (int i = 0; i < L->n; ++i) {
        const int free_row = X->node_start[i] == X->node_start[i + 1];
        plain_rows += free_row;
        term_rows += !free_row;
        if (free_row && plain < 0 && L->row_start[i + 1] - L->row_start[i] >= 3) plain = i;
    }
    printf("  level 0: %d rows without terms, %d with\n", plain_rows, term_rows);
    CHECK(plain >= 0 && term_rows > 0);
    if (plain >= 0) {
        double* v = L->val + 9 * (size_t)L->row_start[plain];
        v[1] = -0.0;
        v[2] = 0.0;
        v[9 + 4] = -0.0;
        v[18 + 5] = -1e-300;
        wc_amg_cross_merge(a, 0, &one);
    }
    int bad = 0, checked = 0;
    for (int i = 0; i < L->n; ++i) {
        if (X->node_start[i] != X->node_start[i + 1]) continue;
        const int a0 = L->row_start[i], nb = L->row_start[i + 1] - a0, o = X->m_start[i];
        bad += X->m_start[i + 1] - o != nb;
        for (int b = 0; b < nb && X->m_start[i + 1] - o == nb; ++b) {
            bad += X->m_col[o + b] != L->col[a0 + b];
            for (int q = 0; q < 9; ++q) {
                const float want = (float)(0.0 + L->val[9 * (size_t)(a0 + b) + q]);
                bad += memcmp(&want, X->m_val_f + 9 * (size_t)(o + b) + q, sizeof want) != 0;
                ++checked;
            }
        }
    }
    const float plus0 = 0.0f;
    const float* f = X->m_val_f + 9 * (size_t)X->m_start[plain >= 0 ? plain : 0];
    const int signs = plain >= 0 ? memcmp(f + 1, &plus0, sizeof plus0) != 0 || memcmp(f + 2, &plus0, sizeof plus0) != 0 ||
                                       memcmp(f + 9 + 4, &plus0, sizeof plus0) != 0 || f[18 + 5] != 0.0f || signbit(f[18 + 5]) == 0
                                 : 1;
    int* seen = malloc(sizeof(int) * (size_t)L->n);
    for (int i = 0; i < L->n; ++i) seen[i] = -1;
    const int layout = amg_merged_layout_errors(L, seen);
    printf("  term-free rows' entries against (float)(0 + B): %d of %d differ; planted zeros' signs %s; layout errors %d\n",
           bad, checked, signs ? "wrong" : "right", layout);
    CHECK(checked > 0);
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(signs, 0);
    CHECK_EQ_INT(layout, 0);
    free(seen);
    wc_amg_destroy(a);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_merged_values);
    RUN_TEST(test_merged_rows);
    return TEST_SUMMARY();
}
