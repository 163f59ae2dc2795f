/* Spectral radius of the iteration Chebyshev accelerates, G = I - gamma D~^{-1} P (under-relaxed
 * filtered block Jacobi), for wc_solver_estimate_rho.
 *
 * D~^{-1} P is self-adjoint in the D~ inner product, so its eigenvalues lambda are real and
 * positive (P SPD) and rho(G) = max(1 - gamma lambda_min, gamma lambda_max - 1). They are
 * estimated by Lanczos in that inner product, run as WCS_RHO_ITERATIONS steps of PCG (the same
 * steps, solve_pcg_steps.h, D~ preconditioner) on P y = g, g a fixed pseudo-random vector in
 * range(S): the CG coefficients give the Lanczos tridiagonal T (diag 1/alpha_j +
 * beta_{j-1}/alpha_{j-1}, off-diagonal sqrt(beta_{j-1})/alpha_{j-1}), whose extreme eigenvalues
 * (bisection on Sturm counts) are Ritz values inside [lambda_min, lambda_max]. Same cost as as
 * many power iterations (one matrix sweep each), far closer: on cloth systems the power-iteration
 * ratio creeps up like 1 - C/k whatever the true rho.
 *
 * On stiff cloth lambda_min is still unresolved after 20 steps (Ritz values approach it roughly
 * like C/k^2), and underestimating rho costs Chebyshev more than overestimating it (iterations
 * grow about like 2 sqrt(F) against sqrt(F) for a factor F on 1 - rho). So lambda_min is
 * extrapolated from the steps 15 and 20 with that C/k^2 model, and rho is clamped to
 * [Ritz value, WCS_RHO_MAX]: the cap 1 - 5e-4 is about the slowest rate a default solve
 * (tolerance 1e-4 within 300 iterations) can use: 1 - rho ~ (ln(1e4) / 300)^2 / 2.
 * The comparisons behind these choices: docs/design/solver.md, "Linear solvers". */
#include <math.h>
#include <stdint.h>
#include "solve_pcg_steps.h"
#include "solve_rho.h"
#include "vec3.h"

#define WCS_RHO_MAX 0.9995

/* Deterministic start component in [-0.5, 0.5) (splitmix64 of the index). */
static double start_value(uint64_t k) {
    uint64_t z = k + 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0) - 0.5;
}

/* Eigenvalues of the leading k x k block of the symmetric tridiagonal (a diagonal, b[j] coupling
 * j-1 and j) below x. */
static int sturm_count(const double* a, const double* b, int k, double x) {
    int count = 0;
    double d = 1.0;
    for (int j = 0; j < k; ++j) {
        d = a[j] - x - (j > 0 ? b[j] * b[j] / d : 0.0);
        if (d == 0.0) d = -1e-300;
        if (d < 0.0) ++count;
    }
    return count;
}

/* The `which`-th smallest eigenvalue (1-based) of the leading k x k block, in [lo, hi]. */
static double tridiag_eig(const double* a, const double* b, int k, int which, double lo, double hi) {
    for (int it = 0; it < 100 && hi - lo > 1e-15 * hi; ++it) {
        double mid = 0.5 * (lo + hi);
        if (sturm_count(a, b, k, mid) >= which) hi = mid;
        else lo = mid;
    }
    return 0.5 * (lo + hi);
}

/* rho(G) from eigenvalue bounds of D~^{-1} P */
static double rho_of(double gamma, double lmin, double lmax) {
    return fmax(1.0 - gamma * lmin, gamma * lmax - 1.0);
}

double wc_rho_from_lanczos(const double* alpha, const double* beta, int k, double gamma) {
    const int K = WCS_RHO_ITERATIONS, K_early = (3 * WCS_RHO_ITERATIONS) / 4;
    double ta[WCS_RHO_ITERATIONS], tb[WCS_RHO_ITERATIONS];
    if (k <= 0) return WCS_RHO_MAX;
    if (k > K) k = K;
    double hi = 0.0;
    for (int j = 0; j < k; ++j) {
        ta[j] = 1.0 / alpha[j] + (j > 0 ? beta[j - 1] / alpha[j - 1] : 0.0);
        tb[j] = j > 0 ? sqrt(beta[j - 1]) / alpha[j - 1] : 0.0;
    }
    for (int j = 0; j < k; ++j) hi = fmax(hi, ta[j] + fabs(tb[j]) + (j + 1 < k ? fabs(tb[j + 1]) : 0.0));
    double lmin = tridiag_eig(ta, tb, k, 1, 0.0, hi), lmax = tridiag_eig(ta, tb, k, k, 0.0, hi);
    double rho_ritz = rho_of(gamma, lmin, lmax), rho = rho_ritz;
    if (k == K) {   /* lambda_k = lambda_min + C / k^2 through the steps K_early and K */
        double le = tridiag_eig(ta, tb, K_early, 1, 0.0, hi);
        double w = (1.0 / (K * K)) / (1.0 / (K_early * K_early) - 1.0 / (K * K));
        rho = rho_of(gamma, lmin - w * (le - lmin), lmax);
    }
    if (!isfinite(rho)) return WCS_RHO_MAX;
    return fmax(fmin(rho_ritz, WCS_RHO_MAX), fmin(rho, WCS_RHO_MAX));
}

double wcs_estimate_rho(wc_solver* s, const double* A, const wc_filter* f, wc_par* par) {
    const double gamma = s->opts.chebyshev_gamma;
    const int K = WCS_RHO_ITERATIONS;
    double alpha[WCS_RHO_ITERATIONS], beta[WCS_RHO_ITERATIONS];

    /* r = g = S (pseudo-random), t = D~^{-1} r, c = S t */
    for (int i = 0; i < s->n; ++i) {
        double v[3];
        for (int k = 0; k < 3; ++k) v[k] = start_value(3 * (uint64_t)i + (uint64_t)k);
        wc_filter_apply(f, i, v, s->r + 3 * i);
    }
    double delta, rr;
    wcs_pcg_update(s, 0.0, NULL, &delta, &rr, par);
    if (rr == 0.0) return 0.0;   /* no free direction anywhere */
    if (!(delta > 0.0) || !isfinite(delta)) return WCS_RHO_MAX;
    wcs_pcg_direction(s, f, 0.0, par);
    const double delta0 = delta;
    int k = 0;
    while (k < K) {
        wcs_mul(s, A, s->c, s->q, par);
        double cq = wcs_pcg_filter_dot(s, f, s->c, s->q, par);
        if (!(cq > 0.0) || !isfinite(cq)) return WCS_RHO_MAX;   /* P not positive definite */
        double delta_old = delta;
        alpha[k] = delta / cq;
        wcs_pcg_update(s, alpha[k], NULL, &delta, &rr, par);
        beta[k] = delta / delta_old;
        ++k;
        /* the Krylov space is (numerically) exhausted: T's eigenvalues are exact */
        if (!(delta > 1e-28 * delta0) || !isfinite(delta)) break;
        wcs_pcg_direction(s, f, beta[k - 1], par);
    }
    return wc_rho_from_lanczos(alpha, beta, k, gamma);
}
