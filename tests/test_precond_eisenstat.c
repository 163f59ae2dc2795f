/* D-ILU with Eisenstat's trick (core/precond_eisenstat.c) against dense algebra built here from the
 * filtered matrix: D~ by its recurrence (D-ILU) or P's diagonal (block Gauss-Seidel), M = (D~ + L) D~^{-1}
 * (D~ + L^T) applied by the sweeps inverts M formed densely, and the trick's product P^ x equals
 * E^{-1} P E^{-T} x with E = (D~ + L) C^{-T} (C C^T = D~) formed densely; then PCG through it
 * (wc_solver_opts.ic_eisenstat) against CHOLMOD on hanging, draped (contacts) and line-pinned
 * sheets, its breakdown rule, the same bits on 1 and 2 threads, no allocation in a solve. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "amg_scene.h"
#include "precond_eisenstat.h"
#include "vec3.h"

/* Dense (n3 x n3, row-major) P and the D~ of the mode, from the projected blocks. */
static void dense_system(const wc_bsr_pattern* p, const double* A, const wc_filter* f, int mode, double* P,
                         double* D) {
    const int n = p->n_rows, n3 = 3 * n;
    memset(P, 0, sizeof(double) * (size_t)n3 * n3);
    for (int i = 0; i < n; ++i)
        for (int b = p->row_start[i]; b < p->row_start[i + 1]; ++b) {
            double B[9];
            wcs_project_block(f, i, p->col[b], A + 9 * b, B);
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) P[(size_t)(3 * i + r) * n3 + 3 * p->col[b] + c] = B[3 * r + c];
        }
    for (int i = 0; i < n; ++i) {
        double* Di = D + 9 * i;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) Di[3 * r + c] = P[(size_t)(3 * i + r) * n3 + 3 * i + c];
        if (mode == 1) continue;
        for (int k = 0; k < i; ++k) {
            double Pik[9], Pki[9], W[9], Dk[9] = {0}, G[9], H[9];
            int nz = 0;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) {
                    Pik[3 * r + c] = P[(size_t)(3 * i + r) * n3 + 3 * k + c];
                    Pki[3 * r + c] = P[(size_t)(3 * k + r) * n3 + 3 * i + c];
                    nz |= Pik[3 * r + c] != 0.0;
                }
            if (!nz) continue;
            memcpy(W, Pki, sizeof W);
            CHECK(m3_inverse(Dk, D + 9 * k) != 0.0);
            m3_mul(G, Pik, Dk);
            m3_mul(H, G, W);
            for (int q = 0; q < 9; ++q) Di[q] -= H[q];
        }
        for (int q = 0; q < 3; ++q) /* symmetric, as the factor keeps it */
            for (int c = q + 1; c < 3; ++c) Di[3 * q + c] = Di[3 * c + q] = 0.5 * (Di[3 * q + c] + Di[3 * c + q]);
    }
}

/* x = G^{-1} x by Gaussian elimination with partial pivoting (G n x n, destroyed). */
static void dense_solve(double* G, double* x, int n) {
    for (int k = 0; k < n; ++k) {
        int piv = k;
        for (int i = k + 1; i < n; ++i)
            if (fabs(G[(size_t)i * n + k]) > fabs(G[(size_t)piv * n + k])) piv = i;
        for (int j = 0; j < n; ++j) {
            double t = G[(size_t)k * n + j];
            G[(size_t)k * n + j] = G[(size_t)piv * n + j];
            G[(size_t)piv * n + j] = t;
        }
        double t = x[k];
        x[k] = x[piv];
        x[piv] = t;
        for (int i = k + 1; i < n; ++i) {
            double l = G[(size_t)i * n + k] / G[(size_t)k * n + k];
            for (int j = k; j < n; ++j) G[(size_t)i * n + j] -= l * G[(size_t)k * n + j];
            x[i] -= l * x[k];
        }
    }
    for (int k = n - 1; k >= 0; --k) {
        double s = x[k];
        for (int j = k + 1; j < n; ++j) s -= G[(size_t)k * n + j] * x[j];
        x[k] = s / G[(size_t)k * n + k];
    }
}

