/* The multigrid hierarchy's values for one system (amg.h), rebuilt by every solve with no
 * allocation: the projected fine operator, block-diagonal inverses and Gershgorin bounds, the
 * smoothed prolongators, T = A P, the Galerkin operators P^T A P and the coarsest factor. */
#include <math.h>
#include <string.h>
#include "amg.h"
#include "clock.h"
#include "vec3.h"

/* o += a^T b (3x3, row-major) */
static void m3_tmul_add(double* o, const double* a, const double* b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) o[3 * r + c] += a[r] * b[c] + a[3 + r] * b[3 + c] + a[6 + r] * b[6 + c];
}

/* o += a b */
static void m3_mul_add(double* o, const double* a, const double* b) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            o[3 * r + c] += a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}

/* Level 0: P^ = S A S + a (I - S), a_i = trace(A_ii) / 3 (amg.h). */
static void project_fine(wc_amg_level* L, const double* A, const wc_filter* f, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            const double* Si = f->S + 9 * i;
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int j = L->col[k];
                const double* Ak = A + 9 * (size_t)k;
                double* o = L->val + 9 * (size_t)k;
                if (f->ndof[i] == 0 && f->ndof[j] == 0) {
                    memcpy(o, Ak, 9 * sizeof(double));
                    continue;
                }
                double tmp[9];
                if (f->ndof[j] == 0) memcpy(tmp, Ak, sizeof tmp);
                else m3_mul(tmp, Ak, f->S + 9 * j);
                if (f->ndof[i] == 0) memcpy(o, tmp, sizeof tmp);
                else m3_mul(o, Si, tmp);
                if (i == j && f->ndof[i] != 0) {
                    double scale = (Ak[0] + Ak[4] + Ak[8]) / 3.0;
                    if (!(scale > 0) || !isfinite(scale)) scale = 1.0;
                    for (int q = 0; q < 9; ++q) o[q] += scale * (((q % 4) == 0 ? 1.0 : 0.0) - Si[q]);
                }
            }
        }
    }
}

/* Inverse block diagonal. */
static void diagonal(wc_amg_level* L, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* Di = L->Dinv + 9 * i;
            const double* Aii = L->val + 9 * (size_t)L->diag[i];
            if (m3_inverse(Di, Aii) == 0.0 || !isfinite(Di[0])) {
                double tr = (Aii[0] + Aii[4] + Aii[8]) / 3.0;
                m3_identity(Di, tr > 0 && isfinite(tr) ? 1.0 / tr : 1.0);
            }
        }
    }
}

/* lambda_max(D^-1 A) by power iterations from L->ev (kept for the next solve): each computes
 * t = A w, the Rayleigh quotient (w . A w) / (w . D w), and w <- D^-1 t / lambda. Sums per
 * chunk of WC_AMG_CHUNK rows, added in chunk order (the same on any thread count). */
static void largest_eigenvalue(wc_amg_level* L, int iterations, wc_par* par) {
    int n_chunks = (L->n + WC_AMG_CHUNK - 1) / WC_AMG_CHUNK;
    wc_amg_start_vector(L->ev, L->n);
    double lambda = 0.0;
    for (int it = 0; it < iterations; ++it) {
        const double* w = L->ev;
        double* next = L->x;
        WC_PAR_REGION(par)
        {
            int c0, c1;
            wc_par_range(n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
            for (int c = c0; c < c1; ++c) {
                int lo = c * WC_AMG_CHUNK, hi = lo + WC_AMG_CHUNK < L->n ? lo + WC_AMG_CHUNK : L->n;
                double num = 0.0, den = 0.0;
                for (int i = lo; i < hi; ++i) {
                    double t[3] = {0, 0, 0}, dw[3];
                    for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
                        m3_mulv_add(t, L->val + 9 * (size_t)k, w + 3 * L->col[k]);
                    m3_mulv(dw, L->val + 9 * (size_t)L->diag[i], w + 3 * i);
                    num += v3_dot(w + 3 * i, t);
                    den += v3_dot(w + 3 * i, dw);
                    m3_mulv(next + 3 * i, L->Dinv + 9 * i, t);
                }
                L->partial[2 * c] = num;
                L->partial[2 * c + 1] = den;
            }
        }
        double num = 0.0, den = 0.0;
        for (int c = 0; c < n_chunks; ++c) {
            num += L->partial[2 * c];
            den += L->partial[2 * c + 1];
        }
        double q = den > 0 ? num / den : 0.0;
        if (!(q > 0) || !isfinite(q)) break;
        lambda = q;
        /* the next iterate, scaled to stay near unit size (w's scale is arbitrary) */
        double scale = 1.0 / (lambda * sqrt(den / (3.0 * L->n)));
        if (!isfinite(scale) || !(scale > 0)) scale = 1.0;
        for (int k = 0; k < 3 * L->n; ++k) L->ev[k] = next[k] * scale;
    }
    L->bound = lambda > 0 ? WC_AMG_SAFETY * lambda : 2.0;
}

/* P = (I - w D^-1 A_F) P_tent: row i = I at agg(i), minus w D_i^-1 A_ij summed per agg(j) over
 * the strong blocks; weak blocks are lumped onto agg(i) (A_F's diagonal). */
static void prolongator(wc_amg_level* L, double weight, wc_par* par) {
    double w = weight / L->bound;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            double* row = L->p_val + 9 * (size_t)L->p_start[i];
            memset(row, 0, 9 * sizeof(double) * (size_t)(L->p_start[i + 1] - L->p_start[i]));
            double* self = L->p_val + 9 * (size_t)L->p_self[i];
            self[0] = self[4] = self[8] = 1.0;
            if (w == 0.0) continue;
            double WD[9];
            for (int q = 0; q < 9; ++q) WD[q] = -w * L->Dinv[9 * i + q];
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int e = L->a_to_p[k] >= 0 ? L->a_to_p[k] : L->p_self[i];
                m3_mul_add(L->p_val + 9 * (size_t)e, WD, L->val + 9 * (size_t)k);
            }
        }
    }
}

