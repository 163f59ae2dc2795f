/* Spring forces, their Jacobians, external forces and the assembled backward-Euler system checked
 * against central finite differences, closed forms and a dense reference built here (double
 * precision, randomly perturbed grids with a fixed seed). */
#include <stdlib.h>
#include "assemble.h"
#include "check.h"
#include "forces.h"
#include "model.h"
#include "test_support.h"
#include "vec3.h"

/* ---- fixtures ---------------------------------------------------------------------------- */

static unsigned long long rng_state_ = 0x9E3779B97F4A7C15ull;
/* uniform in [-1, 1) (xorshift64*, fixed seed) */
static double rnd(void) {
    rng_state_ ^= rng_state_ >> 12;
    rng_state_ ^= rng_state_ << 25;
    rng_state_ ^= rng_state_ >> 27;
    unsigned long long r = rng_state_ * 2685821657736338717ull;
    return (double)(r >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

/* Distinct stiffness and damping per spring type, so a wrong type lookup shows. */
static wc_model build_model(const wc_source_mesh* src) {
    wc_model m;
    wc_diag d = {0};
    wc_model_def def = wc_default_model_def();
    def.material.k[0] = 900.0, def.material.k[1] = 300.0, def.material.k[2] = 70.0;
    def.material.d[0] = 2.0, def.material.d[1] = 0.7, def.material.d[2] = 0.3;
    wc_status st = wc_model_build(&m, src, &def, NULL, &d);
    if (st != WC_OK) fprintf(stderr, "build failed: %s\n", d.message);
    CHECK_EQ_INT(st, WC_OK);
    return m;
}

/* 0: 4x4 quad grid, 1: 4x4 triangle grid, 2: nx x nx quad grid; 1 m square. */
static wc_model grid_model(int kind, int nx) {
    wc_source_mesh src;
    if (kind == 1) ts_tri_grid(&src, nx, nx, 1.0, 1.0);
    else ts_quad_grid(&src, nx, nx, 1.0, 1.0, 0);
    wc_model m = build_model(&src);
    wc_source_mesh_free(&src);
    return m;
}

/* x = rest + amp * spacing-scaled random offsets (z too), v random in [-1, 1). (n x 3) each. */
static void perturb(const wc_model* m, double amp, double* x, double* v) {
    for (int i = 0; i < 3 * m->n_particles; ++i) {
        x[i] = m->rest_pos[i] + amp * rnd();
        if (v) v[i] = rnd();
    }
}

/* Total spring force per particle (n x 3) from per-spring results, gathered over the spring list
 * (not through the pattern). */
static void gather_springs(const wc_model* m, const wc_spring_eval* se, double* F) {
    for (int i = 0; i < 3 * m->n_particles; ++i) F[i] = 0.0;
    for (int s = 0; s < m->n_springs; ++s) {
        for (int q = 0; q < 3; ++q) {
            F[3 * m->springs[s].a + q] += se[s].f[q];
            F[3 * m->springs[s].b + q] -= se[s].f[q];
        }
    }
}

static double spring_length(const wc_model* m, const double* x, int s, double* u) {
    const double *a = x + 3 * m->springs[s].a, *b = x + 3 * m->springs[s].b;
    double L[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    double l = sqrt(L[0] * L[0] + L[1] * L[1] + L[2] * L[2]);
    if (u)
        for (int q = 0; q < 3; ++q) u[q] = L[q] / l;
    return l;
}

/* ---- springs ----------------------------------------------------------------------------- */

/* f = -grad E at zero velocity, E by central differences. */
static void test_force_is_minus_energy_gradient(void) {
    for (int kind = 0; kind < 2; ++kind) {
        wc_model m = grid_model(kind, 4);
        int n = m.n_particles;
        double *x = calloc(3 * (size_t)n, sizeof(double)), *v = calloc(3 * (size_t)n, sizeof(double));
        double* F = calloc(3 * (size_t)n, sizeof(double));
        wc_spring_eval* se = calloc(m.n_springs, sizeof *se);
        wc_par par;
        wc_par_init(&par, 1);
        perturb(&m, 0.08, x, NULL);
        wc_eval_springs(&m, x, v, WC_COMPRESSION_FULL, &par, se);
        gather_springs(&m, se, F);
        double eps = 1e-6, worst = 0.0, fmax = 0.0;
        for (int i = 0; i < 3 * n; ++i) {
            double x0 = x[i];
            x[i] = x0 + eps;
            double ep = wc_spring_energy(&m, x);
            x[i] = x0 - eps;
            double em = wc_spring_energy(&m, x);
            x[i] = x0;
            double g = (ep - em) / (2 * eps);
            if (fabs(F[i] + g) > worst) worst = fabs(F[i] + g);
            if (fabs(F[i]) > fmax) fmax = fabs(F[i]);
        }
        CHECK(fmax > 1.0); /* the configuration is really strained */
        CHECK_NEAR(worst, 0.0, 1e-6 * fmax);
        free(x), free(v), free(F), free(se);
        wc_model_free(&m);
    }
}

/* kx (and -kx for end b) against dF_a/dx by central differences at zero velocity (the damping
 * term's x-derivative vanishes there); kv against dF_a/dv at random velocity. */
static void check_jacobians(wc_compression mode) {
    for (int kind = 0; kind < 2; ++kind) {
        wc_model m = grid_model(kind, 4);
        int n = m.n_particles, ns = m.n_springs;
        double *x = calloc(3 * (size_t)n, sizeof(double)), *v = calloc(3 * (size_t)n, sizeof(double));
        double* zero = calloc(3 * (size_t)n, sizeof(double));
        wc_spring_eval* se = calloc((size_t)ns, sizeof *se);
        wc_spring_eval *sp = calloc((size_t)ns, sizeof *sp), *sm = calloc((size_t)ns, sizeof *sm);
        wc_par par;
        wc_par_init(&par, 1);
        perturb(&m, 0.08, x, v);
        wc_eval_springs(&m, x, v, mode, &par, se);
        /* kx does not depend on velocity */
        wc_eval_springs(&m, x, zero, mode, &par, sp);
        int vel_free = 1;
        for (int s = 0; s < ns; ++s) vel_free &= memcmp(se[s].kx, sp[s].kx, sizeof se[s].kx) == 0;
        CHECK(vel_free);

        /* dx[s][9]: FD of f_a w.r.t. x_a; dxb[s][9]: w.r.t. x_b; dv[s][9]: w.r.t. v_a */
        double *dxa = calloc(9 * (size_t)ns, sizeof(double)), *dxb = calloc(9 * (size_t)ns, sizeof(double));
        double* dva = calloc(9 * (size_t)ns, sizeof(double));
        double eps = 1e-6, eps_v = 1e-2; /* f is affine in v: a large step has no truncation error */
        for (int p = 0; p < n; ++p)
            for (int c = 0; c < 3; ++c) {
                double x0 = x[3 * p + c];
                x[3 * p + c] = x0 + eps;
                wc_eval_springs(&m, x, zero, mode, &par, sp);
                x[3 * p + c] = x0 - eps;
                wc_eval_springs(&m, x, zero, mode, &par, sm);
                x[3 * p + c] = x0;
                for (int s = 0; s < ns; ++s) {
                    double* dst = m.springs[s].a == p ? dxa : m.springs[s].b == p ? dxb : NULL;
                    if (!dst) continue;
                    for (int r = 0; r < 3; ++r) dst[9 * s + 3 * r + c] = (sp[s].f[r] - sm[s].f[r]) / (2 * eps);
                }
                double v0 = v[3 * p + c];
                v[3 * p + c] = v0 + eps_v;
                wc_eval_springs(&m, x, v, mode, &par, sp);
                v[3 * p + c] = v0 - eps_v;
                wc_eval_springs(&m, x, v, mode, &par, sm);
                v[3 * p + c] = v0;
                for (int s = 0; s < ns; ++s) {
                    if (m.springs[s].a != p) continue;
                    for (int r = 0; r < 3; ++r) dva[9 * s + 3 * r + c] = (sp[s].f[r] - sm[s].f[r]) / (2 * eps_v);
                }
            }
        int stretched = 0, compressed = 0, bad_x = 0, bad_xb = 0, bad_v = 0, bad_drop = 0, asym = 0;
        for (int s = 0; s < ns; ++s) {
            double u[3], l = spring_length(&m, x, s, u), k = m.material.k[m.springs[s].type];
            double d = m.material.d[m.springs[s].type];
            int comp = l < m.springs[s].rest;
            compressed += comp;
            stretched += !comp;
            for (int q = 0; q < 9; ++q) {
                int r = q / 3, c = q % 3;
                if (se[s].kx[q] != se[s].kx[3 * c + r] || se[s].kv[q] != se[s].kv[3 * c + r]) ++asym;
                if (fabs(se[s].kv[q] - dva[9 * s + q]) > 1e-7 * (1 + d)) ++bad_v;
                if (mode == WC_COMPRESSION_DROP && comp) {
                    /* dropped geometric term: exactly the axial stiffness */
                    if (fabs(se[s].kx[q] + k * u[r] * u[c]) > 1e-12 * k) ++bad_drop;
                    continue;
                }
                if (fabs(se[s].kx[q] - dxa[9 * s + q]) > 1e-6 * k) ++bad_x;
                if (fabs(-se[s].kx[q] - dxb[9 * s + q]) > 1e-6 * k) ++bad_xb;
            }
        }
        CHECK(stretched > 5);
        CHECK(compressed > 5);
        CHECK_EQ_INT(bad_x, 0);
        CHECK_EQ_INT(bad_xb, 0);
        CHECK_EQ_INT(bad_v, 0);
        CHECK_EQ_INT(bad_drop, 0);
        CHECK_EQ_INT(asym, 0);
        free(x), free(v), free(zero), free(se), free(sp), free(sm), free(dxa), free(dxb), free(dva);
        wc_model_free(&m);
    }
}

static void test_jacobians_full(void) { check_jacobians(WC_COMPRESSION_FULL); }
static void test_jacobians_drop(void) { check_jacobians(WC_COMPRESSION_DROP); }

/* Coincident ends give finite values; a uniformly scaled grid gives closed-form energy and strain. */
static void test_degenerate_energy_strain(void) {
    wc_model m = grid_model(0, 4);
    int n = m.n_particles, ns = m.n_springs;
    double *x = calloc(3 * (size_t)n, sizeof(double)), *v = calloc(3 * (size_t)n, sizeof(double));
    wc_spring_eval* se = calloc((size_t)ns, sizeof *se);
    wc_par par;
    wc_par_init(&par, 1);
    memcpy(x, m.rest_pos, sizeof(double) * 3 * n);
    int a = m.springs[0].a, b = m.springs[0].b;
    memcpy(x + 3 * b, x + 3 * a, 3 * sizeof(double));
    v[3 * a] = 1.0;
    for (int mode = 0; mode < 2; ++mode) {
        wc_eval_springs(&m, x, v, (wc_compression)mode, &par, se);
        int finite = 1;
        for (int s = 0; s < ns; ++s) {
            finite &= v3_finite(se[s].f);
            for (int q = 0; q < 9; ++q) finite &= isfinite(se[s].kx[q]) && isfinite(se[s].kv[q]);
        }
        CHECK(finite);
        /* the force pushes the ends apart along the rest direction (a - b) */
        double R[3];
        v3_sub(R, m.rest_pos + 3 * a, m.rest_pos + 3 * b);
        CHECK(v3_dot(se[0].f, R) > 0.0);
    }
    double strain = 0.1;
    for (int i = 0; i < 3 * n; ++i) x[i] = (1.0 + strain) * m.rest_pos[i];
    double e_ref = 0.0;
    for (int s = 0; s < ns; ++s) {
        double dl = strain * m.springs[s].rest;
        e_ref += 0.5 * m.material.k[m.springs[s].type] * dl * dl;
    }
    CHECK_NEAR(wc_spring_energy(&m, x), e_ref, 1e-12 * e_ref);
    CHECK_NEAR(wc_max_stretch_strain(&m, x), strain, 1e-12);
    for (int i = 0; i < 3 * n; ++i) x[i] = 0.9 * m.rest_pos[i];
    CHECK_NEAR(wc_max_stretch_strain(&m, x), 0.0, 0.0);
    free(x), free(v), free(se);
    wc_model_free(&m);
}

/* ---- external ---------------------------------------------------------------------------- */

/* Gravity alone gives m g; zero drag coefficients skip air entirely (scratch untouched). */
static void test_gravity(void) {
    wc_model m = grid_model(1, 4);
    int n = m.n_particles;
    double *x = calloc(3 * (size_t)n, sizeof(double)), *v = calloc(3 * (size_t)n, sizeof(double));
    double *f = calloc(3 * (size_t)n, sizeof(double)), *scratch = malloc(sizeof(double) * 3 * (size_t)m.n_tris);
    for (int t = 0; t < 3 * m.n_tris; ++t) scratch[t] = NAN;
    wc_par par;
    wc_par_init(&par, 2);
    perturb(&m, 0.05, x, v);
    double g[3] = {0.3, -9.81, 1.5};
    wc_air air = {{4.0, -2.0, 7.0}, 0.0, 0.0};
    wc_eval_external(&m, x, v, g, &air, &par, scratch, f);
    int bad = 0;
    for (int i = 0; i < n; ++i)
        for (int q = 0; q < 3; ++q) bad += f[3 * i + q] != m.mass[i] * g[q];
    CHECK_EQ_INT(bad, 0);
    int untouched = 1;
    for (int t = 0; t < 3 * m.n_tris; ++t) untouched &= isnan(scratch[t]);
    CHECK(untouched);
    free(x), free(v), free(f), free(scratch);
    wc_model_free(&m);
}

/* One triangle with a known normal: f = A (cn (u.n) n + ct (u - (u.n) n)), a third per particle. */
static void check_single_triangle(const double* pos, double area, const double* normal) {
    wc_source_mesh src;
    int sizes[1] = {3}, idx[3] = {0, 1, 2};
    wc_diag d = {0};
    CHECK_EQ_INT(wc_source_mesh_from_arrays(&src, NULL, pos, 3, sizes, 1, idx, 1.0, &d), WC_OK);
    wc_model m = build_model(&src);
    wc_source_mesh_free(&src);
    CHECK_EQ_INT(m.n_particles, 3);
    CHECK_EQ_INT(m.n_tris, 1);
    double x[9], v[9] = {0.5, -1.0, 0.25, 1.5, 0.0, -0.5, -2.0, 0.5, 2.0}, f[9], scratch[3];
    memcpy(x, m.rest_pos, sizeof x);
    double mean_v[3] = {0, 0, 0};
    for (int i = 0; i < 3; ++i)
        for (int q = 0; q < 3; ++q) mean_v[q] += v[3 * i + q] / 3.0;
    wc_air air = {{3.0, -4.0, 5.0}, 2.5, 0.4};
    double u[3], un = 0.0, expect[3];
    for (int q = 0; q < 3; ++q) u[q] = air.wind[q] - mean_v[q], un += u[q] * normal[q];
    for (int q = 0; q < 3; ++q)
        expect[q] = area * (air.normal_drag * un * normal[q] + air.tangent_drag * (u[q] - un * normal[q]));
    double g[3] = {0.0, 0.0, -9.81};
    wc_par par;
    wc_par_init(&par, 1);
    wc_eval_external(&m, x, v, g, &air, &par, scratch, f);
    for (int q = 0; q < 3; ++q) CHECK_NEAR(scratch[q], expect[q], 1e-12);
    for (int i = 0; i < 3; ++i)
        for (int q = 0; q < 3; ++q) CHECK_NEAR(f[3 * i + q], m.mass[i] * g[q] + expect[q] / 3.0, 1e-12);
    wc_model_free(&m);
}

static void test_air_single_triangle(void) {
    double flat[9] = {0, 0, 0, 2, 0, 0, 0, 1, 0}, zn[3] = {0, 0, 1};
    check_single_triangle(flat, 1.0, zn);
    double tilted[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, dn[3] = {1 / sqrt(3.0), 1 / sqrt(3.0), 1 / sqrt(3.0)};
    check_single_triangle(tilted, sqrt(3.0) / 2.0, dn);
}

/* On a perturbed grid: per-triangle forces match the formula computed here, each particle gets a
 * third of its triangles' forces, and the total equals the sum over triangles. */
static void test_air_grid_total(void) {
    wc_model m = grid_model(0, 5);
    int n = m.n_particles, nt = m.n_tris;
    double *x = calloc(3 * (size_t)n, sizeof(double)), *v = calloc(3 * (size_t)n, sizeof(double));
    double *f = calloc(3 * (size_t)n, sizeof(double)), *scratch = calloc(3 * (size_t)nt, sizeof(double));
    double* expect = calloc(3 * (size_t)n, sizeof(double));
    wc_par par;
    wc_par_init(&par, 2);
    perturb(&m, 0.06, x, v);
    double g[3] = {0, 0, 0};
    wc_air air = {{1.0, 2.0, -3.0}, 1.7, 0.3};
    wc_eval_external(&m, x, v, g, &air, &par, scratch, f);
    double tri_sum[3] = {0, 0, 0}, part_sum[3] = {0, 0, 0}, worst_tri = 0.0, worst_part = 0.0;
    for (int t = 0; t < nt; ++t) {
        const int* c = m.tris + 3 * t;
        double e1[3], e2[3], N[3], u[3];
        v3_sub(e1, x + 3 * c[1], x + 3 * c[0]);
        v3_sub(e2, x + 3 * c[2], x + 3 * c[0]);
        v3_cross(N, e1, e2);
        double nn = v3_norm(N), area = 0.5 * nn, un = 0.0;
        for (int q = 0; q < 3; ++q) {
            u[q] = air.wind[q] - (v[3 * c[0] + q] + v[3 * c[1] + q] + v[3 * c[2] + q]) / 3.0;
            un += u[q] * N[q] / nn;
        }
        for (int q = 0; q < 3; ++q) {
            double nq = N[q] / nn;
            double ft = area * (air.normal_drag * un * nq + air.tangent_drag * (u[q] - un * nq));
            worst_tri = fmax(worst_tri, fabs(ft - scratch[3 * t + q]));
            tri_sum[q] += ft;
            for (int k = 0; k < 3; ++k) expect[3 * c[k] + q] += ft / 3.0;
        }
    }
    for (int i = 0; i < n; ++i)
        for (int q = 0; q < 3; ++q) {
            part_sum[q] += f[3 * i + q];
            worst_part = fmax(worst_part, fabs(f[3 * i + q] - expect[3 * i + q]));
        }
    CHECK(fabs(tri_sum[0]) + fabs(tri_sum[1]) + fabs(tri_sum[2]) > 0.1);
    CHECK_NEAR(worst_tri, 0.0, 1e-12);
    CHECK_NEAR(worst_part, 0.0, 1e-12);
    for (int q = 0; q < 3; ++q) CHECK_NEAR(part_sum[q], tri_sum[q], 1e-12);
    free(x), free(v), free(f), free(scratch), free(expect);
    wc_model_free(&m);
}

/* ---- assembly ---------------------------------------------------------------------------- */

/* A = M - h dF/dv - h^2 dF/dx and b = h (f0 + h dF/dx v0) against a dense reference whose
 * Jacobians are central differences of the total spring force (FULL mode, gravity only). */
static void test_assembly_dense(void) {
    for (int kind = 0; kind < 2; ++kind) {
        wc_model m = grid_model(kind, 4);
        int n = m.n_particles, ns = m.n_springs, N = 3 * n;
        const wc_bsr_pattern* p = &m.pattern;
        double *x = calloc((size_t)N, sizeof(double)), *v = calloc((size_t)N, sizeof(double));
        double *zero = calloc((size_t)N, sizeof(double)), *F0 = calloc((size_t)N, sizeof(double));
        double *Fp = calloc((size_t)N, sizeof(double)), *Fm = calloc((size_t)N, sizeof(double));
        double *Jx = calloc((size_t)N * N, sizeof(double)), *Jv = calloc((size_t)N * N, sizeof(double));
        double *A = calloc((size_t)p->n_blocks * 9, sizeof(double)), *b = calloc((size_t)N, sizeof(double));
        double *fext = calloc((size_t)N, sizeof(double)), *ftot = calloc((size_t)N, sizeof(double));
        wc_spring_eval* se = calloc((size_t)ns, sizeof *se);
        wc_par par;
        wc_par_init(&par, 1);
        perturb(&m, 0.08, x, v);
        double h = 0.01, g[3] = {0.0, -9.81, 0.0}, eps = 1e-6, eps_v = 1e-2;
        for (int i = 0; i < n; ++i)
            for (int q = 0; q < 3; ++q) fext[3 * i + q] = m.mass[i] * g[q];
        /* column c of the dense Jacobians */
        for (int c = 0; c < N; ++c) {
            double x0 = x[c];
            x[c] = x0 + eps;
            wc_eval_springs(&m, x, zero, WC_COMPRESSION_FULL, &par, se);
            gather_springs(&m, se, Fp);
            x[c] = x0 - eps;
            wc_eval_springs(&m, x, zero, WC_COMPRESSION_FULL, &par, se);
            gather_springs(&m, se, Fm);
            x[c] = x0;
            for (int r = 0; r < N; ++r) Jx[(size_t)r * N + c] = (Fp[r] - Fm[r]) / (2 * eps);
            double v0 = v[c];
            v[c] = v0 + eps_v;
            wc_eval_springs(&m, x, v, WC_COMPRESSION_FULL, &par, se);
            gather_springs(&m, se, Fp);
            v[c] = v0 - eps_v;
            wc_eval_springs(&m, x, v, WC_COMPRESSION_FULL, &par, se);
            gather_springs(&m, se, Fm);
            v[c] = v0;
            for (int r = 0; r < N; ++r) Jv[(size_t)r * N + c] = (Fp[r] - Fm[r]) / (2 * eps_v);
        }
        wc_eval_springs(&m, x, v, WC_COMPRESSION_FULL, &par, se);
        gather_springs(&m, se, F0);
        wc_assemble(&m, se, fext, v, h, &par, A, b, ftot);

        /* expand the blocks densely and compare entry by entry */
        double* Ad = calloc((size_t)N * N, sizeof(double));
        for (int i = 0; i < n; ++i)
            for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k)
                for (int q = 0; q < 9; ++q) Ad[(size_t)(3 * i + q / 3) * N + 3 * p->col[k] + q % 3] = A[9 * k + q];
        double worst = 0.0, scale = 0.0;
        for (int r = 0; r < N; ++r)
            for (int c = 0; c < N; ++c) {
                double ref = (r == c ? m.mass[r / 3] : 0.0) - h * Jv[(size_t)r * N + c] - h * h * Jx[(size_t)r * N + c];
                worst = fmax(worst, fabs(Ad[(size_t)r * N + c] - ref));
                scale = fmax(scale, fabs(ref));
            }
        CHECK_NEAR(worst, 0.0, 1e-8 * scale);
        double worst_b = 0.0, scale_b = 0.0, worst_f = 0.0;
        for (int r = 0; r < N; ++r) {
            double jv = 0.0;
            for (int c = 0; c < N; ++c) jv += Jx[(size_t)r * N + c] * v[c];
            double f0 = F0[r] + fext[r], ref = h * (f0 + h * jv);
            worst_b = fmax(worst_b, fabs(b[r] - ref));
            scale_b = fmax(scale_b, fabs(ref));
            worst_f = fmax(worst_f, fabs(ftot[r] - f0));
        }
        CHECK(scale_b > 0.0);
        CHECK_NEAR(worst_b, 0.0, 1e-8 * scale_b);
        CHECK_NEAR(worst_f, 0.0, 1e-12 * scale_b / h);
        /* symmetric: block (j, i) is the transpose of block (i, j), exactly */
        int asym = 0;
        for (int k = 0; k < p->n_blocks; ++k)
            for (int q = 0; q < 9; ++q) asym += A[9 * k + q] != A[9 * p->transpose[k] + 3 * (q % 3) + q / 3];
        CHECK_EQ_INT(asym, 0);
        /* f_total is optional */
        double* b2 = calloc((size_t)N, sizeof(double));
        wc_assemble(&m, se, fext, v, h, &par, A, b2, NULL);
        CHECK(memcmp(b, b2, sizeof(double) * N) == 0);
        free(x), free(v), free(zero), free(Fp), free(Fm), free(F0), free(Jx), free(Jv), free(A), free(b);
        free(fext), free(ftot), free(se), free(Ad), free(b2);
        wc_model_free(&m);
    }
}

/* Springs, external forces and assembly with 1 and 2 threads give bit-identical results. */
static void test_threads_bit_identical(void) {
    wc_model m = grid_model(0, 23);
    int n = m.n_particles, ns = m.n_springs, nt = m.n_tris, nb = m.pattern.n_blocks;
    double *x = calloc(3 * (size_t)n, sizeof(double)), *v = calloc(3 * (size_t)n, sizeof(double));
    wc_spring_eval* se[2];
    double *fext[2], *scr[2], *A[2], *b[2], *ft[2];
    for (int r = 0; r < 2; ++r) {
        se[r] = calloc((size_t)ns, sizeof(wc_spring_eval));
        fext[r] = calloc(3 * (size_t)n, sizeof(double));
        scr[r] = calloc(3 * (size_t)nt, sizeof(double));
        A[r] = calloc(9 * (size_t)nb, sizeof(double));
        b[r] = calloc(3 * (size_t)n, sizeof(double));
        ft[r] = calloc(3 * (size_t)n, sizeof(double));
    }
    perturb(&m, 0.01, x, v);
    double g[3] = {0, -9.81, 0};
    wc_air air = {{2.0, 0.5, 1.0}, 1.2, 0.2};
    for (int r = 0; r < 2; ++r) {
        wc_par par;
        wc_par_init(&par, r + 1);
        wc_eval_springs(&m, x, v, WC_COMPRESSION_DROP, &par, se[r]);
        wc_eval_external(&m, x, v, g, &air, &par, scr[r], fext[r]);
        wc_assemble(&m, se[r], fext[r], v, 1.0 / 60.0, &par, A[r], b[r], ft[r]);
    }
    CHECK(memcmp(se[0], se[1], sizeof(wc_spring_eval) * ns) == 0);
    CHECK(memcmp(scr[0], scr[1], sizeof(double) * 3 * nt) == 0);
    CHECK(memcmp(fext[0], fext[1], sizeof(double) * 3 * n) == 0);
    CHECK(memcmp(A[0], A[1], sizeof(double) * 9 * nb) == 0);
    CHECK(memcmp(b[0], b[1], sizeof(double) * 3 * n) == 0);
    CHECK(memcmp(ft[0], ft[1], sizeof(double) * 3 * n) == 0);
    for (int r = 0; r < 2; ++r) free(se[r]), free(fext[r]), free(scr[r]), free(A[r]), free(b[r]), free(ft[r]);
    free(x), free(v);
    wc_model_free(&m);
}

int main(void) {
    RUN_TEST(test_force_is_minus_energy_gradient);
    RUN_TEST(test_jacobians_full);
    RUN_TEST(test_jacobians_drop);
    RUN_TEST(test_degenerate_energy_strain);
    RUN_TEST(test_gravity);
    RUN_TEST(test_air_single_triangle);
    RUN_TEST(test_air_grid_total);
    RUN_TEST(test_assembly_dense);
    RUN_TEST(test_threads_bit_identical);
    return TEST_SUMMARY();
}
