/* Solver workspace (create/destroy), dispatch, options and the kernels the solvers share:
 * the filtered block-diagonal preconditioner, the projected residual and the projection onto
 * the constraint space. */
#include <math.h>
#include <string.h>
#include "solver_impl.h"
#include "vec3.h"

static const char* const solver_names[WC_SOLVER_COUNT] = {"pcg", "jacobi", "chebyshev", "direct"};

static const char* const precond_names[WC_PRECOND_COUNT] = {"block_jacobi", "amg"};

const char* wc_precond_name(wc_precond_type t) {
    return (t >= 0 && t < WC_PRECOND_COUNT) ? precond_names[t] : "unknown";
}

int wc_precond_from_name(const char* name) {
    if (!name) return -1;
    for (int t = 0; t < WC_PRECOND_COUNT; ++t)
        if (strcmp(name, precond_names[t]) == 0) return t;
    return -1;
}

const char* wc_solver_name(wc_solver_type t) {
    return (t >= 0 && t < WC_SOLVER_COUNT) ? solver_names[t] : "unknown";
}

int wc_solver_from_name(const char* name) {
    if (!name) return -1;
    for (int t = 0; t < WC_SOLVER_COUNT; ++t)
        if (strcmp(name, solver_names[t]) == 0) return t;
    return -1;
}

wc_solver_opts wc_default_solver_opts(void) {
    wc_solver_opts o;
    o.type = WC_SOLVER_PCG;
    o.preconditioner = WC_PRECOND_BLOCK_JACOBI;
    o.tolerance = 1e-4;
    o.max_iterations = 300;
    o.check_every = 10;
    o.chebyshev_rho = 0.0;
    o.chebyshev_gamma = 0.9;
    o.chebyshev_delay = 10;
    o.divergence_factor = 1e3;
    return o;
}

static wc_status check_opts(const wc_solver_opts* o, wc_diag* diag) {
    if (!(o->type >= 0 && o->type < WC_SOLVER_COUNT))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "unknown solver type %d", (int)o->type);
    if (!(o->preconditioner >= 0 && o->preconditioner < WC_PRECOND_COUNT))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "unknown preconditioner %d", (int)o->preconditioner);
    if (!(o->tolerance >= 0.0) || !isfinite(o->tolerance))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "solver tolerance must be finite and >= 0 (got %g)",
                       o->tolerance);
    if (o->max_iterations < 1 || o->check_every < 1 || o->chebyshev_delay < 0)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "solver max_iterations and check_every must be >= 1, chebyshev_delay >= 0");
    if (!(o->chebyshev_rho >= 0.0 && o->chebyshev_rho < 1.0))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "chebyshev_rho must be in [0, 1) (got %g)",
                       o->chebyshev_rho);
    if (!(o->chebyshev_gamma > 0.0 && o->chebyshev_gamma <= 1.0))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "chebyshev_gamma must be in (0, 1] (got %g)",
                       o->chebyshev_gamma);
    if (!(o->divergence_factor > 1.0) || !isfinite(o->divergence_factor))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "divergence_factor must be finite and > 1 (got %g)",
                       o->divergence_factor);
    return WC_OK;
}

wc_status wc_solver_create(wc_solver** out, const wc_model* m, const wc_solver_opts* opts, int want_direct,
                             const wc_allocator* alloc, wc_diag* diag) {
    if (!out || !m || !opts) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "wc_solver_create: NULL argument");
    *out = NULL;
    if (m->n_particles < 1 || m->pattern.n_rows != m->n_particles)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "wc_solver_create: model has no particles or no pattern");
    wc_status st = check_opts(opts, diag);
    if (st != WC_OK) return st;
    wc_solver* s = WC_NEW(alloc, wc_solver, 1);
    if (!s) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "solver workspace");
    if (alloc) s->alloc = *alloc;
    s->m = m;
    s->opts = *opts;
    s->n = m->n_particles;
    s->n_chunks = (s->n + WCS_CHUNK - 1) / WCS_CHUNK;
    s->partial = WC_NEW(&s->alloc, double, 2 * (size_t)s->n_chunks);
    s->Dinv = WC_NEW(&s->alloc, double, 9 * (size_t)s->n);
    s->r = WC_NEW(&s->alloc, double, 3 * (size_t)s->n);
    s->c = WC_NEW(&s->alloc, double, 3 * (size_t)s->n);
    s->q = WC_NEW(&s->alloc, double, 3 * (size_t)s->n);
    s->t = WC_NEW(&s->alloc, double, 3 * (size_t)s->n);
    if (!s->partial || !s->Dinv || !s->r || !s->c || !s->q || !s->t) {
        wc_solver_destroy(s);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "solver vectors for %d particles", m->n_particles);
    }
    if (opts->preconditioner == WC_PRECOND_AMG) {
        st = wc_amg_create(&s->amg, m, NULL, &s->alloc, diag);
        if (st != WC_OK) {
            wc_solver_destroy(s);
            return st;
        }
    }
    if (want_direct || opts->type == WC_SOLVER_DIRECT) {
        st = wcs_direct_create(s, diag);
        if (st != WC_OK) {
            wc_solver_destroy(s);
            return st;
        }
    }
    *out = s;
    return WC_OK;
}

