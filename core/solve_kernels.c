/* The kernels every linear solver shares (solve_kernels.h): the filtered block-diagonal
 * preconditioner, the operator with its couplings, the projected residual and the projection onto
 * the constraint space. */
#include <math.h>
#include <string.h>
#include "solve_kernels.h"
#include "vec3.h"

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

/* y += alpha (the couplings' off-diagonal blocks) x: on the threads through the row index during
 * a solve (the same bits as the serial product, coupling.h), else serially. */
static void coupling_add(wc_solver* s, double alpha, const double* x, double* y, wc_par* par) {
    const wc_coupling* c = s->coupling;
    if (!c || c->n == 0) return;
    if (!s->coupling_rows_ok) {
        wc_coupling_mul_offdiag_add(c, alpha, x, y);
        return;
    }
    WC_PAR_REGION(par)
    {
        const int tid = wc_par_tid(), nt = wc_par_nt();
        int lo, hi;
        wc_par_range(c->n, tid, nt, &lo, &hi);
        wc_coupling_scale_terms(c, s->coupling_rows, alpha, x, lo, hi);
        WC_PAR_BARRIER();
        wc_par_range(s->n, tid, nt, &lo, &hi);
        wc_coupling_rows_add(c, s->coupling_rows, y, lo, hi);
    }
}

void wcs_mul(wc_solver* s, const double* A, const double* x, double* y, wc_par* par) {
    wc_bsr_mul(&s->m->pattern, A, x, y, par);
    coupling_add(s, 1.0, x, y, par);
}

void wcs_residual(wc_solver* s, const double* A, const double* b, const double* x, double* y, wc_par* par) {
    wc_bsr_residual(&s->m->pattern, A, b, x, y, par);
    coupling_add(s, -1.0, x, y, par);
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
