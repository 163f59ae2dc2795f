/* The penalty-pair list shared by the mesh colliders' feature pairs and the self-contact pairs
 * (core/penalty_pairs.h):
 *   - an in-pattern list and a coupled list holding the same pair put the same operator into the
 *     system (A's blocks, or A's diagonal blocks plus the coupling's off-diagonal ones) and the
 *     same right-hand side;
 *   - the recheck releases a pair that the solve moved apart (A, b and the coupling back to the
 *     system without it) and takes it back when it closes again; Newton's terms follow g(x);
 *   - the stiffness leaves pinned particles out (sticking ones in);
 *   - what cannot be kept is counted and leaves the list as it was: a pair without pattern
 *     blocks (skipped), a pair past the capacity (overflow). */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_support.h"
#include "coupling.h"
#include "filter.h"
#include "penalty_pairs.h"
#include "vec3.h"

enum { G = 3 };                  /* vertices per side of the sheet */
static const double HE = 1.0 / 60; /* the system's step, s */

/* 1 when the pattern has block (i, j) */
static int has_block(const wc_bsr_pattern* pt, int i, int j) {
    for (int k = pt->row_start[i]; k < pt->row_start[i + 1]; ++k)
        if (pt->col[k] == j) return 1;
    return 0;
}

/* y = A x plus the coupling's off-diagonal blocks (c NULL: none) */
static void system_mul(const wc_model* m, const double* A, const wc_coupling* c, const double* x, double* y) {
    wc_par one;
    wc_par_init(&one, 1);
    wc_bsr_mul(&m->pattern, A, x, y, &one);
    wc_coupling_mul_offdiag_add(c, 1.0, x, y);
}

/* A pair on a spring's two ends (sharing a block), the sheet's point between them 2 mm below a
 * floor at 0: n = +y, off so that g(x_n) = -2 mm. */
typedef struct pair_def {
    int cnt, p[2];
    double w[2], n[3], off, k;
} pair_def;

static pair_def spring_pair(const wc_model* m) {
    pair_def d;
    memset(&d, 0, sizeof d);
    d.cnt = 2;
    d.p[0] = m->springs[0].a;
    d.p[1] = m->springs[0].b;
    d.w[0] = d.w[1] = 0.5;
    d.n[1] = 1.0;
    double y = 0.5 * m->rest_pos[3 * d.p[0] + 1] + 0.5 * m->rest_pos[3 * d.p[1] + 1];
    d.off = y + 0.002;
    d.k = wc_penalty_stiffness(wc_penalty_inv_mass(m, NULL, NULL, d.cnt, d.p, d.w), HE);
    return d;
}

static void test_two_kinds_same_system(void) {
    wc_model m;
    CHECK(ts_sheet(&m, G, 1.0, 0.0, 0, 1.0));
    const int n3 = 3 * m.n_particles, nb = m.pattern.n_blocks;
    pair_def d = spring_pair(&m);
    wc_penalty_pairs in, co;
    CHECK(wc_penalty_pairs_init(&in, 4, 1, NULL));
    CHECK(wc_penalty_pairs_init(&co, 4, 0, NULL));
    CHECK_EQ_INT(wc_penalty_pairs_add(&in, &m.pattern, d.cnt, d.p, d.w, d.n, d.off, d.k), 1);
    CHECK_EQ_INT(wc_penalty_pairs_add(&co, &m.pattern, d.cnt, d.p, d.w, d.n, d.off, d.k), 1);
    wc_coupling cpl = {co.n, co.term};
    double* A_in = calloc(9 * (size_t)nb, sizeof(double));
    double* A_co = calloc(9 * (size_t)nb, sizeof(double));
    double *b_in = calloc(n3, sizeof(double)), *b_co = calloc(n3, sizeof(double));
    double *vstar = calloc(n3, sizeof(double)), *x = calloc(n3, sizeof(double));
    double *y_in = calloc(n3, sizeof(double)), *y_co = calloc(n3, sizeof(double));
    CHECK_EQ_INT(wc_penalty_pairs_assemble(&in, &m, m.rest_pos, vstar, NULL, HE, A_in, b_in, NULL), 1);
    CHECK_EQ_INT(wc_penalty_pairs_assemble(&co, &m, m.rest_pos, vstar, NULL, HE, A_co, b_co, NULL), 1);
    CHECK(in.active[0] == 1 && co.active[0] == 1);
    CHECK(co.term[0].c == HE * HE * d.k);
    CHECK(wc_coupling_active(&cpl) == 1);
    for (int k = 0; k < n3; ++k) x[k] = 0.1 * (k % 7) - 0.3;
    system_mul(&m, A_in, NULL, x, y_in);
    system_mul(&m, A_co, &cpl, x, y_co);
    double worst = 0.0, scale = ts_max_abs(y_in, n3);
    for (int k = 0; k < n3; ++k) worst = fmax(worst, fabs(y_in[k] - y_co[k]));
    printf("  in-pattern and coupled operators differ by %.3g of %.3g\n", worst, scale);
    CHECK(scale > 0.0);
    CHECK(worst <= 1e-14 * scale);
    CHECK(ts_max_diff(b_in, b_co, n3) == 0.0);
    /* the force on the pair's particles pushes up (the gap is negative) */
    CHECK(b_in[3 * d.p[0] + 1] > 0.0 && b_in[3 * d.p[1] + 1] > 0.0);
    free(A_in), free(A_co), free(b_in), free(b_co), free(vstar), free(x), free(y_in), free(y_co);
    wc_penalty_pairs_free(&in, NULL);
    wc_penalty_pairs_free(&co, NULL);
    wc_model_free(&m);
}

