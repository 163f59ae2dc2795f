/* Linear solvers on cloth-like systems built here on real models' patterns:
 * A = M - h dF/dv - h^2 dF/dx of mass-springs in stretched random positions, random b, and a
 * filter with free, pinned, plane-contact and line-constrained particles. The direct solver is
 * checked against a dense Cholesky written here; the iterative ones against the direct one. */
#include <stdint.h>
#include <stdlib.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#include "check.h"
#include "clock.h"
#include "coupling.h"
#include "model.h"
#include "solve.h"
#include "test_support.h"

/* ---- small deterministic random numbers ---- */
typedef struct rng { uint64_t s; } rng;
static double urand(rng* r) {   /* [-1, 1) */
    r->s = r->s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(r->s >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}
static void unit_vec(rng* r, double* u) {
    double l;
    do {
        for (int k = 0; k < 3; ++k) u[k] = urand(r);
        l = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    } while (l < 0.1 || l > 1.0);
    for (int k = 0; k < 3; ++k) u[k] /= l;
}

/* ---- the system ---- */
typedef struct sys {
    int n, nb;
    double* A;      /* (nb x 9) */
    double* b;      /* (n x 3) */
    wc_filter f;
} sys;

static wc_model build_model(const wc_source_mesh* src) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = wc_default_model_def();
    wc_status st = wc_model_build(&m, src, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "build failed: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return m;
}
static wc_model grid_model(int nx, int ny, int tris) {   /* 1 m x 1 m quads or 1 m x 0.8 m triangles */
    wc_source_mesh src;
    if (tris) ts_tri_grid(&src, nx, ny, 1.0, 0.8);
    else ts_quad_grid(&src, nx, ny, 1.0, 1.0, 0);
    wc_model m = build_model(&src);
    wc_source_mesh_free(&src);
    return m;
}
#define quad_model(nx, ny) grid_model(nx, ny, 0)
#define tri_model(nx, ny) grid_model(nx, ny, 1)

static sys sys_alloc(const wc_model* m) {
    sys s;
    s.n = m->n_particles;
    s.nb = m->pattern.n_blocks;
    s.A = calloc((size_t)s.nb * 9, sizeof(double));
    s.b = calloc((size_t)s.n * 3, sizeof(double));
    s.f.n = s.n;
    s.f.S = calloc((size_t)s.n * 9, sizeof(double));
    s.f.z = calloc((size_t)s.n * 3, sizeof(double));
    s.f.ndof = calloc((size_t)s.n, 1);
    for (int i = 0; i < s.n; ++i) wc_filter_free_particle(&s.f, i);
    return s;
}
static void sys_free(sys* s) {
    free(s->A), free(s->b), free(s->f.S), free(s->f.z), free(s->f.ndof);
}

/* A = M - h dF/dv - h^2 dF/dx for the model's springs at positions rest * stretch + noise, with
 * mass scaled by mass_scale; b uniform in [-1, 1). Per spring (unit u along it, length l, rest L):
 * J = dF_a/dx_a = -k (u u^T + max(0, 1 - L/l) (I - u u^T)), Jd = dF_a/dv_a = -d u u^T; the diagonal
 * gets -(h^2 J + h Jd), the block (a, b) +(h^2 J + h Jd). Filled by rows through the pattern. */
static void fill_cloth(const wc_model* m, sys* s, double h, double stretch, double mass_scale, uint64_t seed) {
    rng r = {seed};
    int n = m->n_particles;
    double* x = malloc(sizeof(double) * 3 * (size_t)n);
    for (int i = 0; i < 3 * n; ++i) x[i] = stretch * m->rest_pos[i] + 0.004 * urand(&r);
    for (int i = 0; i < 3 * n; ++i) s->b[i] = urand(&r);
    const wc_bsr_pattern* p = &m->pattern;
    for (int k = 0; k < 9 * s->nb; ++k) s->A[k] = 0.0;
    for (int i = 0; i < n; ++i) {
        double* D = s->A + 9 * p->diag[i];
        D[0] = D[4] = D[8] = m->mass[i] * mass_scale;
        for (int e = p->row_spring_start[i]; e < p->row_spring_start[i + 1]; ++e) {
            const wc_spring* sp = &m->springs[p->row_spring[e]];
            double u[3], l = 0.0;
            for (int k = 0; k < 3; ++k) {
                u[k] = x[3 * sp->b + k] - x[3 * sp->a + k];
                l += u[k] * u[k];
            }
            l = sqrt(l);
            for (int k = 0; k < 3; ++k) u[k] /= l;
            double ks = m->material.k[sp->type], ds = m->material.d[sp->type];
            double geo = 1.0 - sp->rest / l;
            if (geo < 0.0) geo = 0.0;
            double* O = s->A + 9 * p->row_spring_block[e];
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c) {
                    double uu = u[a] * u[c];
                    double J = -ks * (uu + geo * ((a == c) - uu)), Jd = -ds * uu;
                    D[3 * a + c] -= h * h * J + h * Jd;
                    O[3 * a + c] += h * h * J + h * Jd;
                }
        }
    }
    free(x);
}

