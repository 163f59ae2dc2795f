/* The self-contact couplings carried through the multigrid hierarchy (core/amg_cross.c) on a
 * real system (amg_coupled.h): two 21 x 21 layers, the top one falling onto the bottom one, the substep's
 * couplings found by the self-contact pairs (self_pairs.h); the bottom layer has two pinned
 * particles and a row on a plane contact, so the filter acts on some pieces. Checked:
 *   - every level's whole operator (BSR part + the couplings) is the Galerkin product of the level
 *     above's, P^T F P, on random vectors (an independent composition of the products);
 *   - the coarsest level's dense Cholesky factor is that level's whole operator (L L^T);
 *   - the V-cycle stays symmetric positive definite on the filtered system;
 *   - PCG to 1e-8 with the couplings in the hierarchy against the hierarchy of the pattern alone:
 *     the same answer, fewer iterations (asserted at most half);
 *   - a capacity below the active terms: the left-out terms are counted and PCG still converges
 *     to the same answer;
 *   - the V-cycle (its parallel products with the couplings included) is the same to the bit on
 *     1 and 2 threads;
 *   - layers small enough for a single level: its dense factor holds the couplings whole, so PCG
 *     converges at once;
 *   - a list level's summed form (wc_amg_cross.n_blocks): its product against the terms' sum
 *     c_k v_k (v_k . x) computed here from the lists, on 1 and 2 threads; its rows' columns
 *     ascending, each block (k, i) the transpose of (i, k) to the bit, every block equal to a
 *     plain serial loop's sum over the terms, bit for bit; the finest level, and a level whose
 *     blocks do not fit in the room (also by one), keep the terms; the blocks summed on 2 and 3
 *     threads are 1 thread's, bit for bit;
 *   - the merged operators F = B + X (amg_merge.c): products against B's rows plus the terms' sum,
 *     the layout, the same bits on 1, 2 and 3 threads, the V-cycle's use, a level out of room
 *     (their blocks bit for bit against a serial sum, and the short path: test_amg_merge.c);
 *   - the restriction of the terms, on 1, 2 and 3 threads, against a plain serial loop over them,
 *     bit for bit (dense coarse levels and lists, a level with room for half);
 *   - a dense level's products read by columns (AVX, a bit-symmetric matrix) or by rows: the plain
 *     row loop's bits on every range of rows. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "amg_scene.h"
#include "bsr_rows.h"
#include "check.h"
#include "test_support.h"
#include "coupling.h"
#include "self_pairs.h"
#include "solve_kernels.h"
#include "step.h"
#include "amg_coupled.h"
#include "two_layers.h"

enum { N = 21 };
static const double SIZE = 0.6;

static void random_vec(double* v, int n3, uint64_t* st) {
    for (int k = 0; k < n3; ++k) {
        *st = *st * 6364136223846793005ull + 1442695040888963407ull;
        v[k] = (double)(*st >> 11) / 9007199254740992.0 - 0.5;
    }
}

static wc_state* coupled_system(wc_model* m) { return amg_coupled_layers(m, N, SIZE); }

static wc_amg* amg_of(wc_state* s) { return s->solver->amg; }

/* y = F x on level l: the BSR part and the couplings. */
static void level_mul(const wc_amg_level* L, const double* x, double* y) {
    wc_par par;
    wc_par_init(&par, 1);
    memset(y, 0, 3 * (size_t)L->n * sizeof(double));
    for (int i = 0; i < L->n; ++i)
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            m3_mulv_add(y + 3 * i, L->val + 9 * (size_t)k, x + 3 * L->col[k]);
    wc_amg_cross_mul_add(L->cross, 1.0, x, y, L->n, &par);
}

static int live(const wc_amg_level* L, int q) { return !L->dead || !L->dead[q]; }

