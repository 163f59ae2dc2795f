/* PCG's block IC(0) preconditioner (core/precond_ic.c) on real filtered cloth systems: the factor
 * reproduces P on its pattern (what IC(0) means), its application inverts the factor, PCG with it
 * converges to CHOLMOD's answer (hanging, draped with contacts, line pins) in fewer iterations than
 * block Jacobi, the breakdown rule shifts an indefinite-ish system and falls back on a broken one,
 * the bits do not depend on the thread count or on the factor's AVX kernels, and solves allocate
 * nothing. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "amg_scene.h"
#include "precond_ic.h"
#include "vec3.h"

static wc_solver* ic_solver(const wc_model* m, double tol, const wc_allocator* alloc) {
    wc_solver* sv = pcg_solver(m, WC_PRECOND_IC0, tol, 1000, alloc);
    CHECK(sv && sv->ic);
    return sv;
}

/* y = M x with M = (D + L) D^{-1} (D + L^T) multiplied out from the factor's blocks. */
static void factor_mul(const wcs_ic* ic, const double* x, double* y, double* tmp) {
    const wc_bsr_pattern* p = ic->p;
    for (int i = 0; i < p->n_rows; ++i) { /* tmp = D^{-1} (D + L^T) x */
        double s[3] = {0, 0, 0};
        for (int b = p->diag[i]; b < p->row_start[i + 1]; ++b) m3_mulv_add(s, ic->F + 9 * b, x + 3 * p->col[b]);
        m3_mulv(tmp + 3 * i, ic->Dinv + 9 * i, s);
    }
    for (int i = 0; i < p->n_rows; ++i) { /* y = (D + L) tmp */
        double s[3] = {0, 0, 0};
        for (int b = p->row_start[i]; b <= p->diag[i]; ++b) m3_mulv_add(s, ic->F + 9 * b, tmp + 3 * p->col[b]);
        v3_copy(y + 3 * i, s);
    }
}

/* IC(0): M_ij = P_ij on every block (i, j) of the pattern, and apply(M x) = x. */
static void test_factor_matches_pattern(void) {
    scene sc;
    if (!make_scene(&sc, 8, 1.0, DRAPE, 12)) return;
    const wc_model* m = &sc.m;
    const wc_bsr_pattern* p = &m->pattern;
    wc_state* s = sc.s;
    int n = m->n_particles, n3 = 3 * n, constrained = 0;
    for (int i = 0; i < n; ++i) constrained += s->filter.ndof[i] != 0;
    CHECK(constrained > 2); /* pins or contacts in the filter */
    wcs_ic* ic = NULL;
    CHECK(wcs_ic_create(&ic, p, NULL) == WC_OK);
    CHECK(wcs_ic_setup(ic, s->A, &s->filter) == 0.0);
    double *x = calloc(n3, sizeof *x), *y = calloc(n3, sizeof *y), *tmp = calloc(n3, sizeof *tmp);
    double worst = 0, scale = 0, worst_off = 0;
    for (int b = 0; b < p->n_blocks; ++b)
        for (int k = 0; k < 9; ++k) scale = fmax(scale, fabs(s->A[9 * b + k]));
    for (int j = 0; j < n; ++j)
        for (int c = 0; c < 3; ++c) { /* column (j, c) of M against P's */
            memset(x, 0, sizeof(double) * n3);
            x[3 * j + c] = 1.0;
            factor_mul(ic, x, y, tmp);
            for (int bj = p->row_start[j]; bj < p->row_start[j + 1]; ++bj) {
                int i = p->col[bj], bij = p->transpose[bj];
                double P[9];
                wcs_project_block(&s->filter, i, j, s->A + 9 * bij, P);
                for (int r = 0; r < 3; ++r) worst = fmax(worst, fabs(y[3 * i + r] - P[3 * r + c]));
            }
            /* off the pattern M has fill: IC(0) is not the exact factor on a 2D sheet */
            for (int i = 0; i < n; ++i) worst_off = fmax(worst_off, fabs(y[3 * i]) + fabs(y[3 * i + 1]) + fabs(y[3 * i + 2]));
            wcs_ic_apply_scalar(ic, y, tmp); /* the scalar sweeps: the same to rounding */
            wcs_ic_apply(ic, y, y); /* M^{-1} M x = x, in place */
            for (int k = 0; k < n3; ++k) worst = fmax(worst, fabs(y[k] - tmp[k]) * scale);
            for (int k = 0; k < n3; ++k) worst = fmax(worst, fabs(y[k] - x[k]) * scale);
        }
    printf("  8^2 drape: max |M - P| on the pattern %.1e (|A| %.1e)\n", worst, scale);
    CHECK(worst < 1e-10 * scale);
    CHECK(worst_off > 0.0);
    free(x);
    free(y);
    free(tmp);
    wcs_ic_destroy(ic, NULL);
    free_scene(&sc);
}