/* Pin particles pin[0..np), plane contacts on nc particles after them, a line constraint on one. */
static void set_filter(sys* s, const int* pin, int np, const int* contact, int nc, int line, uint64_t seed) {
    rng r = {seed};
    wc_filter* f = &s->f;
    for (int k = 0; k < np; ++k) {
        int i = pin[k];
        for (int q = 0; q < 9; ++q) f->S[9 * i + q] = 0.0;
        for (int q = 0; q < 3; ++q) f->z[3 * i + q] = 0.5 * urand(&r);
        f->ndof[i] = 3;
    }
    for (int k = 0; k < nc; ++k) {
        int i = contact[k];
        double nrm[3], alpha = 0.3 * urand(&r);
        unit_vec(&r, nrm);
        for (int a = 0; a < 3; ++a) {
            for (int c = 0; c < 3; ++c) f->S[9 * i + 3 * a + c] = (a == c) - nrm[a] * nrm[c];
            f->z[3 * i + a] = alpha * nrm[a];
        }
        f->ndof[i] = 1;
    }
    if (line >= 0) {
        double d[3], w[3];
        unit_vec(&r, d);
        for (int a = 0; a < 3; ++a) w[a] = 0.2 * urand(&r);
        double wd = w[0] * d[0] + w[1] * d[1] + w[2] * d[2];
        for (int a = 0; a < 3; ++a) {
            for (int c = 0; c < 3; ++c) f->S[9 * line + 3 * a + c] = d[a] * d[c];
            f->z[3 * line + a] = w[a] - wd * d[a];
        }
        f->ndof[line] = 2;
    }
}

/* The standard constraint set on a grid of nx columns: two corners pinned, five contacts, a line. */
static void set_default_filter(sys* s, int nx, uint64_t seed) {
    int n = s->n;
    int pin[2] = {0, nx - 1};
    int contact[5] = {n / 2, n / 3, n - 1, n - 2, n / 2 + nx};
    set_filter(s, pin, 2, contact, 5, n / 4 + 1, seed);
}

/* ---- references computed here, independently of the solvers ---- */

/* S_i v (plain 3x3 product, no shortcut for free particles) */
static void Sv(const wc_filter* f, int i, const double* v, double* o) {
    const double* S = f->S + 9 * i;
    for (int a = 0; a < 3; ++a) o[a] = S[3 * a] * v[0] + S[3 * a + 1] * v[1] + S[3 * a + 2] * v[2];
}
/* ||S (b - A x)||_2 by a direct loop over the pattern */
static double proj_residual(const wc_model* m, const sys* s, const double* x) {
    const wc_bsr_pattern* p = &m->pattern;
    double sum = 0.0;
    for (int i = 0; i < s->n; ++i) {
        double acc[3] = {s->b[3 * i], s->b[3 * i + 1], s->b[3 * i + 2]}, o[3];
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k)
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c) acc[a] -= s->A[9 * k + 3 * a + c] * x[3 * p->col[k] + c];
        Sv(&s->f, i, acc, o);
        sum += o[0] * o[0] + o[1] * o[1] + o[2] * o[2];
    }
    return sqrt(sum);
}
/* Dense P = S A S + I - S, rhs S (b - A z), Cholesky, dv = z + S y. Returns 0 when P is not
 * positive definite. */
static int dense_solve(const wc_model* m, const sys* s, double* dv) {
    int n = s->n, N = 3 * n;
    const wc_bsr_pattern* p = &m->pattern;
    double* Ad = calloc((size_t)N * N, sizeof(double));
    double* P = calloc((size_t)N * N, sizeof(double));
    double* rhs = calloc((size_t)N, sizeof(double));
    for (int i = 0; i < n; ++i)
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k)
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c) Ad[(size_t)(3 * i + a) * N + 3 * p->col[k] + c] = s->A[9 * k + 3 * a + c];
    /* S A S: row block i scaled by S_i on the left, column block j by S_j on the right */
    for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) {
            double v = 0.0;
            int bi = i / 3, bj = j / 3;
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c)
                    v += s->f.S[9 * bi + 3 * (i % 3) + a] * Ad[(size_t)(3 * bi + a) * N + 3 * bj + c] *
                         s->f.S[9 * bj + 3 * c + j % 3];
            P[(size_t)i * N + j] = v;
        }
    for (int i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) P[(size_t)(3 * i + a) * N + 3 * i + c] += (a == c) - s->f.S[9 * i + 3 * a + c];
    for (int i = 0; i < n; ++i) {
        double acc[3];
        for (int a = 0; a < 3; ++a) {
            acc[a] = s->b[3 * i + a];
            for (int j = 0; j < N; ++j) acc[a] -= Ad[(size_t)(3 * i + a) * N + j] * s->f.z[j];
        }
        Sv(&s->f, i, acc, rhs + 3 * i);
    }
    int ok = 1;
    for (int j = 0; j < N && ok; ++j) {   /* in-place Cholesky, lower triangle */
        double d = P[(size_t)j * N + j];
        for (int k = 0; k < j; ++k) d -= P[(size_t)j * N + k] * P[(size_t)j * N + k];
        if (!(d > 0.0)) { ok = 0; break; }
        d = sqrt(d);
        P[(size_t)j * N + j] = d;
        for (int i = j + 1; i < N; ++i) {
            double v = P[(size_t)i * N + j];
            for (int k = 0; k < j; ++k) v -= P[(size_t)i * N + k] * P[(size_t)j * N + k];
            P[(size_t)i * N + j] = v / d;
        }
    }
    if (ok) {
        for (int i = 0; i < N; ++i) {
            for (int k = 0; k < i; ++k) rhs[i] -= P[(size_t)i * N + k] * rhs[k];
            rhs[i] /= P[(size_t)i * N + i];
        }
        for (int i = N - 1; i >= 0; --i) {
            for (int k = i + 1; k < N; ++k) rhs[i] -= P[(size_t)k * N + i] * rhs[k];
            rhs[i] /= P[(size_t)i * N + i];
        }
        for (int i = 0; i < n; ++i) {
            Sv(&s->f, i, rhs + 3 * i, dv + 3 * i);
            for (int a = 0; a < 3; ++a) dv[3 * i + a] += s->f.z[3 * i + a];
        }
    }
    free(Ad);
    free(P);
    free(rhs);
    return ok;
}

