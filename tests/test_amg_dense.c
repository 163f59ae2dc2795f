/* The coarsest level's dense factor and solve (core/amg_dense.c) against the row-major factor
 * they replaced, kept here verbatim as the reference:
 *   - bit for bit: the factor (stored transposed, L[i][k] = M[k d + i]) and the solve, on the AVX
 *     path and the scalar one, for sizes around the 16-row blocks, a semi-definite matrix whose
 *     dependent unknowns are decoupled, and the real coarsest operator of a 16 x 16 sheet's
 *     multigrid (72 nodes, 216 unknowns), whose setup is checked to hold that factor;
 *   - only the lower triangle is read (the upper one is filled with NaN);
 *   - L L^T reproduces the operator and the solve inverts it. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "amg.h"
#include "amg_scene.h"
#include "check.h"

/* The factor and solve as core/amg_setup.c and amg_cycle.c had them (lower, row-major). */
static void ref_factor(double* M, int d) {
    double scale = 0.0;
    for (int i = 0; i < d; ++i) scale = fmax(scale, fabs(M[(size_t)i * d + i]));
    for (int j = 0; j < d; ++j) {
        double* Rj = M + (size_t)j * d;
        double s = Rj[j];
        for (int k = 0; k < j; ++k) s -= Rj[k] * Rj[k];
        if (!(s > 1e-14 * scale)) {
            for (int k = 0; k < j; ++k) Rj[k] = 0.0;
            s = 1.0;
            for (int i = j + 1; i < d; ++i) M[(size_t)i * d + j] = 0.0;
        }
        double ljj = sqrt(s);
        Rj[j] = ljj;
        for (int i = j + 1; i < d; ++i) {
            double* Ri = M + (size_t)i * d;
            double t = Ri[j];
            for (int k = 0; k < j; ++k) t -= Ri[k] * Rj[k];
            Ri[j] = t / ljj;
        }
    }
}

static void ref_solve(const double* M, int d, const double* r, double* y, double* x) {
    for (int i = 0; i < d; ++i) {
        double s = r[i];
        const double* Ri = M + (size_t)i * d;
        for (int k = 0; k < i; ++k) s -= Ri[k] * y[k];
        y[i] = s / Ri[i];
    }
    for (int i = d - 1; i >= 0; --i) {
        double s = y[i];
        for (int k = i + 1; k < d; ++k) s -= M[(size_t)k * d + i] * x[k];
        x[i] = s / M[(size_t)i * d + i];
    }
}

static uint64_t rng = 88172645463325252ull;
static double urand(void) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0 - 0.5;
}

/* Factor and solve A (d x d, row-major, lower triangle meaningful) both ways; the new factor
 * sees NaN above the diagonal. Returns 1 when every bit agrees. */
static int compare(const double* A, int d, int vec, double* llt_err, double* solve_err) {
    const size_t dd = (size_t)d * d;
    double *R = malloc(dd * sizeof(double)), *U = malloc(dd * sizeof(double));
    double *r = calloc(d, sizeof(double)), *y = calloc(d, sizeof(double)), *x0 = calloc(d, sizeof(double)),
           *x1 = calloc(d, sizeof(double));
    memcpy(R, A, dd * sizeof(double));
    memcpy(U, A, dd * sizeof(double));
    for (int i = 0; i < d; ++i)
        for (int j = i + 1; j < d; ++j) U[(size_t)i * d + j] = NAN;
    ref_factor(R, d);
    wc_amg_dense_factor(U, d, vec);
    int same = 1;
    for (int i = 0; i < d; ++i)
        for (int k = 0; k <= i; ++k)
            if (memcmp(&R[(size_t)i * d + k], &U[(size_t)k * d + i], sizeof(double)) != 0) same = 0;
    for (int i = 0; i < d; ++i) r[i] = urand();
    ref_solve(R, d, r, y, x0);
    wc_amg_dense_solve(U, d, r, y, x1, vec);
    if (memcmp(x0, x1, d * sizeof(double)) != 0) same = 0;
    /* L L^T against A, and A x against r, relative to the largest entry */
    double worst = 0, scale = 0, res = 0, rs = 0;
    for (int i = 0; i < d; ++i) {
        double ax = 0;
        for (int j = 0; j < d; ++j) {
            double aij = i >= j ? A[(size_t)i * d + j] : A[(size_t)j * d + i], s = 0;
            for (int k = 0; k <= (i < j ? i : j); ++k) s += U[(size_t)k * d + i] * U[(size_t)k * d + j];
            worst = fmax(worst, fabs(s - aij));
            scale = fmax(scale, fabs(aij));
            ax += aij * x1[j];
        }
        res = fmax(res, fabs(ax - r[i]));
        rs = fmax(rs, fabs(r[i]));
    }
    *llt_err = worst / scale;
    *solve_err = res / rs;
    free(R);
    free(U);
    free(r);
    free(y);
    free(x0);
    free(x1);
    return same;
}