static void test_galerkin(wc_amg* a) {
    uint64_t st = 777;
    wc_par par;
    wc_par_init(&par, 1);
    CHECK(a->n_levels >= 3);
    for (int l = 0; l + 1 < a->n_levels; ++l) {
        const wc_amg_level *L = &a->lev[l], *C = &a->lev[l + 1];
        CHECK(C->cross != NULL && C->cross->n_terms == L->cross->n_terms); /* nothing left out here */
        int nf = 3 * L->n, nc = 3 * C->n;
        double *xc = malloc(nc * sizeof(double)), *yc = malloc(nc * sizeof(double)), *zc = calloc(nc, sizeof(double));
        double *xf = calloc(nf, sizeof(double)), *yf = malloc(nf * sizeof(double));
        random_vec(xc, nc, &st);
        for (int q = 0; q < nc; ++q)
            if (!live(C, q)) xc[q] = 0.0; /* dead unknowns (amg.h): decoupled by the setup */
        level_mul(C, xc, yc);
        for (int i = 0; i < L->n; ++i) /* xf = P xc */
            for (int e = L->p_start[i]; e < L->p_start[i + 1]; ++e) m3_mulv_add(xf + 3 * i, L->p_val + 9 * (size_t)e, xc + 3 * L->p_col[e]);
        level_mul(L, xf, yf);
        for (int i = 0; i < L->n; ++i) /* zc = P^T yf */
            for (int e = L->p_start[i]; e < L->p_start[i + 1]; ++e) {
                const double* P = L->p_val + 9 * (size_t)e;
                double* o = zc + 3 * L->p_col[e];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) o[c] += P[3 * r + c] * yf[3 * i + r];
            }
        double num = 0, den = 0, cross = 0;
        for (int q = 0; q < nc; ++q) {
            if (!live(C, q)) continue;
            num += (yc[q] - zc[q]) * (yc[q] - zc[q]);
            den += zc[q] * zc[q];
        }
        /* the couplings' share, so that the check can fail */
        memset(yc, 0, nc * sizeof(double));
        wc_amg_cross_mul_add(C->cross, 1.0, xc, yc, C->n, &par);
        for (int q = 0; q < nc; ++q) cross += yc[q] * yc[q];
        printf("  level %d -> %d (%d -> %d nodes, %d terms, %d entries): |F_c x - P^T F P x| / |.| = %.1e "
               "(the couplings alone: %.2g)\n",
               l, l + 1, L->n, C->n, C->cross->n_terms, C->cross->n_entries, sqrt(num / den), sqrt(cross / den));
        /* B's Galerkin products in float (single_setup, amg_setup_f.c): within float's rounding of
           sums, still far below the couplings' share */
        const int f = a->opts.single_setup && L->t_val_f && wc_bsr_rows_fx_vector();
        CHECK(sqrt(num / den) < (f ? 1e-5 : 1e-12));
        CHECK(sqrt(cross / den) > 1e-3);
        free(xc);
        free(yc);
        free(zc);
        free(xf);
        free(yf);
    }
    /* the coarsest level's factor: L L^T = its whole operator */
    const wc_amg_level* C = &a->lev[a->n_levels - 1];
    CHECK(a->coarse_dense);
    int d = a->coarse_dofs;
    double* M = calloc((size_t)d * d, sizeof(double));
    double* e = calloc(d, sizeof(double));
    double* col = malloc(d * sizeof(double));
    for (int j = 0; j < d; ++j) { /* column j of the whole operator */
        e[j] = 1.0;
        level_mul(C, e, col);
        e[j] = 0.0;
        for (int i = 0; i < d; ++i) M[(size_t)i * d + j] = col[i];
    }
    double worst = 0, scale = 0;
    for (int i = 0; i < d; ++i)
        for (int j = 0; j < d; ++j) {
            double llt = 0;
            for (int k = 0; k <= (i < j ? i : j); ++k) llt += a->coarse_L[(size_t)k * d + i] * a->coarse_L[(size_t)k * d + j];
            worst = fmax(worst, fabs(llt - M[(size_t)i * d + j]));
            scale = fmax(scale, fabs(M[(size_t)i * d + j]));
        }
    printf("  coarsest level (%d dofs): max |L L^T - F| / max |F| = %.1e\n", d, worst / scale);
    CHECK(worst / scale < 1e-12);
    free(M);
    free(e);
    free(col);
}