/* ---- running the solvers ---- */
static wc_solver* make_solver(const wc_model* m, wc_solver_opts o, const wc_allocator* alloc) {
    wc_solver* sv = NULL;
    wc_diag d = {0};
    wc_status st = wc_solver_create(&sv, m, &o, 1, alloc, &d);
    if (st != WC_OK) fprintf(stderr, "solver create: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return sv;
}
static wc_status run(wc_solver* sv, wc_solver_type t, const sys* s, double* dv, int threads, wc_solve_result* res) {
    wc_par par;
    wc_par_init(&par, threads);
    for (int i = 0; i < 3 * s->n; ++i) dv[i] = 0.0;
    return wc_solve(sv, t, s->A, s->b, &s->f, dv, &par, res);
}

static const wc_solver_type all_types[4] = {WC_SOLVER_PCG, WC_SOLVER_JACOBI, WC_SOLVER_CHEBYSHEV, WC_SOLVER_DIRECT};

/* The standard cloth-step system on a model: h = 1/30, springs stretched 5 %, default filter. */
static sys cloth_system(const wc_model* m, int nx, uint64_t seed) {
    sys s = sys_alloc(m);
    fill_cloth(m, &s, 1.0 / 30.0, 1.05, 1.0, seed);
    set_default_filter(&s, nx, seed + 1);
    return s;
}

/* Coupling system: diagonal blocks d I, every off-diagonal block of the pattern w I. */
static void fill_coupled(const wc_model* m, sys* s, double d, double w) {
    const wc_bsr_pattern* p = &m->pattern;
    for (int i = 0; i < s->n; ++i)
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k) {
            double v = p->col[k] == i ? d : w;
            for (int q = 0; q < 9; ++q) s->A[9 * k + q] = (q % 4 == 0) ? v : 0.0;
        }
}

/* |(I - S_i)(dv_i - z_i)| over constrained particles, relative to max(1, |dv_i|); pinned must be
 * bit-exact. */
static void check_constraints(const sys* s, const double* dv) {
    double worst = 0.0;
    int pinned_exact = 1;
    for (int i = 0; i < s->n; ++i) {
        if (s->f.ndof[i] == 0) continue;
        if (s->f.ndof[i] == 3 && memcmp(dv + 3 * i, s->f.z + 3 * i, 3 * sizeof(double)) != 0) pinned_exact = 0;
        double e[3], Se[3], nd = 0.0, ne = 0.0;
        for (int a = 0; a < 3; ++a) e[a] = dv[3 * i + a] - s->f.z[3 * i + a];
        Sv(&s->f, i, e, Se);
        for (int a = 0; a < 3; ++a) {
            ne += (e[a] - Se[a]) * (e[a] - Se[a]);
            nd += dv[3 * i + a] * dv[3 * i + a];
        }
        double rel = sqrt(ne) / fmax(1.0, sqrt(nd));
        if (rel > worst) worst = rel;
    }
    CHECK(pinned_exact);
    CHECK(worst <= 1e-14);
}

/* ---- tests ---- */

static void test_names_and_defaults(void) {
    for (int t = 0; t < WC_SOLVER_COUNT; ++t) CHECK_EQ_INT(wc_solver_from_name(wc_solver_name((wc_solver_type)t)), t);
    CHECK(strcmp(wc_solver_name(WC_SOLVER_CHEBYSHEV), "chebyshev") == 0);
    CHECK_EQ_INT(wc_solver_from_name("gauss-seidel"), -1);
    CHECK_EQ_INT(wc_solver_from_name(NULL), -1);
    wc_solver_opts o = wc_default_solver_opts();
    CHECK_EQ_INT(o.type, WC_SOLVER_PCG);
    CHECK(o.tolerance == 1e-4 && o.max_iterations == 300 && o.check_every == 10 && o.chebyshev_rho == 0.0);
    CHECK(o.chebyshev_gamma == 0.9 && o.chebyshev_delay == 10 && o.divergence_factor == 1e3);
}