/* PCG + IC(0) to 1e-8 against CHOLMOD; to 1e-4 in fewer than a third of block Jacobi's iterations. */
static void check_solve(int n, int kind, double k_scale, const char* what) {
    scene sc;
    if (!make_scene(&sc, n, k_scale, kind, 10)) return;
    wc_state* s = sc.s;
    int n3 = 3 * sc.m.n_particles;
    wc_solver* sv = ic_solver(&sc.m, 1e-8, NULL);
    double *ref = calloc(n3, sizeof *ref), *dv = calloc(n3, sizeof *dv);
    wc_solve_result res;
    CHECK(wc_solve(sv, WC_SOLVER_DIRECT, s->A, s->b, &s->filter, ref, &s->par, &res) == WC_OK);
    CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res) == WC_OK);
    CHECK(res.converged);
    double shift = sv->ic->shift;
    CHECK(!sv->ic->jacobi && shift >= 0.0 && shift < 0.01); /* the line pins' stiff system needs 1e-3 */
    double err = ts_rel_diff(dv, ref, n3);
    int it_tight = res.iterations;
    sv->opts.tolerance = 1e-4;
    memset(dv, 0, sizeof(double) * n3);
    CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res) == WC_OK);
    CHECK(res.converged);
    int it_ic = res.iterations;
    sv->opts.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    sv->opts.max_iterations = 3000;
    memset(dv, 0, sizeof(double) * n3);
    wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv, &s->par, &res);
    int it_bj = res.iterations;
    printf("  %-26s error vs CHOLMOD %.1e (%d iterations to 1e-8, shift %g); to 1e-4: IC(0) %d, block Jacobi %d\n",
           what, err, it_tight, shift, it_ic, it_bj);
    CHECK(err < 1e-5);
    CHECK(it_ic * 3 < it_bj);
    free(ref);
    free(dv);
    wc_solver_destroy(sv);
    free_scene(&sc);
}

static void test_pcg_matches_direct(void) {
    check_solve(24, HANG, 1.0, "24^2 hanging");
    check_solve(24, DRAPE, 1.0, "24^2 drape (contacts)");
    check_solve(24, LINE, 100.0, "24^2 line pins, k x 100");
}

/* 1 when r . M^{-1} r > 0 for a few random filtered r. */
static int positive(const wcs_ic* ic, const wc_filter* f, int n) {
    double *r = calloc(3 * n, sizeof *r), *t = calloc(3 * n, sizeof *t);
    uint64_t st = 99;
    int ok = 1;
    for (int trial = 0; trial < 4; ++trial) {
        for (int k = 0; k < 3 * n; ++k) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            r[k] = (double)(st >> 11) / 9007199254740992.0 - 0.5;
        }
        for (int i = 0; i < n; ++i) wc_filter_apply(f, i, r + 3 * i, r + 3 * i);
        wcs_ic_apply(ic, r, t);
        double rt = 0;
        for (int k = 0; k < 3 * n; ++k) rt += r[k] * t[k];
        ok &= rt > 0 && isfinite(rt);
    }
    free(r);
    free(t);
    return ok;
}

/* Breakdown: a sheet whose middle particles' diagonal blocks are cut to a twentieth (P
 * indefinite-ish: the unshifted factor meets a pivot that is not SPD) is factored with a shift;
 * a non-finite block leaves only the block-diagonal fallback. Either way M stays SPD. */