static void test_hierarchy(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    wc_par par;
    wc_par_init(&par, 1);
    int active = wc_coupling_active(&s->self_pairs->coupling), n3 = 3 * m.n_particles;
    double *r = malloc(n3 * sizeof(double)), *z[2];
    uint64_t st = 4242;
    random_vec(r, n3, &st);
    for (int variant = 0; variant < 2; ++variant) { /* dense coarse levels (the default), then lists */
        wc_amg* a = amg_coupled_hierarchy(s, variant ? 0 : WC_AMG_CROSS_DENSE_DOFS, &par);
        if (!a) return;
        printf("  %s: %d particles, %d active couplings, %d levels\n", variant ? "term lists on every level" : "dense coarse levels",
               m.n_particles, active, a->n_levels);
        CHECK(active > 100);
        CHECK_EQ_INT(a->lev[0].cross->n_terms, active);
        CHECK((a->lev[1].cross->dense != NULL) == !variant);
        test_galerkin(a);
        amg_check_spd(a, s, variant ? "coupled layers, filtered, lists" : "coupled layers, filtered, dense");
        z[variant] = malloc(n3 * sizeof(double));
        /* B and X apart on every level (the merged operators round the list levels' couplings to
           float where a dense level keeps them in double: test_merged) */
        for (int l = 0; l < a->n_levels; ++l) a->lev[l].cross->m_blocks = 0;
        wc_amg_apply(a, r, z[variant], &par);
        wc_amg_destroy(a);
    }
    double diff = ts_rel_diff(z[1], z[0], n3);
    printf("  one V-cycle, dense coarse levels against lists: %.1e\n", diff);
    CHECK(diff < 1e-10);
    free(r);
    free(z[0]);
    free(z[1]);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* PCG + AMG on the system: iterations and answer. */
static int solve(wc_state* s, double* dv) {
    memset(dv, 0, 3 * (size_t)s->model->n_particles * sizeof(double));
    wc_solve_result res;
    CHECK_EQ_INT(wc_solve(s->solver, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res), WC_OK);
    CHECK(res.converged);
    return res.iterations;
}

static void test_iterations(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    int n3 = 3 * m.n_particles, active = wc_coupling_active(&s->self_pairs->coupling);
    double *with = malloc(n3 * sizeof(double)), *without = malloc(n3 * sizeof(double)),
           *half = malloc(n3 * sizeof(double));
    int it_with = solve(s, with);
    /* room for every term: each level holds all of them (wc_amg.cross_terms) */
    for (int l = 0; l < amg_of(s)->n_levels; ++l) CHECK_EQ_INT(amg_of(s)->cross_terms[l], active);
    wc_diag d = {0};
    CHECK_EQ_INT(wc_amg_set_coupling(amg_of(s), NULL, 0, &d), WC_OK); /* the pattern's hierarchy alone */
    int it_without = solve(s, without);
    CHECK_EQ_INT(wc_amg_set_coupling(amg_of(s), &s->self_pairs->coupling, active / 2, &d), WC_OK);
    long dropped0 = amg_of(s)->cross_dropped;
    int it_half = solve(s, half);
    long dropped = amg_of(s)->cross_dropped - dropped0;
    /* room for half: the finest level holds what fits, no coarser level more than the level above */
    const int* held = amg_of(s)->cross_terms;
    CHECK(held[0] > 0 && held[0] <= active / 2);
    for (int l = 1; l < amg_of(s)->n_levels; ++l) CHECK(held[l] <= held[l - 1]);
    printf("  PCG to 1e-8, %d couplings: %d iterations with them in the hierarchy, %d without, %d with room for "
           "half (%ld left out over its setups); answers differ by %.1e and %.1e\n",
           active, it_with, it_without, it_half, dropped, ts_rel_diff(without, with, n3), ts_rel_diff(half, with, n3));
    CHECK(2 * it_with <= it_without);
    CHECK(dropped > 0);
    CHECK(ts_rel_diff(without, with, n3) < 1e-5); /* both to residual 1e-8 */
    CHECK(ts_rel_diff(half, with, n3) < 1e-5);
    CHECK_EQ_INT(wc_amg_set_coupling(amg_of(s), NULL, 5, &d), WC_OK);
    CHECK(wc_amg_set_coupling(NULL, NULL, 5, &d) == WC_ERROR_INVALID_ARGUMENT);
    CHECK(wc_amg_set_coupling(amg_of(s), &s->self_pairs->coupling, 0, &d) == WC_ERROR_INVALID_ARGUMENT);
    free(with);
    free(without);
    free(half);
    wc_state_destroy(s);
    wc_model_free(&m);
}

static void test_threads(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    int n3 = 3 * m.n_particles;
    double *r = malloc(n3 * sizeof(double)), *z1 = malloc(n3 * sizeof(double)), *z2 = malloc(n3 * sizeof(double));
    uint64_t st = 99;
    random_vec(r, n3, &st);
    wc_amg* a = amg_of(s);
    for (int t = 1; t <= 2; ++t) {
        wc_par par;
        wc_par_init(&par, t);
        wc_amg_setup(a, s->A, &s->filter, &par);
        wc_amg_apply(a, r, t == 1 ? z1 : z2, &par);
        }
    CHECK(memcmp(z1, z2, n3 * sizeof(double)) == 0);
    printf("  V-cycle with the couplings on 1 and 2 threads: %s\n", memcmp(z1, z2, n3 * sizeof(double)) ? "differ" : "bit-identical");
    free(r);
    free(z1);
    free(z2);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Layers small enough for one level: the dense factor is the whole projected system, so PCG with
 * it converges at once. */
static void test_one_level(void) {
    wc_model m;
    wc_state* s = amg_coupled_layers(&m, 6, SIZE * 5.0 / (N - 1));
    if (!s) return;
    int active = wc_coupling_active(&s->self_pairs->coupling), n3 = 3 * m.n_particles;
    double* dv = malloc(n3 * sizeof(double));
    int it = solve(s, dv);
    printf("  two 6 x 6 layers, %d active couplings, %d level: PCG to 1e-8 in %d iterations\n", active,
           amg_of(s)->n_levels, it);
    CHECK(active > 10);
    CHECK_EQ_INT(amg_of(s)->n_levels, 1);
    CHECK(it <= 2);
    free(dv);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* y = sum_k c_k v_k (v_k . x) from level L's term lists. */
static void terms_mul(const wc_amg_cross* X, const double* x, double* y, int n) {
    memset(y, 0, 3 * (size_t)n * sizeof(double));
    for (int q = 0; q < X->n_terms; ++q) {
        double d = 0.0;
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) d += v3_dot(X->val + 3 * (size_t)e, x + 3 * X->node[e]);
        for (int e = X->start[q]; e < X->start[q + 1]; ++e) v3_axpy(y + 3 * X->node[e], X->c[q] * d, X->val + 3 * (size_t)e);
    }
}

/* The summed blocks' layout: columns ascending, (k, i) = (i, k)^T to the bit; returns the
 * mismatches. */
static int summed_layout_errors(const wc_amg_cross* X, int n) {
    int bad = 0;
    for (int i = 0; i < n; ++i)
        for (int b = X->blk_start[i]; b < X->blk_start[i + 1]; ++b) {
            const int k = X->blk_col[b];
            if (b > X->blk_start[i] && X->blk_col[b - 1] >= k) ++bad;
            int t = -1;
            for (int u = X->blk_start[k]; u < X->blk_start[k + 1]; ++u)
                if (X->blk_col[u] == i) t = u;
            if (t < 0) {
                ++bad;
                continue;
            }
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) bad += X->blk_val[9 * (size_t)b + 3 * r + c] != X->blk_val[9 * (size_t)t + 3 * c + r];
        }
    return bad;
}

/* The summed blocks against a plain serial loop over the terms: each term's c (v(i)_r v(k)_s) added
 * to block (i, k) for every pair of its entries, in term order (both triangles: (k, i)'s entries
 * are (i, k)'s products, commuted); every block reached, bit for bit; returns the mismatches. */
static int summed_errors(const wc_amg_cross* X, int n) {
    const int nb = X->n_blocks;
    double* ref = calloc(9 * (size_t)nb + 1, sizeof(double));
    unsigned char* hit = calloc((size_t)nb + 1, 1);
    int bad = 0;
    for (int q = 0; q < X->n_terms; ++q)
        for (int e = X->start[q]; e < X->start[q + 1]; ++e)
            for (int g = X->start[q]; g < X->start[q + 1]; ++g) {
                const int i = X->node[e], k = X->node[g];
                int b = X->blk_start[i];
                while (b < X->blk_start[i + 1] && X->blk_col[b] != k) ++b;
                if (b == X->blk_start[i + 1]) {
                    ++bad; /* a column missing */
                    continue;
                }
                hit[b] = 1;
                const double *u = X->val + 3 * (size_t)e, *v = X->val + 3 * (size_t)g;
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) ref[9 * (size_t)b + 3 * r + c] += X->c[q] * (u[r] * v[c]);
            }
    for (int b = 0; b < nb; ++b) bad += !hit[b]; /* a column no term reaches */
    bad += X->blk_start[n] != nb;
    for (size_t k = 0; k < 9 * (size_t)nb; ++k) bad += memcmp(ref + k, X->blk_val + k, sizeof(double)) != 0;
    free(ref);
    free(hit);
    return bad;
}