/* (1) direct = dense Cholesky of the projected system written here; (2) constraints exact. */
static void check_direct_dense(const wc_model* m, int nx) {
    sys s = cloth_system(m, nx, 3);
    wc_solver* sv = make_solver(m, wc_default_solver_opts(), NULL);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    double* ref = calloc(3 * (size_t)s.n, sizeof(double));
    wc_solve_result res;
    CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, dv, 1, &res), WC_OK);
    CHECK_EQ_INT(res.solver, WC_SOLVER_DIRECT);
    CHECK_EQ_INT(res.iterations, 1);
    CHECK(res.converged);
    double r0 = proj_residual(m, &s, s.f.z);
    CHECK_NEAR(res.residual0 / r0, 1.0, 1e-12);
    CHECK(res.residual <= 1e-10);
    CHECK(proj_residual(m, &s, dv) / r0 <= 1e-10);
    CHECK(dense_solve(m, &s, ref));
    CHECK(ts_rel_diff(dv, ref, 3 * s.n) <= 1e-9);
    check_constraints(&s, dv);
    free(dv);
    free(ref);
    wc_solver_destroy(sv);
    sys_free(&s);
}
static void test_direct_matches_dense(void) {
    wc_model q = quad_model(12, 12), t = tri_model(9, 7);
    check_direct_dense(&q, 12);
    check_direct_dense(&t, 9);
    wc_model_free(&q);
    wc_model_free(&t);
}

/* (2)+(3) Every iterative solver reaches tolerance 1e-8 and the direct solution: the error is
 * bounded by cond(P) x residual, and cond is about 1e2 .. 1e3 here (h^2 k / m ~ 5e3, two pins),
 * so 1e-6 relative leaves a margin of about ten. The reported residual is the true one. */
static void check_iterative(const wc_model* m, int nx) {
    sys s = cloth_system(m, nx, 5);
    wc_solver_opts o = wc_default_solver_opts();
    o.tolerance = 1e-8;
    o.max_iterations = 20000;
    wc_solver* sv = make_solver(m, o, NULL);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    double* ref = calloc(3 * (size_t)s.n, sizeof(double));
    wc_solve_result res;
    CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, ref, 1, &res), WC_OK);
    double r0 = proj_residual(m, &s, s.f.z);
    for (int k = 0; k < 3; ++k) {
        wc_status st = run(sv, all_types[k], &s, dv, 1, &res);
        CHECK_EQ_INT(st, WC_OK);
        CHECK_EQ_INT(res.solver, all_types[k]);
        CHECK(res.converged);
        CHECK(res.iterations > 0 && res.iterations < o.max_iterations);
        CHECK(res.residual <= o.tolerance);
        CHECK_NEAR(proj_residual(m, &s, dv) / r0, res.residual, 1e-3 * o.tolerance);
        double err = ts_rel_diff(dv, ref, 3 * s.n);
        if (!(err <= 1e-6)) fprintf(stderr, "%s: relative error %g\n", wc_solver_name(all_types[k]), err);
        CHECK(err <= 1e-6);
        check_constraints(&s, dv);
    }
    /* a random initial guess (projected by the solver) and the solution itself as one */
    wc_par par;
    wc_par_init(&par, 1);
    rng r = {6};
    for (int i = 0; i < 3 * s.n; ++i) dv[i] = urand(&r);
    CHECK_EQ_INT(wc_solve(sv, WC_SOLVER_PCG, s.A, s.b, &s.f, dv, &par, &res), WC_OK);
    CHECK(res.converged && ts_rel_diff(dv, ref, 3 * s.n) <= 1e-6);
    check_constraints(&s, dv);
    for (int i = 0; i < 3 * s.n; ++i) dv[i] = ref[i];
    CHECK_EQ_INT(wc_solve(sv, WC_SOLVER_PCG, s.A, s.b, &s.f, dv, &par, &res), WC_OK);
    CHECK(res.converged && res.iterations == 0);
    /* Chebyshev with a given rho (no estimate) converges as well */
    wc_solver_destroy(sv);
    o.chebyshev_rho = 0.998;
    sv = make_solver(m, o, NULL);
    CHECK_EQ_INT(run(sv, WC_SOLVER_CHEBYSHEV, &s, dv, 1, &res), WC_OK);
    CHECK(res.converged && res.residual <= o.tolerance);
    CHECK(ts_rel_diff(dv, ref, 3 * s.n) <= 1e-6);
    free(dv);
    free(ref);
    wc_solver_destroy(sv);
    sys_free(&s);
}
/* CHOLMOD's own OpenMP regions run serially (solve_direct.c): the direct solver sets the calling
 * thread's max-active-levels to 0 around each CHOLMOD call and must hand back the host's value,
 * at creation (the analysis) and after each solve, failed ones included. */
