/* The steps of the modified PCG (solve_pcg_steps.h): each over a range of rows or chunks, and as
 * a region of its own for the Lanczos estimate of rho's. */
#include "solve_pcg_steps.h"
#include "vec3.h"

void wcs_pcg_filter_dot_chunks(wc_solver* s, const wc_filter* f, const double* c, double* q, int c0, int c1,
                               int slot) {
    for (int k = c0; k < c1; ++k) {
        int lo, hi;
        wcs_chunk_rows(s, k, &lo, &hi);
        double acc = 0.0;
        for (int i = lo; i < hi; ++i) {
            wc_filter_apply(f, i, q + 3 * i, q + 3 * i);
            acc += v3_dot(c + 3 * i, q + 3 * i);
        }
        s->partial[slot * s->n_chunks + k] = acc;
    }
}

void wcs_pcg_update_chunks(wc_solver* s, double alpha, double* dv, int jacobi, int c0, int c1, int rr_slot,
                           int delta_slot) {
    const double *c = s->c, *q = s->q, *Dinv = s->Dinv;
    double *r = s->r, *t = s->t;
    for (int k = c0; k < c1; ++k) {
        int lo, hi;
        wcs_chunk_rows(s, k, &lo, &hi);
        double acc_d = 0.0, acc_r = 0.0;
        for (int i = lo; i < hi; ++i) {
            if (alpha != 0.0) {
                if (dv) v3_axpy(dv + 3 * i, alpha, c + 3 * i);
                v3_axpy(r + 3 * i, -alpha, q + 3 * i);
            }
            if (jacobi) {
                m3_mulv(t + 3 * i, Dinv + 9 * i, r + 3 * i);
                acc_d += v3_dot(r + 3 * i, t + 3 * i);
            }
            acc_r += v3_dot(r + 3 * i, r + 3 * i);
        }
        s->partial[rr_slot * s->n_chunks + k] = acc_r;
        if (jacobi) s->partial[delta_slot * s->n_chunks + k] = acc_d;
    }
}

void wcs_pcg_direction_rows(wc_solver* s, const wc_filter* f, double beta, int lo, int hi) {
    double* c = s->c;
    const double* t = s->t;
    for (int i = lo; i < hi; ++i) {
        double v[3];
        if (beta != 0.0) {
            v3_scale(v, c + 3 * i, beta);
            v3_add(v, v, t + 3 * i);
        } else {
            v3_copy(v, t + 3 * i);
        }
        wc_filter_apply(f, i, v, c + 3 * i);
    }
}

double wcs_pcg_filter_dot(wc_solver* s, const wc_filter* f, const double* c, double* q, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        wcs_pcg_filter_dot_chunks(s, f, c, q, c0, c1, 0);
    }
    return wcs_sum(s, 0);
}

void wcs_pcg_update(wc_solver* s, double alpha, double* dv, double* delta, double* rr, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int c0, c1;
        wc_par_range(s->n_chunks, wc_par_tid(), wc_par_nt(), &c0, &c1);
        wcs_pcg_update_chunks(s, alpha, dv, 1, c0, c1, 1, 0);
    }
    *delta = wcs_sum(s, 0);
    *rr = wcs_sum(s, 1);
}

void wcs_pcg_direction(wc_solver* s, const wc_filter* f, double beta, wc_par* par) {
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(s->n, wc_par_tid(), wc_par_nt(), &lo, &hi);
        wcs_pcg_direction_rows(s, f, beta, lo, hi);
    }
}
