/* Block Jacobi and Chebyshev-accelerated block Jacobi on the projected system.
 *
 * Jacobi on P y = S (b - A z) with D~ = blockdiag(P): y += D~^{-1} (S (b - A z) - P y). With
 * dv = z + S y and y in range(S), S (b - A z) - P y = S (b - A dv), and D~^{-1} maps range(S)
 * onto itself, so the sweep on dv is  dv += D~^{-1} S (b - A dv)  (the increment is filtered once
 * more so that rounding adds nothing along constrained directions).
 *
 * Chebyshev (Wang 2015): the accelerated iteration is the under-relaxed sweep
 * J(dv) = dv + gamma D~^{-1} S (b - A dv), whose iteration matrix G = I - gamma D~^{-1} P has real
 * eigenvalues (D~^{-1} P is similar to the symmetric D~^{-1/2} P D~^{-1/2}):
 *     dv_{k+1} = J(dv_k)                                         k < delay (omega = 1)
 *     dv_{k+1} = omega_k (J(dv_k) - dv_{k-1}) + dv_{k-1}         omega_delay = 2 / (2 - rho^2),
 *                                                                omega_k = 4 / (4 - rho^2 omega_{k-1})
 * with rho = spectral radius of G (delay is at least 1: the recurrence needs dv_{k-1}).
 * Robustness choices:
 *  - gamma < 1 (0.9) keeps the negative end of G's spectrum, 1 - gamma lambda_max(D~^{-1} P),
 *    inside (-1, 1) even where plain block Jacobi (lambda_max near 2) barely converges.
 *  - rho, when not given, comes from wcs_estimate_rho (solve_rho.c: Lanczos, extrapolated,
 *    erring high and capped below 1, since an underestimate costs more than an overestimate).
 *    It is cached until wc_solver_invalidate_rho. A user-given chebyshev_rho is used as it is.
 *  - Modes of G outside (-1, 1) (Jacobi itself diverging: lambda_max(D~^{-1} P) > 2 / gamma, on
 *    systems far from block-diagonal dominance) are caught by the residual check: a residual
 *    above divergence_factor x max(initial residual of z, of the initial guess), or not finite,
 *    stops with SOLVER_DIVERGED; dv is the last checked iterate when finite, else z.
 * Per iteration: one matrix sweep and one vector pass; the residual norm is accumulated in that
 * pass only every check_every iterations. */
#include <math.h>
#include "solve_jacobi.h"
#include "solve_rho.h"
#include "vec3.h"

double wc_chebyshev_omega(int k, int delay, double rho, double omega) {
    if (k < delay) return 1.0;
    return k == delay ? 2.0 / (2.0 - rho * rho) : 4.0 / (4.0 - rho * rho * omega);
}

/* One sweep from x = dv_k: writes dv_{k+1} = omega (x + gamma D~^{-1} S (b - A x) - p) + p into p
 * (p holds dv_{k-1} on entry; omega == 1 ignores it). Returns ||S (b - A x)||^2 when check, else 0. */
static double sweep(wc_solver* s, const double* A, const double* b, const wc_filter* f, const double* x, double* p,
                    double gamma, double omega, int check, wc_par* par) {
    wcs_residual(s, A, b, x, s->r, par);
    const double* r = s->r;
    const double* Dinv = s->Dinv;
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        for (int c = c0; c < c1; ++c) {
            int lo, hi;
            wcs_chunk_rows(s, c, &lo, &hi);
            double acc = 0.0;
            for (int i = lo; i < hi; ++i) {
                double sr[3], d[3], nx[3];
                wc_filter_apply(f, i, r + 3 * i, sr);
                if (check) acc += v3_dot(sr, sr);
                m3_mulv(d, Dinv + 9 * i, sr);
                wc_filter_apply(f, i, d, d);
                const double* xi = x + 3 * i;
                double* pi = p + 3 * i;
                for (int k = 0; k < 3; ++k) nx[k] = xi[k] + gamma * d[k];
                if (omega == 1.0) v3_copy(pi, nx);
                else
                    for (int k = 0; k < 3; ++k) pi[k] = omega * (nx[k] - pi[k]) + pi[k];
            }
            s->partial[c] = acc;
        }
    }
    return check ? wcs_sum(s, 0) : 0.0;
}

wc_status wcs_solve_jacobi(wc_solver* s, const double* A, const double* b, const wc_filter* f, double* dv,
                             wc_par* par, wc_solve_result* res, int chebyshev) {
    const wc_solver_opts* o = &s->opts;
    const double res0 = res->residual0, goal = o->tolerance * res->scale;
    const double gamma = chebyshev ? o->chebyshev_gamma : 1.0;
    const int delay = o->chebyshev_delay > 1 ? o->chebyshev_delay : 1;
    wc_status st = WC_OK;

    wcs_build_precond(s, A, f, par);
    double rho = 0.0;
    if (chebyshev) {
        if (o->chebyshev_rho > 0.0) {
            rho = o->chebyshev_rho;
        } else {
            if (!s->rho_valid) {
                s->rho = wcs_estimate_rho(s, A, f, par);
                s->rho_valid = 1;
            }
            rho = s->rho;
        }
    }
    double *x = dv, *prev = s->t;
    double omega = 1.0, limit = o->divergence_factor * res0, rn = res0;
    int k = 0, converged = 0;
    for (;; ++k) {
        int check = (k % o->check_every == 0) || k >= o->max_iterations;
        if (chebyshev) omega = wc_chebyshev_omega(k, delay, rho, omega);
        double rr = sweep(s, A, b, f, x, prev, gamma, omega, check, par);
        if (check) {
            rn = sqrt(rr);
            if (k == 0) limit = o->divergence_factor * fmax(res0, rn);
            if (!isfinite(rn) || rn > limit) {
                st = WC_ERROR_SOLVER_DIVERGED;
                break;
            }
            if (rn <= goal) {
                converged = 1;
                break;
            }
            if (k >= o->max_iterations) break;
        }
        double* tmp = x;
        x = prev;
        prev = tmp;
    }
    /* x = dv_k, the iterate whose residual rn was measured */
    if (x != dv)
        for (int i = 0; i < 3 * s->n; ++i) dv[i] = x[i];
    res->iterations = k;
    res->converged = converged;
    if (!isfinite(rn) || !wcs_all_finite(dv, s->n)) {
        wcs_fallback(f, dv, s->n);   /* no finite iterate kept: dv = z, whose relative residual is 1 */
        res->residual = 1.0;
        return st;
    }
    wcs_project(f, dv, par);
    res->residual = rn / res->scale;
    return st;
}