static void test_direct_keeps_host_openmp(void) {
#ifdef _OPENMP
    wc_model m = quad_model(12, 12);
    sys s = cloth_system(&m, 12, 5);
    const int host = omp_get_max_active_levels() > 1 ? 1 : 2; /* not the default: a value to keep */
    omp_set_max_active_levels(host);
    wc_solver* sv = make_solver(&m, wc_default_solver_opts(), NULL);
    CHECK_EQ_INT(omp_get_max_active_levels(), host);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    wc_solve_result res;
    CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, dv, 1, &res), WC_OK);
    CHECK(res.converged);
    CHECK_EQ_INT(omp_get_max_active_levels(), host);
    for (int k = 0; k < 9 * s.nb; ++k) s.A[k] = -s.A[k]; /* negative definite: the factorisation fails */
    CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, dv, 1, &res), WC_ERROR_FACTORIZATION);
    CHECK_EQ_INT(omp_get_max_active_levels(), host);
    free(dv);
    wc_solver_destroy(sv);
    sys_free(&s);
    wc_model_free(&m);
#else
    printf("  (built without OpenMP: nothing to keep)\n");
#endif
}

static void test_iterative_match_direct(void) {
    wc_model q = quad_model(12, 12), t = tri_model(9, 7);
    check_iterative(&q, 12);
    check_iterative(&t, 9);
    wc_model_free(&q);
    wc_model_free(&t);
}

/* (4) a looser tolerance takes fewer PCG iterations */
static void test_pcg_tolerance(void) {
    wc_model m = quad_model(12, 12);
    sys s = cloth_system(&m, 12, 9);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    int last = -1;
    for (double tol = 1e-10; tol < 0.5; tol *= 100.0) {
        wc_solver_opts o = wc_default_solver_opts();
        o.tolerance = tol;
        o.max_iterations = 5000;
        wc_solver* sv = make_solver(&m, o, NULL);
        wc_solve_result res;
        CHECK_EQ_INT(run(sv, WC_SOLVER_PCG, &s, dv, 1, &res), WC_OK);
        CHECK(res.converged && res.residual <= tol);
        if (last >= 0) CHECK(res.iterations < last);
        last = res.iterations;
        wc_solver_destroy(sv);
    }
    /* tolerance 0 runs to the cap */
    wc_solver_opts o = wc_default_solver_opts();
    o.tolerance = 0.0;
    o.max_iterations = 40;
    wc_solver* sv = make_solver(&m, o, NULL);
    wc_solve_result res;
    CHECK_EQ_INT(run(sv, WC_SOLVER_PCG, &s, dv, 1, &res), WC_OK);
    CHECK_EQ_INT(res.iterations, 40);
    CHECK(!res.converged);
    wc_solver_destroy(sv);
    free(dv);
    sys_free(&s);
    wc_model_free(&m);
}

/* (5) SPD but far from diagonally dominant (diagonal 6 I, every coupling block I: the block
 * Jacobi iteration matrix is -adjacency / 6, spectral radius about 2 on this grid): Jacobi and
 * Chebyshev report divergence and leave finite values; PCG and the direct solver still agree. */
static void test_jacobi_divergence(void) {
    wc_model m = quad_model(12, 12);
    sys s = sys_alloc(&m);
    fill_coupled(&m, &s, 6.0, 1.0);
    rng r = {21};
    for (int i = 0; i < 3 * s.n; ++i) s.b[i] = urand(&r);
    set_default_filter(&s, 12, 22);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    double* ref = calloc(3 * (size_t)s.n, sizeof(double));
    CHECK(dense_solve(&m, &s, ref));   /* positive definite */
    wc_solver_opts o = wc_default_solver_opts();
    o.tolerance = 1e-8;
    wc_solver* sv = make_solver(&m, o, NULL);
    wc_solve_result res;
    for (int k = 1; k <= 2; ++k) {
        wc_status st = run(sv, all_types[k], &s, dv, 1, &res);
        CHECK_EQ_INT(st, WC_ERROR_SOLVER_DIVERGED);
        CHECK_EQ_INT(res.status, WC_ERROR_SOLVER_DIVERGED);
        CHECK(!res.converged);
        CHECK(res.iterations < 100);   /* caught early, not at the cap */
        int finite = 1;
        for (int i = 0; i < 3 * s.n; ++i) finite &= isfinite(dv[i]) ? 1 : 0;
        CHECK(finite);
        check_constraints(&s, dv);
    }
    CHECK_EQ_INT(run(sv, WC_SOLVER_PCG, &s, dv, 1, &res), WC_OK);
    CHECK(ts_rel_diff(dv, ref, 3 * s.n) <= 1e-6);
    CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, dv, 1, &res), WC_OK);
    CHECK(ts_rel_diff(dv, ref, 3 * s.n) <= 1e-10);
    wc_solver_destroy(sv);
    free(dv);
    free(ref);
    sys_free(&s);
    wc_model_free(&m);
}