/* Lower C with C C^T = D (3x3). */
static void chol3(const double* D, double* C) {
    memset(C, 0, 9 * sizeof(double));
    C[0] = sqrt(D[0]);
    C[3] = D[3] / C[0];
    C[6] = D[6] / C[0];
    C[4] = sqrt(D[4] - C[3] * C[3]);
    C[7] = (D[7] - C[6] * C[3]) / C[4];
    C[8] = sqrt(D[8] - C[6] * C[6] - C[7] * C[7]);
}

static double frand(uint64_t* st) {
    *st = *st * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*st >> 11) / 9007199254740992.0 - 0.5;
}

/* For each mode: D~ as set up equals the dense recurrence's (through the sweeps: apply(M x) = x
 * with M formed densely), and P^ x = E^{-1} P E^{-T} x. */
static void test_dense_formula(void) {
    scene sc;
    if (!make_scene(&sc, 6, 1.0, DRAPE, 12)) return;
    const wc_bsr_pattern* p = &sc.m.pattern;
    wc_state* s = sc.s;
    const int n = sc.m.n_particles, n3 = 3 * n;
    int constrained = 0;
    for (int i = 0; i < n; ++i) constrained += s->filter.ndof[i] != 0;
    CHECK(constrained > 2);
    double* P = malloc(sizeof(double) * n3 * n3);
    double* M = malloc(sizeof(double) * n3 * n3);
    double* E = malloc(sizeof(double) * n3 * n3);
    double* G = malloc(sizeof(double) * n3 * n3);
    double *D = malloc(sizeof(double) * 9 * n), *x = malloc(sizeof(double) * n3), *y = malloc(sizeof(double) * n3);
    double *w = malloc(sizeof(double) * n3), *t = malloc(sizeof(double) * n3), *z = malloc(sizeof(double) * n3);
    wcs_eis* e = NULL;
    CHECK(wcs_eis_create(&e, p, NULL) == WC_OK);
    uint64_t st = 7;
    for (int mode = 0; mode < 2; ++mode) {
        e->mode = mode;
        CHECK(wcs_eis_setup(e, s->A, &s->filter));
        CHECK(!e->gs);
        dense_system(p, s->A, &s->filter, mode, P, D);
        /* M = (D~ + L) D~^{-1} (D~ + L^T), E = (D~ + L) C^{-T} */
        memset(M, 0, sizeof(double) * n3 * n3);
        memset(E, 0, sizeof(double) * n3 * n3);
        double scale = 0.0;
        for (int k = 0; k < n3 * n3; ++k) scale = fmax(scale, fabs(P[k]));
        for (int i = 0; i < n; ++i) { /* (D~ + L) block row i times D~_i... built column block by block */
            for (int j = 0; j <= i; ++j) {
                double B[9], Dj[9], C[9], Ct[9], Cti[9] = {0}, BE[9];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c)
                        B[3 * r + c] = i == j ? D[9 * i + 3 * r + c] : P[(size_t)(3 * i + r) * n3 + 3 * j + c];
                memcpy(Dj, D + 9 * j, sizeof Dj);
                chol3(Dj, C);
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) Ct[3 * r + c] = C[3 * c + r];
                CHECK(m3_inverse(Cti, Ct) != 0.0);
                m3_mul(BE, B, Cti);
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) E[(size_t)(3 * i + r) * n3 + 3 * j + c] = BE[3 * r + c];
            }
        }
        for (int r = 0; r < n3; ++r) /* M = E E^T */
            for (int c = 0; c < n3; ++c) {
                double a = 0.0;
                for (int k = 0; k < n3; ++k) a += E[(size_t)r * n3 + k] * E[(size_t)c * n3 + k];
                M[(size_t)r * n3 + c] = a;
            }
        double worst_apply = 0.0, worst_prod = 0.0, norm = 0.0;
        for (int trial = 0; trial < 3; ++trial) {
            for (int k = 0; k < n3; ++k) x[k] = frand(&st);
            for (int r = 0; r < n3; ++r) { /* y = M x; apply(y) = x */
                double a = 0.0;
                for (int k = 0; k < n3; ++k) a += M[(size_t)r * n3 + k] * x[k];
                y[r] = a;
            }
            wcs_eis_apply(e, y, w, t);
            for (int k = 0; k < n3; ++k) worst_apply = fmax(worst_apply, fabs(t[k] - x[k]));
            /* z = E^{-T} x, y = P z, then E w = y with w the product */
            for (int r = 0; r < n3; ++r)
                for (int c = 0; c < n3; ++c) G[(size_t)r * n3 + c] = E[(size_t)c * n3 + r];
            memcpy(z, x, sizeof(double) * n3);
            dense_solve(G, z, n3);
            for (int r = 0; r < n3; ++r) {
                double a = 0.0;
                for (int k = 0; k < n3; ++k) a += P[(size_t)r * n3 + k] * z[k];
                y[r] = a;
            }
            memcpy(G, E, sizeof(double) * n3 * n3);
            dense_solve(G, y, n3);
            const double xo = wcs_eis_product(e, x, t, w);
            double xy = 0.0;
            for (int k = 0; k < n3; ++k) {
                worst_prod = fmax(worst_prod, fabs(w[k] - y[k]));
                norm = fmax(norm, fabs(y[k]));
                xy += x[k] * y[k];
            }
            CHECK(fabs(xo - xy) <= 1e-9 * fabs(xy));
            wcs_eis_product_scalar(e, x, t, z); /* the scalar rows: the same to rounding */
            for (int k = 0; k < n3; ++k) CHECK(fabs(z[k] - w[k]) <= 1e-12 * norm);
        }
        printf("  6^2 drape, mode %d: |apply(M x) - x| %.1e, |P^ x - E^-1 P E^-T x| %.1e (|P^ x| %.1e, |P| %.1e)\n",
               mode, worst_apply, worst_prod, norm, scale);
        CHECK(worst_apply < 1e-9);
        CHECK(worst_prod < 1e-10 * norm);
    }
    wcs_eis_destroy(e, NULL);
    free(P), free(M), free(E), free(G), free(D), free(x), free(y), free(w), free(t), free(z);
    free_scene(&sc);
}

