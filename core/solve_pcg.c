/* Modified preconditioned conjugate gradient of Baraff & Witkin (1998) section 5.3: CG on the
 * projected system with every search direction filtered (c = S (P^{-1} r + beta c)), so the
 * iterate stays in z + range(S). Preconditioner: the filtered block-diagonal
 * D~_i^{-1} = (S_i A_ii S_i + I - S_i)^{-1} in place of B&W's diagonal one, or the multigrid
 * V-cycle (amg.h); the direct solver runs the same iterations with its factor (wcs_pcg_run).
 *
 * Stopping: ||r||_2 <= tolerance max(||S (b - A z)||_2, floor) (solve.h) with r the recursively
 * updated residual. When that test passes, the true residual S (b - A dv) is computed; if it is
 * above the tolerance (the recursion drifted) r is replaced by it and CG restarts from dv, until
 * the cap. The reported residual is always the true one of the returned dv.
 *
 * Divergence: a non-finite value, a residual above divergence_factor x max(initial residual of
 * z, of the initial guess), or c^T S A c <= 0 (P not positive definite along c) stop the
 * iteration with SOLVER_DIVERGED; dv keeps the last iterate (finite: alpha is checked before it
 * is applied). */
#include <math.h>
#include "clock.h"
#include "solve_pcg.h"
#include "vec3.h"

/* wcs_pcg_update with the multigrid preconditioner: t = V-cycle(r). */
static void pcg_update_amg(wc_solver* s, double alpha, double* dv, double* delta, double* rr, wc_par* par) {
    const double *c = s->c, *q = s->q;
    double *r = s->r, *t = s->t;
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int k = c0; k < c1; ++k) {
            int lo, hi;
            wcs_chunk_rows(s, k, &lo, &hi);
            double acc_r = 0.0;
            for (int i = lo; i < hi; ++i) {
                if (alpha != 0.0) {
                    if (dv) v3_axpy(dv + 3 * i, alpha, c + 3 * i);
                    v3_axpy(r + 3 * i, -alpha, q + 3 * i);
                }
                acc_r += v3_dot(r + 3 * i, r + 3 * i);
            }
            s->partial[k] = acc_r;
        }
    }
    *rr = wcs_sum(s, 0);
    wc_amg_apply(s->amg, r, t, par);
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int k = c0; k < c1; ++k) {
            int lo, hi;
            wcs_chunk_rows(s, k, &lo, &hi);
            double acc_d = 0.0;
            for (int i = lo; i < hi; ++i) acc_d += v3_dot(r + 3 * i, t + 3 * i);
            s->partial[k] = acc_d;
        }
    }
    *delta = wcs_sum(s, 0);
}

wc_status wcs_solve_pcg(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                        wc_par* par, wc_solve_result* res) {
    const int amg = s->amg && s->opts.preconditioner == WC_PRECOND_AMG;
    double t_setup = wc_now_ms();
    if (amg) wc_amg_setup(s->amg, A, f, par);
    else wcs_build_precond(s, A, f, par);
    res->setup_ms += wc_now_ms() - t_setup;
    wc_status st = wcs_pcg_run(s, A, b, f, dv, par, res, amg ? pcg_update_amg : wcs_pcg_update);
    if (amg && s->amg->bounds_reused && (st != WC_OK || !res->converged)) {
        /* the reused eigenvalue bounds may have fallen short of this matrix's (the smoother then
           amplifies the modes above them and the V-cycle can turn indefinite), or the kept coarse
           levels (hold_coarse) may serve this system poorly: a fresh setup, and
           PCG again, from the last iterate when it merely ran out of iterations, from z (the
           constraints' values, as a solve without a guess starts) when it diverged */
        int it = res->iterations, hold = s->amg->hold_bounds, hold_coarse = s->amg->hold_coarse;
        if (st != WC_OK) wcs_fallback(f, dv, s->n);
        ++s->amg->bound_fallbacks;
        t_setup = wc_now_ms();
        s->amg->hold_bounds = 0;
        s->amg->hold_coarse = 0;
        wc_amg_setup(s->amg, A, f, par);
        s->amg->hold_bounds = hold;
        s->amg->hold_coarse = hold_coarse;
        res->setup_ms += wc_now_ms() - t_setup;
        st = wcs_pcg_run(s, A, b, f, dv, par, res, pcg_update_amg);
        res->iterations += it;
    }
    return st;
}

wc_status wcs_pcg_run(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv, wc_par* par,
                      wc_solve_result* res, wcs_pcg_update_fn update) {
    const wc_solver_opts* o = &s->opts;
    const double res0 = res->residual0, goal = o->tolerance * res->scale;
    wc_status st = WC_OK;
    int it = 0, converged = 0;
    double delta, rr, rr_final = -1.0;

    rr = wcs_filtered_residual(s, A, b, f, dv, s->r, par);
    const double limit = o->divergence_factor * fmax(res0, sqrt(rr));
    update(s, 0.0, dv, &delta, &rr, par);
    wcs_pcg_direction(s, f, 0.0, par);
    for (;;) {
        if (!isfinite(rr) || !(delta >= 0.0) || !isfinite(delta) || sqrt(rr) > limit) {
            st = WC_ERROR_SOLVER_DIVERGED;
            break;
        }
        if (sqrt(rr) <= goal) {
            /* confirm with the true residual; on drift restart from it */
            wcs_project(f, dv, par);
            double rt = wcs_filtered_residual(s, A, b, f, dv, s->q, par);
            if (sqrt(rt) <= goal) {
                converged = 1;
                rr_final = rt;
                break;
            }
            if (it >= o->max_iterations) break;
            for (int k = 0; k < 3 * s->n; ++k) s->r[k] = s->q[k];
            update(s, 0.0, dv, &delta, &rr, par);
            wcs_pcg_direction(s, f, 0.0, par);
            continue;
        }
        if (it >= o->max_iterations) break;
        wcs_mul(s, A, s->c, s->q, par);
        double cq = wcs_pcg_filter_dot(s, f, s->c, s->q, par);
        double alpha = delta / cq;
        if (!(cq > 0.0) || !isfinite(alpha)) {
            st = WC_ERROR_SOLVER_DIVERGED;
            break;
        }
        double delta_old = delta;
        update(s, alpha, dv, &delta, &rr, par);
        ++it;
        wcs_pcg_direction(s, f, delta / delta_old, par);
    }
    if (!converged) {
        wcs_project(f, dv, par);
        rr_final = wcs_filtered_residual(s, A, b, f, dv, s->q, par);
    }
    res->iterations = it;
    res->residual = sqrt(rr_final) / res->scale;
    res->converged = converged || res->residual <= o->tolerance;
    if (st == WC_OK && !isfinite(res->residual)) st = WC_ERROR_SOLVER_DIVERGED;
    return st;
}