/* (6) an indefinite matrix (diagonal 0.5 I, couplings I) makes the direct solver report
 * FACTORIZATION (the dense Cholesky agrees it is not positive definite), leaves finite values,
 * and the same solver then solves a good system. CHOLMOD picks a simplicial factor for the
 * 8 x 8 grid, supernodal ones for the others. */
static void test_direct_not_spd(void) {
    int sizes[3] = {8, 12, 40};
    for (int k = 0; k < 3; ++k) {
        int nx = sizes[k];
        wc_model m = quad_model(nx, nx);
        sys s = sys_alloc(&m);
        fill_coupled(&m, &s, 0.5, 1.0);
        rng r = {31};
        for (int i = 0; i < 3 * s.n; ++i) s.b[i] = urand(&r);
        set_default_filter(&s, nx, 32);
        double* dv = calloc(3 * (size_t)s.n, sizeof(double));
        if (nx <= 12) CHECK(!dense_solve(&m, &s, dv));
        wc_solver* sv = make_solver(&m, wc_default_solver_opts(), NULL);
        wc_solve_result res;
        CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, dv, 1, &res), WC_ERROR_FACTORIZATION);
        CHECK(!res.converged);
        int finite = 1;
        for (int i = 0; i < 3 * s.n; ++i) finite &= isfinite(dv[i]) ? 1 : 0;
        CHECK(finite);
        check_constraints(&s, dv);
        /* recovery on the same solver */
        sys_free(&s);
        s = cloth_system(&m, nx, 33);
        CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, dv, 1, &res), WC_OK);
        CHECK(proj_residual(&m, &s, dv) / proj_residual(&m, &s, s.f.z) <= 1e-10);
        wc_solver_destroy(sv);
        free(dv);
        sys_free(&s);
        wc_model_free(&m);
    }
}

/* (7) the same solve on 1, 2 and 3 threads is bit-identical (reductions by fixed chunks): every
 * solver, then PCG (block Jacobi, the multigrid, the direct factor) with off-pattern couplings,
 * whose product runs on the threads through its row index (900 particles: four chunks, so 3 threads
 * own 1, 1 and 2). */
static void test_threads_bit_identical(void) {
    wc_model m = quad_model(30, 30);
    sys s = cloth_system(&m, 30, 41);
    wc_solver_opts o = wc_default_solver_opts();
    o.tolerance = 1e-6;
    o.max_iterations = 400;
    double* a = calloc(3 * (size_t)s.n, sizeof(double));
    double* b = calloc(3 * (size_t)s.n, sizeof(double));
    /* couplings between particles ~n/3 apart (their diagonal blocks added to A: A stays SPD) */
    enum { N_TERMS = 40 };
    wc_coupling_term term[N_TERMS];
    rng r = {77};
    for (int k = 0; k < N_TERMS; ++k) {
        wc_coupling_term* t = &term[k];
        t->cnt = 2;
        t->p[0] = (k * 97) % s.n;
        t->p[1] = (t->p[0] + s.n / 3 + k) % s.n;
        t->w[0] = 1.0;
        t->w[1] = -1.0;
        unit_vec(&r, t->n);
        t->c = 5.0 + k;
        for (int q = 0; q < 2; ++q) {
            double* D = s.A + 9 * (size_t)m.pattern.diag[t->p[q]];
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j) D[3 * i + j] += t->c * t->n[i] * t->n[j];
        }
    }
    wc_coupling cpl = {N_TERMS, term};
    for (int pass = 0; pass < 2; ++pass) { /* all solvers; PCG's preconditioners with couplings */
        for (int k = 0; k < (pass == 0 ? 4 : 3); ++k) {
            wc_solver_type type = pass == 0 ? all_types[k] : (k == 2 ? WC_SOLVER_DIRECT : WC_SOLVER_PCG);
            o.preconditioner = pass == 1 && k == 1 ? WC_PRECOND_AMG : WC_PRECOND_BLOCK_JACOBI;
            wc_solver* sv = make_solver(&m, o, NULL);
            wc_diag d = {0};
            if (pass == 1) CHECK_EQ_INT(wc_solver_set_coupling(sv, &cpl, N_TERMS, &d), WC_OK);
            wc_solve_result ra, rb;
            CHECK_EQ_INT(run(sv, type, &s, a, 1, &ra), WC_OK);
            for (int threads = 2; threads <= 3; ++threads) {
                wc_solver_invalidate_rho(sv);
                CHECK_EQ_INT(run(sv, type, &s, b, threads, &rb), WC_OK);
                CHECK(memcmp(a, b, sizeof(double) * 3 * (size_t)s.n) == 0);
                CHECK_EQ_INT(ra.iterations, rb.iterations);
                CHECK(memcmp(&ra.residual, &rb.residual, sizeof(double)) == 0);
            }
            CHECK(ra.converged || type == WC_SOLVER_JACOBI || type == WC_SOLVER_CHEBYSHEV);
            printf("  %s%s%s: %d iterations on 1, 2 and 3 threads, bit-identical\n", wc_solver_name(type),
                   pass == 1 && k == 1 ? " (multigrid)" : "", pass == 1 ? " with couplings" : "", ra.iterations);
            CHECK(ra.iterations > (type == WC_SOLVER_DIRECT ? (pass == 0 ? 0 : 2) : 10));
            wc_solver_invalidate_rho(sv);
            wc_solver_destroy(sv);
        }
    }
    free(a);
    free(b);
    sys_free(&s);
    wc_model_free(&m);
}

