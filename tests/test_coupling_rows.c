/* The couplings' product by rows (core/coupling.h, wc_coupling_rows), which PCG and the solvers'
 * operator run on their threads:
 *   - against the off-diagonal blocks c w_a w_b n n^T (a != b) summed here term by term, pair by
 *     pair (an independent form of the product);
 *   - bit-identical to the serial wc_coupling_mul_offdiag_add for 1 to 5 "threads" (the terms and
 *     the rows split as par.h splits them, the parts run in reverse order), with inactive terms
 *     (c = 0) that must leave y alone even where it holds -0.0;
 *   - the index refuses what it has no room for (more terms than the capacity, a particle out
 *     of range), and a rebuild after the terms changed follows them. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "test_support.h"
#include "coupling.h"
#include "par.h"
#include "vec3.h"

enum { N = 40, TERMS = 300 };

static double urand(unsigned* s) {
    *s = *s * 1664525u + 1013904223u;
    return (*s >> 8) / 16777216.0;
}

/* random terms on N particles (2 to 4 distinct each, about one in six inactive) */
static void make_terms(wc_coupling_term* t, int n, unsigned seed) {
    for (int k = 0; k < n; ++k) {
        t[k].cnt = 2 + (int)(urand(&seed) * 3);
        for (int a = 0; a < t[k].cnt; ++a) {
            int p, dup;
            do {
                p = (int)(urand(&seed) * N);
                dup = 0;
                for (int b = 0; b < a; ++b) dup |= t[k].p[b] == p;
            } while (dup);
            t[k].p[a] = p;
            t[k].w[a] = urand(&seed) * 2.0 - 1.0;
        }
        double v[3] = {urand(&seed) - 0.5, urand(&seed) - 0.5, urand(&seed) - 0.5};
        v3_scale(t[k].n, v, 1.0 / v3_norm(v));
        t[k].c = urand(&seed) < 1.0 / 6 ? 0.0 : 1.0 + 100.0 * urand(&seed);
    }
}

/* the product through the index, split over nt parts each way, the parts in reverse order */
static void rows_product(const wc_coupling* c, wc_coupling_rows* r, double alpha, const double* x, double* y,
                         int nt) {
    int lo, hi;
    for (int t = nt - 1; t >= 0; --t) {
        wc_par_range(c->n, t, nt, &lo, &hi);
        wc_coupling_scale_terms(c, r, alpha, x, lo, hi);
    }
    for (int t = nt - 1; t >= 0; --t) {
        wc_par_range(N, t, nt, &lo, &hi);
        wc_coupling_rows_add(c, r, y, lo, hi);
    }
}

static void test_rows_against_serial_and_pairs(void) {
    wc_coupling_term term[TERMS];
    make_terms(term, TERMS, 12345u);
    wc_coupling c = {TERMS, term};
    wc_coupling_rows* r = wc_coupling_rows_create(N, TERMS, NULL);
    CHECK(r != NULL);
    if (!r) return;
    CHECK(wc_coupling_rows_build(r, &c));
    unsigned seed = 99u;
    double x[3 * N], y0[3 * N], ys[3 * N], yr[3 * N], yp[3 * N];
    for (int i = 0; i < 3 * N; ++i) {
        x[i] = urand(&seed) * 2.0 - 1.0;
        y0[i] = i % 7 == 0 ? -0.0 : urand(&seed) - 0.5;
    }
    /* particle 0 only in inactive terms: its row must keep its -0.0 */
    for (int k = 0; k < TERMS; ++k)
        for (int a = 0; a < term[k].cnt; ++a)
            if (term[k].p[a] == 0 && term[k].c > 0.0) term[k].c = 0.0;
    CHECK(wc_coupling_rows_build(r, &c));
    int multi = 0; /* rows with three or more slots: their additions' order matters */
    for (int i = 0; i < N; ++i) multi += r->row_start[i + 1] - r->row_start[i] >= 3;
    CHECK(multi > N / 2);
    const double alphas[2] = {1.0, -1.0};
    for (int ia = 0; ia < 2; ++ia) {
        const double alpha = alphas[ia];
        /* independent: y += alpha c w_a w_b n (n . x_b) over the pairs a != b of active terms */
        memcpy(yp, y0, sizeof yp);
        for (int k = 0; k < TERMS; ++k) {
            const wc_coupling_term* t = &term[k];
            if (t->c == 0.0) continue;
            for (int a = 0; a < t->cnt; ++a)
                for (int b = 0; b < t->cnt; ++b)
                    if (a != b)
                        v3_axpy(yp + 3 * t->p[a], alpha * t->c * t->w[a] * t->w[b] * v3_dot(t->n, x + 3 * t->p[b]),
                                t->n);
        }
        memcpy(ys, y0, sizeof ys);
        wc_coupling_mul_offdiag_add(&c, alpha, x, ys);
        double err = 0.0, scale = 0.0;
        for (int i = 0; i < 3 * N; ++i) {
            err = fmax(err, fabs(ys[i] - yp[i]));
            scale = fmax(scale, fabs(yp[i] - y0[i]));
        }
        CHECK(scale > 1.0);
        CHECK(err <= 1e-12 * scale);
        int same = 0;
        for (int nt = 1; nt <= 5; ++nt) {
            memcpy(yr, y0, sizeof yr);
            rows_product(&c, r, alpha, x, yr, nt);
            same += memcmp(yr, ys, sizeof yr) == 0;
        }
        CHECK_EQ_INT(same, 5);
        CHECK(signbit(yr[0]) && yr[0] == 0.0);
        printf("  alpha %+g: serial product within %.2g of the pairs' sum (scale %.3g); the rows' product "
               "bit-equal to it on %d of 1-5 parts\n", alpha, err, scale, same);
    }
    /* the terms change (particles and activity): a rebuild follows them */
    make_terms(term, TERMS / 2, 777u);
    c.n = TERMS / 2;
    CHECK(wc_coupling_rows_build(r, &c));
    memcpy(ys, y0, sizeof ys);
    wc_coupling_mul_offdiag_add(&c, 1.0, x, ys);
    memcpy(yr, y0, sizeof yr);
    rows_product(&c, r, 1.0, x, yr, 3);
    CHECK(memcmp(yr, ys, sizeof yr) == 0);
    wc_coupling_rows_destroy(r, NULL);
}

static void test_refusals(void) {
    wc_coupling_term term[8];
    make_terms(term, 8, 4242u);
    for (int k = 0; k < 8; ++k) term[k].c = 1.0;
    wc_coupling c = {8, term};
    wc_coupling_rows* r = wc_coupling_rows_create(N, 4, NULL);
    CHECK(r != NULL);
    if (!r) return;
    CHECK(!wc_coupling_rows_build(r, &c)); /* 8 terms, room for 4 */
    c.n = 4;
    CHECK(wc_coupling_rows_build(r, &c));
    term[2].p[1] = N;
    CHECK(!wc_coupling_rows_build(r, &c)); /* a particle out of range */
    term[2].c = 0.0;
    CHECK(wc_coupling_rows_build(r, &c)); /* inactive: not indexed */
    CHECK(!wc_coupling_rows_build(r, NULL));
    CHECK(!wc_coupling_rows_build(NULL, &c));
    CHECK(wc_coupling_rows_create(0, 4, NULL) == NULL);
    wc_coupling_rows_destroy(r, NULL);
}

int main(void) {
    RUN_TEST(test_rows_against_serial_and_pairs);
    RUN_TEST(test_refusals);
    return TEST_SUMMARY();
}