/* PCG through the trick to 1e-8 against CHOLMOD, for each mode; the iterations to 1e-4 beside
 * IC(0)'s. */
static void check_solve(int n, int kind, double k_scale, const char* what) {
    scene sc;
    if (!make_scene(&sc, n, k_scale, kind, 10)) return;
    wc_state* s = sc.s;
    const int n3 = 3 * sc.m.n_particles;
    double *ref = calloc(n3, sizeof *ref), *dv = calloc(n3, sizeof *dv);
    wc_solve_result res;
    wc_solver* ic = pcg_solver(&sc.m, WC_PRECOND_IC0, 1e-4, 1000, NULL);
    CHECK(wc_solve(ic, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, ref, &s->par, &res) == WC_OK);
    CHECK(wc_solve(ic, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res) == WC_OK);
    printf("  %-24s IC(0) %d it. to 1e-4;", what, res.iterations);
    wc_solver_destroy(ic);
    for (int mode = 1; mode <= 2; ++mode) {
        wc_solver_opts o = wc_default_solver_opts();
        o.preconditioner = WC_PRECOND_IC0;
        o.ic_eisenstat = mode;
        o.tolerance = 1e-8;
        o.max_iterations = 2000;
        wc_solver* sv = NULL;
        wc_diag d = {0};
        CHECK(wc_solver_create(&sv, &sc.m, &o, 0, NULL, &d) == WC_OK && sv->eis);
        memset(dv, 0, sizeof(double) * n3);
        CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res) == WC_OK);
        CHECK(res.converged && res.residual <= 1e-8);
        const long setups = sv->eis->setups, checks = sv->eis->checks;
        CHECK(setups == 1 && checks >= 1); /* the trick ran (no IC(0) fallback) */
        const double err = ts_rel_diff(dv, ref, n3);
        CHECK(err < 1e-5);
        sv->opts.tolerance = 1e-4;
        memset(dv, 0, sizeof(double) * n3);
        CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res) == WC_OK);
        CHECK(res.converged && res.residual <= 1e-4);
        printf(" %s %d (err %.0e)", mode == 1 ? "D-ILU" : "SGS", res.iterations, err);
        wc_solver_destroy(sv);
    }
    printf("\n");
    free(ref);
    free(dv);
    free_scene(&sc);
}