/* Closed forms: block-diagonal A makes D~^{-1} P = I, so rho(I - gamma D~^{-1} P) = 1 - gamma and
 * one Jacobi sweep is exact. The estimate is cached until invalidated. */
static void test_rho_and_jacobi_closed_form(void) {
    wc_model m = quad_model(12, 12);
    sys s = cloth_system(&m, 12, 51);
    const wc_bsr_pattern* p = &m.pattern;
    wc_par par;
    wc_par_init(&par, 1);
    wc_solver_opts o = wc_default_solver_opts();
    o.check_every = 1;
    o.tolerance = 1e-12;
    wc_solver* sv = make_solver(&m, o, NULL);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    double* ref = calloc(3 * (size_t)s.n, sizeof(double));
    double rho_cloth = wc_solver_estimate_rho(sv, s.A, &s.f, &par);
    CHECK(rho_cloth > 0.9 && rho_cloth < 1.0);
    /* drop the couplings */
    for (int i = 0; i < s.n; ++i)
        for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k)
            if (p->col[k] != i)
                for (int q = 0; q < 9; ++q) s.A[9 * k + q] = 0.0;
    CHECK(wc_solver_estimate_rho(sv, s.A, &s.f, &par) == rho_cloth);   /* cached */
    wc_solver_invalidate_rho(sv);
    CHECK_NEAR(wc_solver_estimate_rho(sv, s.A, &s.f, &par), 1.0 - o.chebyshev_gamma, 1e-12);
    wc_solve_result res;
    CHECK_EQ_INT(run(sv, WC_SOLVER_JACOBI, &s, dv, 1, &res), WC_OK);
    CHECK_EQ_INT(res.iterations, 1);
    CHECK(res.converged);
    CHECK_EQ_INT(run(sv, WC_SOLVER_DIRECT, &s, ref, 1, &res), WC_OK);
    CHECK(ts_rel_diff(dv, ref, 3 * s.n) <= 1e-13);
    wc_solver_destroy(sv);
    free(dv);
    free(ref);
    sys_free(&s);
    wc_model_free(&m);
}

/* Zero right-hand side (b = A z): dv = z exactly, no iteration; non-finite b: failure status,
 * finite dv; bad arguments. */
static void test_edge_cases(void) {
    wc_model m = quad_model(8, 8);
    sys s = cloth_system(&m, 8, 61);
    wc_par par;
    wc_par_init(&par, 1);
    wc_bsr_mul(&m.pattern, s.A, s.f.z, s.b, &par);   /* b = A z, summed as the solvers sum it */
    wc_solver* sv = make_solver(&m, wc_default_solver_opts(), NULL);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    wc_solve_result res;
    for (int k = 0; k < 4; ++k) {
        CHECK_EQ_INT(run(sv, all_types[k], &s, dv, 1, &res), WC_OK);
        CHECK(memcmp(dv, s.f.z, sizeof(double) * 3 * (size_t)s.n) == 0);
        CHECK(res.converged && res.residual == 0.0 && res.iterations == 0);
    }
    s.b[7] = NAN;
    for (int k = 0; k < 4; ++k) {
        wc_status st = run(sv, all_types[k], &s, dv, 1, &res);
        CHECK_EQ_INT(st, k == 3 ? WC_ERROR_FACTORIZATION : WC_ERROR_SOLVER_DIVERGED);
        CHECK(memcmp(dv, s.f.z, sizeof(double) * 3 * (size_t)s.n) == 0);
    }
    CHECK_EQ_INT(wc_solve(sv, (wc_solver_type)7, s.A, s.b, &s.f, dv, &par, &res), WC_ERROR_INVALID_ARGUMENT);
    wc_solver_destroy(sv);
    /* without want_direct the direct solver is not analysed */
    wc_solver_opts o = wc_default_solver_opts();
    wc_diag d = {0};
    CHECK_EQ_INT(wc_solver_create(&sv, &m, &o, 0, NULL, &d), WC_OK);
    CHECK_EQ_INT(wc_solve(sv, WC_SOLVER_DIRECT, s.A, s.b, &s.f, dv, &par, &res), WC_ERROR_CALL_ORDER);
    wc_solver_destroy(sv);
    o.chebyshev_gamma = 1.5;
    CHECK_EQ_INT(wc_solver_create(&sv, &m, &o, 0, NULL, &d), WC_ERROR_INVALID_ARGUMENT);
    CHECK(sv == NULL);
    free(dv);
    sys_free(&s);
    wc_model_free(&m);
}

