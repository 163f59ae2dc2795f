/* The linear solvers' front (solve.h): names and options, the workspace's create/destroy and
 * setters, the rho cache, and wc_solve, which starts every solve the same way and dispatches it
 * to PCG, Jacobi/Chebyshev or the direct solver. Nothing below calls back here. */
#include <math.h>
#include <string.h>
#include "precond_ic.h"
#include "solve_direct.h"
#include "solve_jacobi.h"
#include "solve_kernels.h"
#include "solve_pcg.h"
#include "solve_rho.h"

static const char* const solver_names[WC_SOLVER_COUNT] = {"pcg", "jacobi", "chebyshev", "direct"};

static const char* const precond_names[WC_PRECOND_COUNT] = {"block_jacobi", "amg", "ic0"};

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
    s->partial = WC_NEW(&s->alloc, double, 3 * (size_t)s->n_chunks);
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
    if (opts->preconditioner == WC_PRECOND_IC0 && wcs_ic_create(&s->ic, &m->pattern, &s->alloc) != WC_OK) {
        wc_solver_destroy(s);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "IC(0) factor for %d blocks", m->pattern.n_blocks);
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

void wc_solver_hold_bounds(wc_solver* s, int hold) {
    if (s && s->amg) s->amg->hold_bounds = hold != 0;
}

void wc_solver_carry_bounds(wc_solver* s, int carry) {
    if (s && s->amg) s->amg->carry_bounds = carry != 0;
}

void wc_solver_invalidate_bounds(wc_solver* s) {
    if (s) wc_amg_bounds_invalidate(s->amg);
}

void wc_solver_bounds_get(const wc_solver* s, wc_amg_bounds* b) {
    wc_amg_bounds_get(s ? s->amg : NULL, b);
}

void wc_solver_bounds_set(wc_solver* s, const wc_amg_bounds* b) {
    if (s) wc_amg_bounds_set(s->amg, b);
}

void wc_solver_hold_coarse(wc_solver* s, int hold) {
    if (s && s->amg) s->amg->hold_coarse = hold != 0;
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
    wc_coupling_rows_destroy(s->coupling_rows, &s->alloc);
    s->coupling_rows = NULL;
    s->coupling_rows_ok = 0;
    if (c && capacity >= 1 && !(s->coupling_rows = wc_coupling_rows_create(s->n, capacity, &s->alloc)))
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "wc_solver_set_coupling: row index for %d terms", capacity);
    return s->amg ? wc_amg_set_coupling(s->amg, c, capacity, diag) : WC_OK;
}

void wc_solver_destroy(wc_solver* s) {
    if (!s) return;
    wcs_direct_destroy(s);
    wc_amg_destroy(s->amg);
    wc_allocator a = s->alloc;
    wcs_ic_destroy(s->ic, &a);
    wc_coupling_rows_destroy(s->coupling_rows, &a);
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

/* Shared start of every solve: projects the initial guess (dv = z + S dv; a non-finite guess is
 * replaced by z), fills res->residual0 = ||S (b - A z)|| and res->scale and leaves S (b - A z) in
 * s->r. Returns 1 when the solve is already finished: a zero right-hand side (dv = z, residual 0)
 * or a non-finite one (dv = z, SOLVER_DIVERGED). */
static int begin(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv, wc_par* par,
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
    /* the couplings may have changed since the last solve: their row index again */
    s->coupling_rows_ok =
        s->coupling && s->coupling->n > 0 && wc_coupling_rows_build(s->coupling_rows, s->coupling);
    if (begin(s, A_val, b, f, dv, par, res, &st)) {
        s->coupling_rows_ok = 0;
        return res->status = st;
    }
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
    s->coupling_rows_ok = 0;
    res->status = st;
    return st;
}