static void test_pcg_matches_direct(void) {
    check_solve(24, HANG, 1.0, "24^2 hanging");
    check_solve(24, DRAPE, 1.0, "24^2 drape (contacts)");
    check_solve(24, LINE, 100.0, "24^2 line pins, k x 100");
}

/* A non-finite diagonal: no D~ (setup 0); PCG then runs IC(0) (its own fallback) and returns. */
static void test_breakdown(void) {
    scene sc;
    if (!make_scene(&sc, 12, 1.0, HANG, 6)) return;
    const wc_bsr_pattern* p = &sc.m.pattern;
    wc_state* s = sc.s;
    double* A = malloc(sizeof(double) * 9 * p->n_blocks);
    memcpy(A, s->A, sizeof(double) * 9 * p->n_blocks);
    wcs_eis* e = NULL;
    CHECK(wcs_eis_create(&e, p, NULL) == WC_OK);
    CHECK(wcs_eis_setup(e, A, &s->filter));
    A[9 * p->diag[sc.m.n_particles / 2] + 4] = NAN;
    CHECK(!wcs_eis_setup(e, A, &s->filter));
    CHECK(wcs_eis_setup(e, s->A, &s->filter) && !e->gs);
    wcs_eis_destroy(e, NULL);
    free(A);
    free_scene(&sc);
}

/* The same bits on 1 and 2 threads; nothing allocated by solves. */
static void test_threads_and_allocation(void) {
    scene sc;
    if (!make_scene(&sc, 20, 1.0, DRAPE, 10)) return;
    wc_state* s = sc.s;
    const int n3 = 3 * sc.m.n_particles;
    counter c = {0, 0};
    wc_allocator a = {count_alloc, count_free, &c};
    wc_solver_opts o = wc_default_solver_opts();
    o.preconditioner = WC_PRECOND_IC0;
    o.ic_eisenstat = 1;
    o.tolerance = 1e-6;
    wc_solver* sv = NULL;
    wc_diag d = {0};
    CHECK(wc_solver_create(&sv, &sc.m, &o, 0, &a, &d) == WC_OK);
    const long after_create = c.allocs;
    double *dv1 = calloc(n3, sizeof *dv1), *dv2 = calloc(n3, sizeof *dv2);
    wc_par p1, p2;
    wc_par_init(&p1, 1);
    wc_par_init(&p2, 2);
    wc_solve_result r1, r2;
    CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv1, &p1, &r1) == WC_OK);
    CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv2, &p2, &r2) == WC_OK);
    CHECK(r1.converged && r1.iterations == r2.iterations);
    CHECK(memcmp(dv1, dv2, sizeof(double) * n3) == 0);
    CHECK_EQ_INT((int)c.allocs, (int)after_create);
    wc_solver_destroy(sv);
    CHECK_EQ_INT((int)c.frees, (int)c.allocs);
    free(dv1);
    free(dv2);
    free_scene(&sc);
}

int main(void) {
    RUN_TEST(test_dense_formula);
    RUN_TEST(test_pcg_matches_direct);
    RUN_TEST(test_breakdown);
    RUN_TEST(test_threads_and_allocation);
    return TEST_SUMMARY();
}