/* Everything is allocated at create (through the given allocator) and freed at destroy; solves
 * allocate nothing through it. */
typedef struct counter { long allocs, frees; } counter;
static void* count_alloc(size_t n, void* u) { return ++((counter*)u)->allocs, malloc(n); }
static void count_free(void* ptr, void* u) { ++((counter*)u)->frees, free(ptr); }
static void test_allocation(void) {
    wc_model m = quad_model(12, 12);
    sys s = cloth_system(&m, 12, 71);
    counter c = {0, 0};
    wc_allocator a = {count_alloc, count_free, &c};
    wc_solver* sv = make_solver(&m, wc_default_solver_opts(), &a);
    long after_create = c.allocs;
    CHECK(after_create > 0);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    wc_solve_result res;
    for (int k = 0; k < 4; ++k) run(sv, all_types[k], &s, dv, 2, &res);
    CHECK_EQ_INT(c.allocs, after_create);
    wc_solver_destroy(sv);
    CHECK_EQ_INT(c.frees, c.allocs);
    free(dv);
    sys_free(&s);
    wc_model_free(&m);
}

/* Not a check: iterations and time of each solver on a 100 x 100 grid (1 m, default material,
 * h = 1/30, two corners pinned), printed so that the solvers can be compared; the error is
 * relative to the direct solution. Smaller in unoptimised builds. Times on a loaded machine are
 * noise (ctest runs this with OMP_WAIT_POLICY=passive so that an oversubscribed OpenMP team
 * sleeps instead of spinning through every barrier). */
static void print_comparison(void) {
#ifdef NDEBUG
    const int nx = 100;
#else
    const int nx = 30;
#endif
    wc_model m = quad_model(nx, nx);
    sys s = sys_alloc(&m);
    fill_cloth(&m, &s, 1.0 / 30.0, 1.05, 1.0, 81);
    int pin[2] = {nx * (nx - 1), nx * nx - 1};
    set_filter(&s, pin, 2, NULL, 0, -1, 82);
    double* dv = calloc(3 * (size_t)s.n, sizeof(double));
    double* ref = calloc(3 * (size_t)s.n, sizeof(double));
    struct { wc_solver_type t; double tol; int max_it; } rows[] = {
        {WC_SOLVER_DIRECT, 0, 1},         {WC_SOLVER_PCG, 1e-4, 300},        {WC_SOLVER_JACOBI, 1e-4, 300},
        {WC_SOLVER_CHEBYSHEV, 1e-4, 300}, {WC_SOLVER_PCG, 1e-4, 3000}};
    printf("\n%d x %d grid (%d particles, %d blocks), h = 1/30, default material:\n", nx, nx, s.n, s.nb);
    printf("  %-10s %8s %6s %5s %5s %10s %10s %9s %9s\n", "solver", "tol", "max_it", "thr", "iters", "residual",
           "rel.error", "ms", "ms/iter");
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; ++k) {
        wc_solver_opts o = wc_default_solver_opts();
        o.tolerance = rows[k].tol;
        o.max_iterations = rows[k].max_it;
        wc_solver* sv = make_solver(&m, o, NULL);
        for (int threads = 1; threads <= 2; ++threads) {
            wc_solve_result res;
            wc_solver_invalidate_rho(sv);   /* Chebyshev's time includes its rho estimate */
            double t0 = wc_now_ms();
            run(sv, rows[k].t, &s, dv, threads, &res);
            double best = wc_now_ms() - t0;
            if (rows[k].t == WC_SOLVER_DIRECT && threads == 1)
                for (int i = 0; i < 3 * s.n; ++i) ref[i] = dv[i];
            printf("  %-10s %8.0e %6d %5d %5d %10.2e %10.2e %9.2f %9.3f%s\n", wc_solver_name(rows[k].t), rows[k].tol,
                   rows[k].max_it, threads, res.iterations, res.residual, ts_rel_diff(dv, ref, 3 * s.n), best,
                   best / (res.iterations > 0 ? res.iterations : 1), res.status == WC_OK ? "" : "  (failed)");
        }
        wc_solver_destroy(sv);
    }
    free(dv);
    free(ref);
    sys_free(&s);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_names_and_defaults);
    RUN_TEST(test_direct_matches_dense);
    RUN_TEST(test_direct_keeps_host_openmp);
    RUN_TEST(test_iterative_match_direct);
    RUN_TEST(test_pcg_tolerance);
    RUN_TEST(test_jacobi_divergence);
    RUN_TEST(test_direct_not_spd);
    RUN_TEST(test_threads_bit_identical);
    RUN_TEST(test_rho_and_jacobi_closed_form);
    RUN_TEST(test_edge_cases);
    RUN_TEST(test_allocation);
    print_comparison();
    return TEST_SUMMARY();
}