/* A = B B^T + shift I with B d x m; m < d and shift 0: semi-definite (decoupled pivots) */
static double* random_matrix(int d, int m, double shift) {
    double* B = malloc((size_t)d * m * sizeof(double));
    double* A = malloc((size_t)d * d * sizeof(double));
    for (size_t k = 0; k < (size_t)d * m; ++k) B[k] = urand();
    for (int i = 0; i < d; ++i)
        for (int j = 0; j < d; ++j) {
            double s = i == j ? shift : 0.0;
            for (int k = 0; k < m; ++k) s += B[(size_t)i * m + k] * B[(size_t)j * m + k];
            A[(size_t)i * d + j] = s;
        }
    free(B);
    return A;
}

static void test_random(void) {
    static const int sizes[] = {1, 2, 3, 15, 16, 17, 31, 33, 48, 100, 216};
    const int paths = wc_amg_dense_vec() ? 2 : 1;
    if (paths == 1) printf("  (no AVX on this CPU: the scalar path only)\n");
    for (size_t s = 0; s < sizeof sizes / sizeof *sizes; ++s) {
        int d = sizes[s];
        double* A = random_matrix(d, d, 0.5);
        for (int vec = 0; vec < paths; ++vec) {
            double e1, e2;
            CHECK(compare(A, d, vec, &e1, &e2));
            CHECK(e1 < 1e-12 && e2 < 1e-9);
            if (d == 216) printf("  SPD d = %d, %s: identical bits, |LL^T - A| %.1e, |Ax - r| %.1e\n", d, vec ? "AVX" : "scalar", e1, e2);
        }
        free(A);
    }
    /* semi-definite: rank d/2, and a zero row and column; the dependent unknowns are decoupled */
    for (int d = 20; d <= 70; d += 50) {
        double* A = random_matrix(d, d / 2, 0.0);
        for (int j = 0; j < d; ++j) A[(size_t)3 * d + j] = A[(size_t)j * d + 3] = 0.0;
        for (int vec = 0; vec < paths; ++vec) {
            double e1, e2;
            CHECK(compare(A, d, vec, &e1, &e2));
            printf("  semi-definite d = %d, %s: identical bits\n", d, vec ? "AVX" : "scalar");
        }
        free(A);
    }
}

/* The real coarsest operator of a hanging 16 x 16 sheet: the setup's factor is the reference's. */
static void test_sheet(void) {
    scene sc;
    if (!make_scene(&sc, 16, 1.0, HANG, 5)) {
        CHECK(0);
        return;
    }
    wc_state* s = sc.s;
    wc_solver* sv = amg_solver(&sc.m, 1e-8, NULL);
    CHECK(sv != NULL);
    if (!sv) return;
    wc_amg* a = sv->amg;
    wc_amg_setup(a, s->A, &s->filter, &s->par);
    CHECK(a->coarse_dense);
    const wc_amg_level* C = &a->lev[a->n_levels - 1];
    const int d = a->coarse_dofs;
    CHECK(d == 3 * C->n && d >= 48);
    double* A = calloc((size_t)d * d, sizeof(double));
    for (int i = 0; i < C->n; ++i)
        for (int k = C->row_start[i]; k < C->row_start[i + 1]; ++k)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) A[(size_t)(3 * i + r) * d + 3 * C->col[k] + c] = C->val[9 * (size_t)k + 3 * r + c];
    double* R = malloc((size_t)d * d * sizeof(double));
    memcpy(R, A, (size_t)d * d * sizeof(double));
    ref_factor(R, d);
    int same = 1;
    for (int i = 0; i < d; ++i)
        for (int k = 0; k <= i; ++k)
            if (memcmp(&R[(size_t)i * d + k], &a->coarse_L[(size_t)k * d + i], sizeof(double)) != 0) same = 0;
    CHECK(same);
    for (int vec = 0; vec < (wc_amg_dense_vec() ? 2 : 1); ++vec) {
        double e1, e2;
        CHECK(compare(A, d, vec, &e1, &e2));
        CHECK(e1 < 1e-12);
    }
    printf("  16 x 16 sheet: %d levels, coarsest %d nodes (%d unknowns): the setup's factor is the reference's, bit for bit\n",
           a->n_levels, C->n, d);
    free(A);
    free(R);
    wc_solver_destroy(sv);
    free_scene(&sc);
}

int main(void) {
    RUN_TEST(test_random);
    RUN_TEST(test_sheet);
    return TEST_SUMMARY();
}