/* Levels 1.. of a and b hold the same summed blocks, bit for bit; returns the levels that differ. */
static int summed_differ(const wc_amg* a, const wc_amg* b) {
    int differ = 0;
    for (int l = 1; l < a->n_levels; ++l) {
        const wc_amg_cross *X = a->lev[l].cross, *Y = b->lev[l].cross;
        const int n = a->lev[l].n, nb = X->n_blocks;
        differ += nb != Y->n_blocks ||
                  (nb > 0 && (memcmp(X->blk_start, Y->blk_start, sizeof(int) * ((size_t)n + 1)) ||
                              memcmp(X->blk_col, Y->blk_col, sizeof(int) * (size_t)nb) ||
                              memcmp(X->blk_val, Y->blk_val, 9 * sizeof(double) * (size_t)nb)));
    }
    return differ;
}

static void test_summed(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    wc_par one, two;
    wc_par_init(&one, 1);
    wc_par_init(&two, 2);
    wc_amg* a = amg_coupled_hierarchy(s, 0, &one); /* term lists on every level */
    if (!a) return;
    uint64_t st = 31337;
    int summed = 0;
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_level* L = &a->lev[l];
        const wc_amg_cross* X = L->cross;
        const int n3 = 3 * L->n;
        double *x = malloc(n3 * sizeof(double)), *ref = malloc(n3 * sizeof(double));
        double *y1 = calloc(n3, sizeof(double)), *y2 = calloc(n3, sizeof(double));
        random_vec(x, n3, &st);
        terms_mul(X, x, ref, L->n);
        wc_amg_cross_mul_add(X, 1.0, x, y1, L->n, &one);
        wc_amg_cross_mul_add(X, 1.0, x, y2, L->n, &two);
        const double diff = ts_rel_diff(y1, ref, n3);
        const int bad = X->n_blocks > 0 ? summed_layout_errors(X, L->n) : 0;
        const int sums = X->n_blocks > 0 ? summed_errors(X, L->n) : 0;
        printf("  level %d: %d nodes, %d terms, %d entries, %d summed blocks: |X x - sum c v (v . x)| / |.| = %.1e, "
               "layout errors %d, blocks against the serial loop %d, 1 / 2 threads %s\n",
               l, L->n, X->n_terms, X->n_entries, X->n_blocks, diff, bad, sums,
               memcmp(y1, y2, n3 * sizeof(double)) ? "differ" : "bit-identical");
        CHECK(diff < 1e-13);
        CHECK_EQ_INT(bad, 0);
        CHECK_EQ_INT(sums, 0);
        CHECK(memcmp(y1, y2, n3 * sizeof(double)) == 0);
        CHECK(X->n_blocks <= X->n_entries);
        summed += X->n_blocks > 0;
        free(x);
        free(ref);
        free(y1);
        free(y2);
    }
    /* the finest level keeps its terms (4 particles each, little overlap); the coarse ones overlap
       (a term reaches ~10 nodes of two layers' patches) */
    CHECK_EQ_INT(a->lev[0].cross->n_blocks, 0);
    CHECK_EQ_INT(summed, a->n_levels - 1);
    /* room for fewer blocks than a level needs: the terms' products, the same answer */
    wc_diag d = {0};
    const int active = wc_coupling_active(&s->self_pairs->coupling);
    CHECK_EQ_INT(wc_amg_set_coupling(a, &s->self_pairs->coupling, active, &d), WC_OK);
    const int need = a->lev[1].cross->cap_blocks;
    a->lev[1].cross->cap_blocks = 10;
    wc_amg_setup(a, s->A, &s->filter, &one);
    CHECK_EQ_INT(a->lev[1].cross->n_blocks, 0);
    CHECK(a->lev[2].cross->n_blocks > 0);
    a->lev[1].cross->cap_blocks = need;
    /* the blocks summed on 2 and 3 threads (sum_blocks splits the rows) are those of 1 thread, also
       after a setup that ran out of room on 2 (its counts' marks cleared) */
    wc_amg_setup(a, s->A, &s->filter, &one);
    wc_par three;
    wc_par_init(&three, 3);
    wc_amg* b = amg_coupled_hierarchy(s, 0, &three);
    if (b) {
        CHECK(b->lev[1].cross->n_blocks > 0);
        const int on_three = summed_differ(a, b);
        CHECK_EQ_INT(on_three, 0);
        int three_sums = 0;
        for (int l = 1; l < b->n_levels; ++l) three_sums += summed_errors(b->lev[l].cross, b->lev[l].n);
        CHECK_EQ_INT(three_sums, 0);
        /* room for exactly level 1's blocks (every row's columns staged, the last to the room's
           end), then for one fewer (none summed, the marks cleared) */
        const int exact = b->lev[1].cross->n_blocks;
        b->lev[1].cross->cap_blocks = exact;
        wc_amg_setup(b, s->A, &s->filter, &two);
        CHECK_EQ_INT(b->lev[1].cross->n_blocks, exact);
        const int exact_sums = summed_errors(b->lev[1].cross, b->lev[1].n), exact_differ = summed_differ(a, b);
        CHECK_EQ_INT(exact_sums, 0);
        CHECK_EQ_INT(exact_differ, 0);
        b->lev[1].cross->cap_blocks = exact - 1;
        wc_amg_setup(b, s->A, &s->filter, &two);
        CHECK_EQ_INT(b->lev[1].cross->n_blocks, 0);
        printf("  level 1 with room for exactly its %d blocks, 2 threads: %d mismatches against the serial loop, "
               "%d levels differ from 1 thread's; with one fewer: %d blocks\n",
               exact, exact_sums, exact_differ, b->lev[1].cross->n_blocks);
        b->lev[1].cross->cap_blocks = 10;
        wc_amg_setup(b, s->A, &s->filter, &two);
        CHECK_EQ_INT(b->lev[1].cross->n_blocks, 0);
        int marked = 0; /* every thread's blk_pos back at -1 */
        for (size_t k = 0; k < (size_t)WC_PAR_MAX_THREADS * b->lev[1].n; ++k) marked += b->lev[1].cross->blk_pos[k] != -1;
        CHECK_EQ_INT(marked, 0);
        b->lev[1].cross->cap_blocks = need;
        wc_amg_setup(b, s->A, &s->filter, &one); /* other row ranges than the marks' */
        const int after_full = summed_differ(a, b);
        wc_amg_setup(b, s->A, &s->filter, &two);
        printf("  summed blocks on 3 threads, 1 after 2 out of room, and 2 against 1: %d, %d, %d levels differ\n",
               on_three, after_full, summed_differ(a, b));
        CHECK_EQ_INT(after_full, 0);
        CHECK_EQ_INT(summed_differ(a, b), 0);
        wc_amg_destroy(b);
    }
    wc_amg_destroy(a);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Levels of a and b hold the same merged operators, bit for bit; returns the levels that differ. */