static void test_recheck_and_newton(void) {
    wc_model m;
    CHECK(ts_sheet(&m, G, 1.0, 0.0, 0, 1.0));
    const int n3 = 3 * m.n_particles, nb = m.pattern.n_blocks;
    pair_def d = spring_pair(&m);
    for (int kind = 0; kind < 2; ++kind) {
        wc_penalty_pairs pp;
        CHECK(wc_penalty_pairs_init(&pp, 2, kind == 0, NULL));
        CHECK_EQ_INT(wc_penalty_pairs_add(&pp, &m.pattern, d.cnt, d.p, d.w, d.n, d.off, d.k), 1);
        double* A = calloc(9 * (size_t)nb, sizeof(double));
        double* A0 = calloc(9 * (size_t)nb, sizeof(double));
        double *b = calloc(n3, sizeof(double)), *vstar = calloc(n3, sizeof(double));
        double *dv = calloc(n3, sizeof(double)), *g = calloc(n3, sizeof(double));
        for (int k = 0; k < 9 * nb; ++k) A[k] = A0[k] = (k % 9) % 4 == 0 ? 1.0 : 0.0;   /* identity blocks */
        CHECK_EQ_INT(wc_penalty_pairs_assemble(&pp, &m, m.rest_pos, vstar, NULL, HE, A, b, NULL), 1);
        /* a solve that lifts both particles 6 mm over the substep: the gap opens, the pair is released */
        dv[3 * d.p[0] + 1] = dv[3 * d.p[1] + 1] = 0.006 / HE;
        CHECK_EQ_INT(wc_penalty_pairs_recheck(&pp, &m, m.rest_pos, vstar, dv, HE, A, b), 1);
        CHECK(pp.active[0] == 0 && pp.term[0].c == 0.0);
        CHECK(ts_max_diff(A, A0, 9 * nb) <= 1e-12);
        CHECK(ts_max_abs(b, n3) <= 1e-12);
        CHECK_EQ_INT(wc_penalty_pairs_recheck(&pp, &m, m.rest_pos, vstar, dv, HE, A, b), 0);
        /* one that leaves them where they are: taken back */
        memset(dv, 0, n3 * sizeof(double));
        CHECK_EQ_INT(wc_penalty_pairs_recheck(&pp, &m, m.rest_pos, vstar, dv, HE, A, b), 1);
        CHECK(pp.active[0] == 1 && pp.term[0].c == HE * HE * d.k);
        /* Newton: touching at the rest positions (g = -2 mm), not 1 cm higher */
        double e = wc_penalty_pairs_energy(&pp, m.rest_pos);
        CHECK_NEAR(e, 0.5 * d.k * 0.002 * 0.002, 1e-9 * e);
        CHECK_EQ_INT(wc_penalty_pairs_newton(&pp, &m, m.rest_pos, HE, A, g), 1);
        CHECK(pp.active[0] == 1 && g[3 * d.p[0] + 1] > 0.0);
        double* x = malloc(n3 * sizeof(double));
        memcpy(x, m.rest_pos, n3 * sizeof(double));
        x[3 * d.p[0] + 1] += 0.01;
        x[3 * d.p[1] + 1] += 0.01;
        CHECK(wc_penalty_pairs_energy(&pp, x) == 0.0);
        CHECK_EQ_INT(wc_penalty_pairs_newton(&pp, &m, x, HE, A, g), 0);
        CHECK(pp.active[0] == 0 && pp.term[0].c == 0.0);
        free(A), free(A0), free(b), free(vstar), free(dv), free(g), free(x);
        wc_penalty_pairs_free(&pp, NULL);
    }
    wc_model_free(&m);
}