static void test_breakdown(void) {
    scene sc;
    if (!make_scene(&sc, 16, 1.0, HANG, 6)) return;
    const wc_model* m = &sc.m;
    const wc_bsr_pattern* p = &m->pattern;
    wc_state* s = sc.s;
    int n = m->n_particles;
    double* A = malloc(sizeof(double) * 9 * p->n_blocks);
    memcpy(A, s->A, sizeof(double) * 9 * p->n_blocks);
    wcs_ic* ic = NULL;
    CHECK(wcs_ic_create(&ic, p, NULL) == WC_OK);
    CHECK(wcs_ic_factor(ic, A, &s->filter, 0.0));
    for (int i = n / 2 - 8; i < n / 2 + 8; ++i)
        for (int k = 0; k < 9; ++k) A[9 * p->diag[i] + k] *= 0.05;
    CHECK(!wcs_ic_factor(ic, A, &s->filter, 0.0));
    double shift = wcs_ic_setup(ic, A, &s->filter);
    printf("  16^2 sheet, 16 diagonal blocks x 0.05: shift %g\n", shift);
    CHECK(shift > 0.0 && !ic->jacobi);
    CHECK_EQ_INT((int)ic->shifted, 1);
    CHECK(positive(ic, &s->filter, n));
    A[9 * p->diag[n / 2] + 4] = NAN;
    CHECK(wcs_ic_setup(ic, A, &s->filter) < 0.0);
    CHECK(ic->jacobi);
    CHECK_EQ_INT((int)ic->fallbacks, 1);
    CHECK(positive(ic, &s->filter, n));
    /* back on the healthy matrix: no shift, no fallback */
    CHECK(wcs_ic_setup(ic, s->A, &s->filter) == 0.0 && !ic->jacobi);
    free(A);
    wcs_ic_destroy(ic, NULL);
    free_scene(&sc);
}

/* The factor with AVX's 3x3 products (wcs_ic_factor, where the CPU has AVX) and with the scalar
 * ones: the same bits, in F and D^{-1}, on a hanging sheet, a drape with contacts and a shifted
 * factor. */
static void test_factor_avx_bits(void) {
    const int kinds[3] = {HANG, DRAPE, DRAPE};
    const double alphas[3] = {0.0, 0.0, 1e-3};
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    printf("  AVX on this CPU: %d\n", __builtin_cpu_supports("avx") ? 1 : 0);
#endif
    for (int t = 0; t < 3; ++t) {
        scene sc;
        if (!make_scene(&sc, 12, 1.0, kinds[t], 8)) return;
        const wc_bsr_pattern* p = &sc.m.pattern;
        wcs_ic *a = NULL, *b = NULL;
        CHECK(wcs_ic_create(&a, p, NULL) == WC_OK && wcs_ic_create(&b, p, NULL) == WC_OK);
        CHECK(wcs_ic_factor(a, sc.s->A, &sc.s->filter, alphas[t]));
        CHECK(wcs_ic_factor_scalar(b, sc.s->A, &sc.s->filter, alphas[t]));
        CHECK(memcmp(a->F, b->F, sizeof(double) * 9 * p->n_blocks) == 0);
        CHECK(memcmp(a->Dinv, b->Dinv, sizeof(double) * 9 * p->n_rows) == 0);
        wcs_ic_destroy(a, NULL);
        wcs_ic_destroy(b, NULL);
        free_scene(&sc);
    }
}

/* The AVX2 sweeps' operations in plain C (fma() is the fused instruction's exact rounding): per
 * row, each block row's lanes multiply-added, lane 3 the next row's first entry (or zero) times
 * zero, the lanes summed (l0 + l1) + (l2 + l3), then r - sum (forward) and m3_mulv's order. */
static void ref_sum(const wcs_ic* ic, int k0, int k1, const double* x, double* s) {
    double a[3][4] = {{0}};
    for (int k = k0; k < k1; ++k) {
        const double* B = ic->F + 9 * (size_t)k;
        const double* v = x + 3 * (size_t)ic->p->col[k];
        for (int r = 0; r < 3; ++r) {
            for (int j = 0; j < 3; ++j) a[r][j] = fma(B[3 * r + j], v[j], a[r][j]);
            a[r][3] = fma(r < 2 ? B[3 * r + 3] : 0.0, 0.0, a[r][3]);
        }
    }
    for (int r = 0; r < 3; ++r) s[r] = (a[r][0] + a[r][1]) + (a[r][2] + a[r][3]);
}

static void ref_apply(const wcs_ic* ic, const double* r, double* t) {
    const wc_bsr_pattern* p = ic->p;
    for (int i = 0; i < p->n_rows; ++i) {
        double s[3], v[3];
        ref_sum(ic, p->row_start[i], p->diag[i], t, s);
        for (int c = 0; c < 3; ++c) v[c] = r[3 * i + c] + -1.0 * s[c];
        m3_mulv(t + 3 * (size_t)i, ic->Dinv + 9 * (size_t)i, v);
    }
    for (int i = p->n_rows - 1; i >= 0; --i) {
        double s[3], d[3];
        ref_sum(ic, p->diag[i] + 1, p->row_start[i + 1], t, s);
        m3_mulv(d, ic->Dinv + 9 * (size_t)i, s);
        v3_sub(t + 3 * (size_t)i, t + 3 * (size_t)i, d);
    }
}