void wc_solver_set_positions(wc_solver* s, const double* x) {
    if (s && s->amg) s->amg->pos = x;
}

void wc_solver_set_residual_floor(wc_solver* s, double floor) {
    if (s && floor >= 0.0 && isfinite(floor)) s->residual_floor = floor;
}

double wc_solver_residual_floor(const wc_solver* s) {
    return s ? s->residual_floor : 0.0;
}

void wc_solver_set_tolerance(wc_solver* s, double tolerance) {
    if (s && tolerance >= 0.0 && isfinite(tolerance)) s->opts.tolerance = tolerance;
}

double wc_solver_tolerance(const wc_solver* s) {
    return s ? s->opts.tolerance : 0.0;
}

wc_status wc_solver_set_coupling(wc_solver* s, const wc_coupling* c, int capacity, wc_diag* diag) {
    if (!s) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "wc_solver_set_coupling: NULL solver");
    s->coupling = c;
    return s->amg ? wc_amg_set_coupling(s->amg, c, capacity, diag) : WC_OK;
}

void wc_solver_destroy(wc_solver* s) {
    if (!s) return;
    wcs_direct_destroy(s);
    wc_amg_destroy(s->amg);
    wc_allocator a = s->alloc;
    wc_free(&a, s->partial);
    wc_free(&a, s->Dinv);
    wc_free(&a, s->r);
    wc_free(&a, s->c);
    wc_free(&a, s->q);
    wc_free(&a, s->t);
    wc_free(&a, s);
}

void wc_solver_invalidate_rho(wc_solver* s) {
    if (s) s->rho_valid = 0;
}

int wc_solver_rho_cache(const wc_solver* s, double* rho) {
    if (!s || !s->rho_valid) return 0;
    if (rho) *rho = s->rho;
    return 1;
}

void wc_solver_set_rho_cache(wc_solver* s, int valid, double rho) {
    if (!s) return;
    s->rho_valid = valid ? 1 : 0;
    s->rho = valid ? rho : 0.0;
}

double wc_solver_estimate_rho(wc_solver* s, const double* A_val, const wc_filter* f, wc_par* par) {
    if (!s || !A_val || !f || !par || f->n != s->n) return 0.0;
    if (s->rho_valid) return s->rho;
    wcs_build_precond(s, A_val, f, par);
    s->rho = wcs_estimate_rho(s, A_val, f, par);
    s->rho_valid = 1;
    return s->rho;
}

wc_status wc_solve(wc_solver* s, wc_solver_type type, const double* A_val, const double* b, const wc_filter* f,
                     double* dv, wc_par* par, wc_solve_result* res) {
    wc_solve_result local;
    if (!res) res = &local;
    memset(res, 0, sizeof *res);
    res->solver = type;
    if (!s || !A_val || !b || !f || !dv || !par || f->n != s->n || !(type >= 0 && type < WC_SOLVER_COUNT))
        return res->status = WC_ERROR_INVALID_ARGUMENT;
    if (type == WC_SOLVER_DIRECT && !s->direct) return res->status = WC_ERROR_CALL_ORDER;
    wc_status st = WC_OK;
    if (wcs_begin(s, A_val, b, f, dv, par, res, &st)) return res->status = st;
    switch (type) {
    case WC_SOLVER_PCG: st = wcs_solve_pcg(s, A_val, b, f, dv, par, res); break;
    case WC_SOLVER_JACOBI: st = wcs_solve_jacobi(s, A_val, b, f, dv, par, res, 0); break;
    case WC_SOLVER_CHEBYSHEV: st = wcs_solve_jacobi(s, A_val, b, f, dv, par, res, 1); break;
    default: st = wcs_solve_direct(s, A_val, b, f, dv, par, res); break;
    }
    /* the last guard of the contract: never hand back non-finite values */
    if (!wcs_all_finite(dv, s->n)) {
        wcs_fallback(f, dv, s->n);
        if (st == WC_OK) st = type == WC_SOLVER_DIRECT ? WC_ERROR_FACTORIZATION : WC_ERROR_SOLVER_DIVERGED;
    }
    res->status = st;
    return st;
}