static void test_inv_mass(void) {
    wc_model m;
    CHECK(ts_sheet(&m, G, 1.0, 0.0, 0, 1.0));
    pair_def d = spring_pair(&m);
    const int n = m.n_particles;
    wc_filter f;
    f.n = n;
    f.S = calloc(9 * (size_t)n, sizeof(double));
    f.z = calloc(3 * (size_t)n, sizeof(double));
    f.ndof = calloc((size_t)n, 1);
    for (int i = 0; i < n; ++i) wc_filter_free_particle(&f, i);
    unsigned char* stick = calloc((size_t)n, 1);
    double all = wc_penalty_inv_mass(&m, &f, stick, d.cnt, d.p, d.w);
    CHECK_NEAR(all, 0.25 * m.inv_mass[d.p[0]] + 0.25 * m.inv_mass[d.p[1]], 1e-15 * all);
    f.ndof[d.p[0]] = 3;   /* pinned */
    CHECK_NEAR(wc_penalty_inv_mass(&m, &f, stick, d.cnt, d.p, d.w), 0.25 * m.inv_mass[d.p[1]], 1e-15 * all);
    stick[d.p[0]] = 1;    /* held by a sticking contact: still moves with its collider */
    CHECK(wc_penalty_inv_mass(&m, &f, stick, d.cnt, d.p, d.w) == all);
    stick[d.p[0]] = 0;
    f.ndof[d.p[1]] = 3;
    CHECK(wc_penalty_inv_mass(&m, &f, stick, d.cnt, d.p, d.w) == 0.0);
    free(f.S), free(f.z), free(f.ndof), free(stick);
    wc_model_free(&m);
}

static void test_what_cannot_be_kept(void) {
    wc_model m;
    CHECK(ts_sheet(&m, G, 1.0, 0.0, 0, 1.0));
    pair_def d = spring_pair(&m);
    wc_penalty_pairs pp;
    CHECK(wc_penalty_pairs_init(&pp, 0, 1, NULL));   /* a capacity below 1 is taken as 1 */
    CHECK_EQ_INT(pp.cap, 1);
    /* two opposite corners share no spring: no block, skipped */
    int far[2] = {ts_sheet_particle(&m, G, 0, 0), ts_sheet_particle(&m, G, G - 1, G - 1)};
    CHECK(!has_block(&m.pattern, far[0], far[1]));
    CHECK_EQ_INT(wc_penalty_pairs_add(&pp, &m.pattern, 2, far, d.w, d.n, d.off, d.k), 0);
    CHECK_EQ_INT(pp.skipped, 1);
    CHECK_EQ_INT(pp.n, 0);
    CHECK_EQ_INT(wc_penalty_pairs_add(&pp, &m.pattern, d.cnt, d.p, d.w, d.n, d.off, d.k), 1);
    /* past the capacity: counted, the kept pair untouched */
    double n2[3] = {0.0, 0.0, 1.0};
    CHECK_EQ_INT(wc_penalty_pairs_add(&pp, &m.pattern, d.cnt, d.p, d.w, n2, 1.0, 2.0 * d.k), 0);
    CHECK_EQ_INT(pp.overflow, 1);
    CHECK_EQ_INT(pp.n, 1);
    CHECK(pp.term[0].n[1] == 1.0 && pp.off[0] == d.off && pp.k[0] == d.k && pp.active[0] == 0);
    /* a coupled list needs no blocks: the far pair is kept */
    wc_penalty_pairs co;
    CHECK(wc_penalty_pairs_init(&co, 1, 0, NULL));
    CHECK_EQ_INT(wc_penalty_pairs_add(&co, &m.pattern, 2, far, d.w, d.n, d.off, d.k), 1);
    CHECK_EQ_INT(co.skipped, 0);
    wc_penalty_pairs_clear(&pp);
    CHECK(pp.n == 0 && pp.overflow == 0 && pp.skipped == 0);
    wc_penalty_pairs_free(&co, NULL);
    wc_penalty_pairs_free(&pp, NULL);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_two_kinds_same_system);
    RUN_TEST(test_recheck_and_newton);
    RUN_TEST(test_inv_mass);
    RUN_TEST(test_what_cannot_be_kept);
    return TEST_SUMMARY();
}