/* T = A P, then the next level's operator P^T T. */
static void galerkin(wc_amg_level* L, wc_amg_level* N, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(L->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            int t0 = L->t_start[i], t1 = L->t_start[i + 1];
            memset(L->t_val + 9 * (size_t)t0, 0, 9 * sizeof(double) * (size_t)(t1 - t0));
            for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k) {
                int j = L->col[k];
                const double* Ak = L->val + 9 * (size_t)k;
                for (int e = L->p_start[j]; e < L->p_start[j + 1]; ++e) {
                    int slot = wc_amg_find(L->t_col, t0, t1, L->p_col[e]);
                    m3_mul_add(L->t_val + 9 * (size_t)slot, Ak, L->p_val + 9 * (size_t)e);
                }
            }
        }
    }
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(N->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int I = lo; I < hi; ++I) {
            int c0 = N->row_start[I], c1 = N->row_start[I + 1];
            memset(N->val + 9 * (size_t)c0, 0, 9 * sizeof(double) * (size_t)(c1 - c0));
            for (int s = L->pt_start[I]; s < L->pt_start[I + 1]; ++s) {
                int i = L->pt_row[s];
                const double* Pe = L->p_val + 9 * (size_t)L->pt_entry[s];
                for (int k = L->t_start[i]; k < L->t_start[i + 1]; ++k) {
                    int slot = wc_amg_find(N->col, c0, c1, L->t_col[k]);
                    m3_tmul_add(N->val + 9 * (size_t)slot, Pe, L->t_val + 9 * (size_t)k);
                }
            }
        }
    }
}

/* Dense Cholesky of the coarsest operator (a pivot that is not positive gets 1: that unknown is
 * decoupled, which a semi-definite coarse operator's null directions are). */
static void coarse_factor(wc_amg* a) {
    const wc_amg_level* L = &a->lev[a->n_levels - 1];
    int d = a->coarse_dofs;
    double* M = a->coarse_L;
    memset(M, 0, sizeof(double) * (size_t)d * d);
    for (int i = 0; i < L->n; ++i)
        for (int k = L->row_start[i]; k < L->row_start[i + 1]; ++k)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c)
                    M[(size_t)(3 * i + r) * d + 3 * L->col[k] + c] = L->val[9 * (size_t)k + 3 * r + c];
    double scale = 0.0;
    for (int i = 0; i < d; ++i) scale = fmax(scale, fabs(M[(size_t)i * d + i]));
    for (int j = 0; j < d; ++j) {
        double* Rj = M + (size_t)j * d;
        double s = Rj[j];
        for (int k = 0; k < j; ++k) s -= Rj[k] * Rj[k];
        if (!(s > 1e-14 * scale)) {
            for (int k = 0; k < j; ++k) Rj[k] = 0.0;
            s = 1.0;
            for (int i = j + 1; i < d; ++i) M[(size_t)i * d + j] = 0.0; /* decouple the column too */
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

void wc_amg_setup(wc_amg* a, const double* A, const wc_filter* f, wc_par* par) {
    double t0 = wc_now_ms();
    project_fine(&a->lev[0], A, f, par);
    for (int l = 0; l + 1 < a->n_levels; ++l) {
        wc_amg_level *L = &a->lev[l], *N = &a->lev[l + 1];
        diagonal(L, par);
        largest_eigenvalue(L, a->opts.power_iterations, par);
        if (l == 0) L->bound *= a->fine_bound_scale; /* seams (amg.h, WC_AMG_SEAM_BOUND) */
        prolongator(L, a->opts.prolong_weight, par);
        galerkin(L, N, par);
    }
    if (a->coarse_dense) coarse_factor(a);
    else {
        diagonal(&a->lev[a->n_levels - 1], par);
        largest_eigenvalue(&a->lev[a->n_levels - 1], a->opts.power_iterations, par);
        if (a->n_levels == 1) a->lev[0].bound *= a->fine_bound_scale;
    }
    a->setup_ms = wc_now_ms() - t0;
}