/* ---- shared kernels ---- */

double wcs_sum(const wc_solver* s, int slot) {
    const double* p = s->partial + (size_t)slot * s->n_chunks;
    double sum = 0.0;
    for (int c = 0; c < s->n_chunks; ++c) sum += p[c];
    return sum;
}

void wcs_project_block(const wc_filter* f, int i, int j, const double* Aij, double* out) {
    const double* Si = f->S + 9 * i;
    const double* Sj = f->S + 9 * j;
    double tmp[9];
    if (f->ndof[j] == 0) memcpy(tmp, Aij, sizeof tmp);
    else m3_mul(tmp, Aij, Sj);
    if (f->ndof[i] == 0) memcpy(out, tmp, sizeof tmp);
    else m3_mul(out, Si, tmp);
    if (i == j && f->ndof[i] != 0)
        for (int k = 0; k < 9; ++k) out[k] += ((k % 4 == 0) ? 1.0 : 0.0) - Si[k];
}

void wcs_build_precond(wc_solver* s, const double* A, const wc_filter* f, wc_par* par) {
    const wc_bsr_pattern* p = &s->m->pattern;
    double* Dinv = s->Dinv;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(s->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double D[9];
            wcs_project_block(f, i, i, A + 9 * (size_t)p->diag[i], D);
            if (m3_inverse(Dinv + 9 * i, D) == 0.0) m3_identity(Dinv + 9 * i, 1.0);
        }
    }
}

void wcs_mul(wc_solver* s, const double* A, const double* x, double* y, wc_par* par) {
    wc_bsr_mul(&s->m->pattern, A, x, y, par);
    wc_coupling_mul_offdiag_add(s->coupling, 1.0, x, y);
}

void wcs_residual(wc_solver* s, const double* A, const double* b, const double* x, double* y, wc_par* par) {
    wc_bsr_residual(&s->m->pattern, A, b, x, y, par);
    wc_coupling_mul_offdiag_add(s->coupling, -1.0, x, y);
}

double wcs_filtered_residual(wc_solver* s, const double* A, const double* b, const wc_filter* f, const double* x,
                             double* out, wc_par* par) {
    wcs_residual(s, A, b, x, out, par);
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int lo, hi;
            wcs_chunk_rows(s, c, &lo, &hi);
            double acc = 0.0;
            for (int i = lo; i < hi; ++i) {
                double* o = out + 3 * i;
                wc_filter_apply(f, i, o, o);
                acc += v3_dot(o, o);
            }
            s->partial[c] = acc;
        }
    }
    return wcs_sum(s, 0);
}

void wcs_project(const wc_filter* f, double* dv, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(f->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            if (f->ndof[i] == 0) continue;
            double* d = dv + 3 * i;
            wc_filter_apply(f, i, d, d);
            v3_add(d, d, f->z + 3 * i);
        }
    }
}

int wcs_all_finite(const double* v, int n) {
    int ok = 1;
    for (int k = 0; k < 3 * n; ++k) ok &= isfinite(v[k]) ? 1 : 0;
    return ok;
}

void wcs_fallback(const wc_filter* f, double* dv, int n) {
    for (int k = 0; k < 3 * n; ++k) dv[k] = isfinite(f->z[k]) ? f->z[k] : 0.0;
}

int wcs_begin(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv, wc_par* par,
              wc_solve_result* res, wc_status* status) {
    double rr0 = wcs_filtered_residual(s, A, b, f, f->z, s->r, par);
    res->residual0 = sqrt(rr0);
    res->scale = fmax(res->residual0, s->residual_floor);
    *status = WC_OK;
    if (!isfinite(rr0)) {
        wcs_fallback(f, dv, s->n);
        res->residual = INFINITY;
        *status = res->solver == WC_SOLVER_DIRECT ? WC_ERROR_FACTORIZATION : WC_ERROR_SOLVER_DIVERGED;
        return 1;
    }
    if (rr0 == 0.0) {   /* S (b - A z) = 0: y = 0 solves the projected system, dv = z */
        wcs_fallback(f, dv, s->n);
        res->converged = 1;
        res->iterations = 0;
        return 1;
    }
    if (!wcs_all_finite(dv, s->n)) wcs_fallback(f, dv, s->n);   /* unusable initial guess */
    wcs_project(f, dv, par);
    return 0;
}