/* wcs_ic_apply (the AVX2 sweeps where the CPU has AVX2 and FMA) gives the reference's bits, in
 * place and not, on a hanging sheet, a drape with contacts and a shifted factor; without AVX2 it
 * is the scalar sweeps. */
static void test_apply_avx2_bits(void) {
    const int kinds[3] = {HANG, DRAPE, DRAPE};
    const double alphas[3] = {0.0, 0.0, 1e-3};
    int avx2 = 0;
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    printf("  AVX2 and FMA on this CPU: %d\n", avx2);
#endif
    for (int t = 0; t < 3; ++t) {
        scene sc;
        if (!make_scene(&sc, 12, 1.0, kinds[t], 8)) return;
        const wc_bsr_pattern* p = &sc.m.pattern;
        const int n3 = 3 * p->n_rows;
        wcs_ic* ic = NULL;
        CHECK(wcs_ic_create(&ic, p, NULL) == WC_OK);
        CHECK(wcs_ic_factor(ic, sc.s->A, &sc.s->filter, alphas[t]));
        double *r = malloc(sizeof(double) * n3), *a = malloc(sizeof(double) * n3), *b = malloc(sizeof(double) * n3);
        uint64_t seed = 12345u + (uint64_t)t;
        for (int k = 0; k < n3; ++k) {
            seed = seed * 6364136223846793005u + 1442695040888963407u;
            r[k] = (double)(seed >> 11) / 9007199254740992.0 - 0.5;
        }
        if (avx2) ref_apply(ic, r, b);
        else wcs_ic_apply_scalar(ic, r, b);
        wcs_ic_apply(ic, r, a);
        CHECK(memcmp(a, b, sizeof(double) * n3) == 0);
        memcpy(a, r, sizeof(double) * n3);
        wcs_ic_apply(ic, a, a); /* in place */
        CHECK(memcmp(a, b, sizeof(double) * n3) == 0);
        free(r);
        free(a);
        free(b);
        wcs_ic_destroy(ic, NULL);
        free_scene(&sc);
    }
}

/* The same bits on 1 and 2 threads; nothing allocated by solves (everything at create). */
static void test_threads_and_allocation(void) {
    scene sc;
    if (!make_scene(&sc, 20, 1.0, DRAPE, 10)) return;
    wc_state* s = sc.s;
    int n3 = 3 * sc.m.n_particles;
    counter c = {0, 0};
    wc_allocator a = {count_alloc, count_free, &c};
    wc_solver* sv = ic_solver(&sc.m, 1e-6, &a);
    long after_create = c.allocs;
    double *dv1 = calloc(n3, sizeof *dv1), *dv2 = calloc(n3, sizeof *dv2);
    wc_par p1, p2;
    wc_par_init(&p1, 1);
    wc_par_init(&p2, 2);
    wc_solve_result r1, r2;
    CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv1, &p1, &r1) == WC_OK);
    CHECK(wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv2, &p2, &r2) == WC_OK);
    CHECK(r1.converged && r1.iterations == r2.iterations);
    CHECK(memcmp(dv1, dv2, sizeof(double) * n3) == 0);
    for (int k = 0; k < 3; ++k) wc_solve(sv, WC_SOLVER_PCG, s->A, s->b, &s->filter, dv1, &p2, &r1);
    CHECK_EQ_INT((int)c.allocs, (int)after_create);
    wc_solver_destroy(sv);
    CHECK_EQ_INT((int)c.frees, (int)c.allocs);
    free(dv1);
    free(dv2);
    free_scene(&sc);
}

int main(void) {
    CHECK_EQ_INT(wc_precond_from_name("ic0"), WC_PRECOND_IC0);
    RUN_TEST(test_factor_matches_pattern);
    RUN_TEST(test_pcg_matches_direct);
    RUN_TEST(test_breakdown);
    RUN_TEST(test_factor_avx_bits);
    RUN_TEST(test_apply_avx2_bits);
    RUN_TEST(test_threads_and_allocation);
    return TEST_SUMMARY();
}