static int merged_differ(const wc_amg* a, const wc_amg* b) {
    int differ = 0;
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_cross *X = a->lev[l].cross, *Y = b->lev[l].cross;
        const int n = a->lev[l].n, nb = X->m_blocks;
        differ += nb != Y->m_blocks ||
                  (nb > 0 && (memcmp(X->m_start, Y->m_start, sizeof(int) * ((size_t)n + 1)) ||
                              memcmp(X->m_col, Y->m_col, sizeof(int) * (size_t)nb) ||
                              memcmp(X->m_val_f, Y->m_val_f, 9 * sizeof(float) * (size_t)nb)));
    }
    return differ;
}

/* The merged operators F = B + X (wc_amg_cross.m_blocks): each level's product against B's rows
 * plus the terms' sum c_k v_k (v_k . x), both in double here (the merged blocks are floats: a few
 * 1e-8 apart); the layout; the same bits on 1, 2 and 3 threads; the V-cycle reads them (its result
 * moves by float roundings when they are taken away); a level whose room is short keeps B and X. */
static void test_merged(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    wc_par one, two, three;
    wc_par_init(&one, 1);
    wc_par_init(&two, 2);
    wc_par_init(&three, 3);
    wc_amg* a = amg_coupled_hierarchy(s, 0, &one); /* term lists on every level: level 0 merged from its terms,
                                          the others from their summed blocks */
    if (!a) return;
    uint64_t st = 4242;
    for (int l = 0; l < a->n_levels; ++l) {
        const wc_amg_level* L = &a->lev[l];
        const wc_amg_cross* X = L->cross;
        const int n3 = 3 * L->n;
        double *x = malloc(n3 * sizeof(double)), *ref = malloc(n3 * sizeof(double));
        double* y = malloc(n3 * sizeof(double));
        int* seen = malloc(sizeof(int) * (size_t)L->n);
        for (int i = 0; i < L->n; ++i) seen[i] = -1;
        random_vec(x, n3, &st);
        terms_mul(X, x, ref, L->n);
        for (int i = 0; i < L->n; ++i)
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
                m3_mulv_add(ref + 3 * i, L->val + 9 * (size_t)k, x + 3 * L->col[k]);
        CHECK(X->m_blocks > 0);
        if (X->m_blocks > 0) {
            wc_bsr_rows_f(X->m_start, X->m_col, X->m_val_f, 0, L->n, NULL, 1.0, x, y);
            const double diff = ts_rel_diff(y, ref, n3);
            const int bad = amg_merged_layout_errors(L, seen);
            printf("  level %d: %d nodes, %d BSR blocks, %d merged: |F x - (B x + sum c v (v . x))| / |.| = %.1e, "
                   "layout errors %d\n", l, L->n, L->n_blocks, X->m_blocks, diff, bad);
            CHECK(diff < 1e-6);
            CHECK_EQ_INT(bad, 0);
            CHECK(X->m_blocks > L->n_blocks); /* the couplings reach outside B's pattern */
        }
        free(x);
        free(ref);
        free(y);
        free(seen);
    }
    wc_amg* b = amg_coupled_hierarchy(s, 0, &three);
    if (b) {
        const int on_three = merged_differ(a, b);
        wc_amg_setup(b, s->A, &s->filter, &two);
        printf("  merged on 3 threads, 2 threads against 1: %d, %d levels differ\n", on_three, merged_differ(a, b));
        CHECK_EQ_INT(on_three, 0);
        CHECK_EQ_INT(merged_differ(a, b), 0);
        /* the V-cycle reads them: without them (B's rows and the terms) it moves by float roundings */
        const int n3 = 3 * b->lev[0].n;
        double *r = malloc(n3 * sizeof(double)), *z1 = malloc(n3 * sizeof(double)), *z2 = malloc(n3 * sizeof(double));
        random_vec(r, n3, &st);
        wc_amg_apply(b, r, z1, &two);
        for (int l = 0; l < b->n_levels; ++l) b->lev[l].cross->m_blocks = 0;
        wc_amg_apply(b, r, z2, &two);
        const double diff = ts_rel_diff(z1, z2, n3);
        printf("  V-cycle merged against B and X apart: %.1e\n", diff);
        CHECK(diff > 0.0 && diff < 1e-5);
        /* room short on level 0: left unmerged, every thread's marks back at -1, the others merged */
        b->lev[0].cross->cap_merged = b->lev[0].n_blocks;
        wc_amg_setup(b, s->A, &s->filter, &two);
        CHECK_EQ_INT(b->lev[0].cross->m_blocks, 0);
        CHECK(b->lev[1].cross->m_blocks > 0);
        int marked = 0;
        for (size_t k = 0; k < (size_t)WC_PAR_MAX_THREADS * b->lev[0].n; ++k) marked += b->lev[0].cross->m_pos[k] != -1;
        CHECK_EQ_INT(marked, 0);
        wc_amg_apply(b, r, z2, &two);
        CHECK(ts_rel_diff(z1, z2, n3) < 1e-5);
        free(r);
        free(z1);
        free(z2);
        wc_amg_destroy(b);
    }
    wc_amg_destroy(a);
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Level l + 1's couplings restricted here from level l's, serially in term order as a plain loop
 * over terms (each term's P^T v accumulated node by node, its live entries in the order first
 * touched, the block diagonal's part and a dense level's upper triangle summed term by term),
 * against what the setup left there; returns the mismatches (0: the same bits). */
static int restricted_errors(const wc_amg* a, int l) {
    const wc_amg_level *L = &a->lev[l], *C = &a->lev[l + 1];
    const wc_amg_cross *X = L->cross, *Y = C->cross;
    if (X->dense) return 0; /* a dense level's Galerkin product P^T X P: serial, not restricted */
    const int n = C->n, g = C->group;
    const size_t d = 3 * (size_t)n;
    double *acc = calloc(d, sizeof(double)), *dadd = calloc(9 * (size_t)g * n, sizeof(double));
    double* dense = Y->dense ? calloc(d * d, sizeof(double)) : NULL;
    int* touched = malloc(sizeof(int) * (size_t)n);
    unsigned char* mark = calloc((size_t)n, 1);
    int bad = 0, e = 0, q = 0;
    for (; q < X->n_terms; ++q) {
        int nt = 0;
        for (int s = X->start[q]; s < X->start[q + 1]; ++s) {
            const double* v = X->val + 3 * (size_t)s;
            for (int pe = L->p_start[X->node[s]]; pe < L->p_start[X->node[s] + 1]; ++pe) {
                const int J = L->p_col[pe];
                const double* P = L->p_val + 9 * (size_t)pe;
                double* o = acc + 3 * (size_t)J;
                if (!mark[J]) touched[nt++] = J;
                mark[J] = 1;
                o[0] += P[0] * v[0] + P[3] * v[1] + P[6] * v[2];
                o[1] += P[1] * v[0] + P[4] * v[1] + P[7] * v[2];
                o[2] += P[2] * v[0] + P[5] * v[1] + P[8] * v[2];
            }
        }
        const double c = X->c[q];
        if (dense) {
            for (int u = 0; u < nt; ++u)
                for (int w = 0; w < nt; ++w) {
                    const int I = touched[u], J = touched[w];
                    if (J < I) continue;
                    for (int r = 0; r < 3; ++r)
                        for (int k = 0; k < 3; ++k) dense[(3 * (size_t)I + r) * d + 3 * (size_t)J + k] += c * acc[3 * I + r] * acc[3 * J + k];
                }
        } else if (e + nt > Y->cap_entries) {
            break; /* this term and the later ones left out */
        } else {
            for (int u = 0; u < nt; ++u) {
                const int J = touched[u];
                const double* o = acc + 3 * (size_t)J;
                if (o[0] == 0.0 && o[1] == 0.0 && o[2] == 0.0) continue;
                bad += Y->node[e] != J || memcmp(Y->val + 3 * (size_t)e, o, 3 * sizeof(double)) != 0;
                ++e;
                for (int p = 0; p < g; ++p) { /* (J, J), and (J, J ^ 1) on a pair level */
                    const double* b = acc + 3 * (size_t)(g == 1 ? J : (J & ~1) + p);
                    double* Da = dadd + 9 * ((size_t)g * J + p);
                    for (int r = 0; r < 3; ++r)
                        for (int k = 0; k < 3; ++k) Da[3 * r + k] += c * o[r] * b[k];
                }
            }
            bad += Y->start[q + 1] != e || Y->c[q] != c;
        }
        for (int u = 0; u < nt; ++u) {
            acc[3 * touched[u]] = acc[3 * touched[u] + 1] = acc[3 * touched[u] + 2] = 0.0;
            mark[touched[u]] = 0;
        }
    }
    bad += Y->n_terms != q;
    if (dense) {
        for (size_t I = 0; I < d; ++I)
            for (size_t J = 0; J < I; ++J) dense[I * d + J] = dense[J * d + I];
        for (size_t k = 0; k < d * d; ++k) bad += memcmp(dense + k, Y->dense + k, sizeof(double)) != 0;
    } else {
        bad += Y->n_entries != e;
        for (size_t k = 0; k < 9 * (size_t)g * n; ++k) bad += memcmp(dadd + k, Y->dadd + k, sizeof(double)) != 0;
    }
    free(acc);
    free(dadd);
    free(dense);
    free(touched);
    free(mark);
    return bad;
}

/* The restriction of the couplings (wc_amg_cross_restrict: a list level's terms over ranges of
 * terms, their block diagonal's part over nodes, a dense level's rows) on 1, 2 and 3 threads
 * against a plain serial loop over the terms, bit for bit, with dense coarse levels and with lists
 * on every level, also with room for half the terms on level 1 (the later ones left out); a dense
 * level 1 also in batches of 7 terms and of 1 (restrict_dense's stage). */
static void test_restricted(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    const int active = wc_coupling_active(&s->self_pairs->coupling);
    for (int variant = 0; variant < 2; ++variant)
        for (int t = 1; t <= 3; ++t) {
            wc_par par;
            wc_par_init(&par, t);
            wc_amg* a = amg_coupled_hierarchy(s, variant ? 0 : WC_AMG_CROSS_DENSE_DOFS, &par);
            if (!a) return;
            int bad = 0, dense = 0;
            for (int l = 0; l + 1 < a->n_levels; ++l) {
                bad += restricted_errors(a, l);
                dense += a->lev[l + 1].cross->dense != NULL;
            }
            int short_bad = 0, held = 0, batch_bad = 0;
            wc_amg_cross* Y1 = a->lev[1].cross;
            if (Y1->dense) { /* restrict_dense's batches: the last one partial; then 7 terms, 1 term a batch */
                CHECK(active > Y1->stage_terms && active % Y1->stage_terms != 0);
                for (int b = 7; b > 0; b -= 6) {
                    Y1->stage_terms = b;
                    wc_amg_setup(a, s->A, &s->filter, &par);
                    batch_bad += restricted_errors(a, 0);
                }
                printf("  batches of %d terms (%d nodes), then 7 and 1: %d mismatches\n", Y1->stage_cap, a->lev[1].n, batch_bad);
            } else { /* room for about half the terms on level 1 */
                a->lev[1].cross->cap_entries = a->lev[1].cross->n_entries / 2;
                wc_amg_setup(a, s->A, &s->filter, &par);
                held = a->lev[1].cross->n_terms;
                for (int l = 0; l + 1 < a->n_levels; ++l) short_bad += restricted_errors(a, l);
                CHECK(held > 0 && held < active);
            }
            printf("  %s, %d thread%s: %d levels restricted (%d dense), %d mismatches against the serial loop; "
                   "level 1 with room for half: %d of %d terms held, %d mismatches\n",
                   variant ? "lists" : "dense coarse levels", t, t > 1 ? "s" : "", a->n_levels - 1, dense, bad, held,
                   active, short_bad);
            CHECK(variant || dense > 0);
            CHECK_EQ_INT(bad, 0);
            CHECK_EQ_INT(short_bad, 0);
            CHECK_EQ_INT(batch_bad, 0);
            wc_amg_destroy(a);
        }
    wc_state_destroy(s);
    wc_model_free(&m);
}

/* Rows [r0, r1) of y += alpha M x, each a scalar sum over k ascending (the product's definition). */
static void dense_ref(const double* M, int d, double alpha, const double* x, double* y, int r0, int r1) {
    for (int r = r0; r < r1; ++r) {
        double acc = 0.0;
        for (int k = 0; k < d; ++k) acc += M[(size_t)r * d + k] * x[k];
        y[r] += alpha * acc;
    }
}

/* Rows of y differing in bits from the plain row loop's over ranges of every length and offset
 * (panels of 16 and 4 and the rows left), alpha -1, 1 and 0.7; rows outside the range untouched. */
static int dense_rows_errors(const wc_amg_cross* X, int d, int vec, uint64_t* st) {
    double *x = malloc(sizeof(double) * d), *y0 = malloc(sizeof(double) * d), *y = malloc(sizeof(double) * d),
           *yr = malloc(sizeof(double) * d);
    random_vec(x, d, st);
    random_vec(y0, d, st);
    const double alphas[3] = {-1.0, 1.0, 0.7};
    int bad = 0;
    for (int r0 = 0; r0 < d; r0 += r0 < 40 ? 1 : 37)
        for (int len = 1; r0 + len <= d; len += len < 40 ? 1 : 53) {
            const double alpha = alphas[(r0 + len) % 3];
            memcpy(y, y0, sizeof(double) * d);
            memcpy(yr, y0, sizeof(double) * d);
            wc_amg_cross_dense_rows(X, d, alpha, x, y, r0, r0 + len, vec);
            dense_ref(X->dense, d, alpha, x, yr, r0, r0 + len);
            for (int r = 0; r < d; ++r) bad += memcmp(y + r, yr + r, sizeof(double)) != 0;
        }
    free(x);
    free(y0);
    free(y);
    free(yr);
    return bad;
}

/* A dense level's products (wc_amg_cross_dense_rows): one restricted from a list level is
 * symmetric to the bit and marked so, a Galerkin product's is not marked; read by columns (AVX)
 * or by rows, each row's sum is the plain row loop's, bit for bit, on every range of rows; a
 * matrix not marked symmetric (here not symmetric) is read by rows. */
static void test_dense_rows(void) {
    wc_model m;
    wc_state* s = coupled_system(&m);
    if (!s) return;
    wc_par par;
    wc_par_init(&par, 1);
    wc_amg* a = amg_coupled_hierarchy(s, WC_AMG_CROSS_DENSE_DOFS, &par);
    if (!a) return;
    const int vec = wc_amg_cross_dense_vec();
    uint64_t st = 7;
    int levels = 0, sym_levels = 0, asym = 0, bad = 0;
    for (int l = 1; l < a->n_levels; ++l) {
        const wc_amg_cross* X = a->lev[l].cross;
        if (!X->dense || X->n_terms == 0) continue;
        const int d = 3 * a->lev[l].n;
        CHECK_EQ_INT(X->dense_sym, !a->lev[l - 1].cross->dense);
        if (X->dense_sym) {
            ++sym_levels;
            for (int r = 0; r < d; ++r)
                for (int k = 0; k < r; ++k)
                    asym += memcmp(X->dense + (size_t)r * d + k, X->dense + (size_t)k * d + r, sizeof(double)) != 0;
        }
        for (int v = 0; v <= vec; ++v) bad += dense_rows_errors(X, d, v, &st);
        ++levels;
    }
    /* a matrix that is not symmetric, not marked so: by rows whatever vec */
    const int d = 45;
    wc_amg_cross Z;
    memset(&Z, 0, sizeof Z);
    Z.dense = malloc(sizeof(double) * d * d);
    random_vec(Z.dense, d * d, &st);
    const int bad_asym = dense_rows_errors(&Z, d, vec, &st);
    Z.dense_sym = 1; /* marked symmetric, it is read by columns: M^T x */
    double *x = malloc(sizeof(double) * d), *y = calloc(d, sizeof(double)), *yr = calloc(d, sizeof(double));
    random_vec(x, d, &st);
    wc_amg_cross_dense_rows(&Z, d, 1.0, x, y, 0, d, vec);
    dense_ref(Z.dense, d, 1.0, x, yr, 0, d);
    const int cols_read = vec && memcmp(y, yr, sizeof(double) * d) != 0;
    printf("  %d dense levels (%d restricted from lists, %d entries off symmetric), AVX %s: %d rows differ from "
           "the row loop; unmarked 45 x 45: %d; marked: read by columns %s\n",
           levels, sym_levels, asym, vec ? "on" : "off", bad, bad_asym, cols_read ? "yes" : "no");
    CHECK(sym_levels > 0);
    CHECK_EQ_INT(asym, 0);
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bad_asym, 0);
    CHECK(cols_read || !vec);
    free(Z.dense);
    free(x);
    free(y);
    free(yr);
    wc_amg_destroy(a);
    wc_state_destroy(s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_hierarchy);
    RUN_TEST(test_iterations);
    RUN_TEST(test_threads);
    RUN_TEST(test_one_level);
    RUN_TEST(test_summed);
    RUN_TEST(test_merged);
    RUN_TEST(test_restricted);
    RUN_TEST(test_dense_rows);
    return TEST_SUMMARY();
}
