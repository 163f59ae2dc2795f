/* Backward-Euler system assembly by rows (formulas in assemble.h). Row i only reads its incident
 * springs (pattern.row_spring*) and writes its own blocks and entries, so rows run in parallel
 * without atomics and the result does not depend on the thread count.
 * For a spring with end blocks kx, kv (dF_a/dx_a, dF_a/dv_a) and J = h kv + h^2 kx:
 *   A(i,i) -= J at both ends, A(i,j) += J (since dF_i/dx_j = -dF_i/dx_i),
 *   (dF/dx v)_i = kx (v_i - v_j). */
#include "assemble.h"
#include "vec3.h"

void wc_assemble(const wc_model* m, const wc_spring_eval* se, const double* f_ext, const double* v, double h,
                 wc_par* par, double* A_val, double* b, double* f_total) {
    const wc_bsr_pattern* p = &m->pattern;
    const wc_spring* sp = m->springs;
    double h2 = h * h;
    WC_PAR_REGION(par)
    {
        int lo, hi;
        wc_par_range(m->n_particles, wc_par_tid(), wc_par_nt(), &lo, &hi);
        for (int i = lo; i < hi; ++i) {
            /* clear the row's blocks; the diagonal starts at M */
            for (int k = p->row_start[i]; k < p->row_start[i + 1]; ++k) m3_zero(A_val + 9 * k);
            double* D = A_val + 9 * p->diag[i];
            m3_identity(D, m->mass[i]);
            double f0[3], kv_acc[3] = {0, 0, 0};
            v3_copy(f0, f_ext + 3 * i);
            const double* vi = v + 3 * i;
            for (int k = p->row_spring_start[i]; k < p->row_spring_start[i + 1]; ++k) {
                int s = p->row_spring[k];
                const wc_spring_eval* e = se + s;
                int j = p->row_spring_sign[k] > 0 ? sp[s].b : sp[s].a;
                double J[9];
                for (int q = 0; q < 9; ++q) J[q] = h * e->kv[q] + h2 * e->kx[q];
                m3_axpy(D, -1.0, J);
                m3_axpy(A_val + 9 * p->row_spring_block[k], 1.0, J);
                v3_axpy(f0, (double)p->row_spring_sign[k], e->f);
                double dvij[3];
                v3_sub(dvij, vi, v + 3 * j);
                m3_mulv_add(kv_acc, e->kx, dvij);
            }
            double* bi = b + 3 * i;
            for (int q = 0; q < 3; ++q) bi[q] = h * (f0[q] + h * kv_acc[q]);
            if (f_total) v3_copy(f_total + 3 * i, f0);
        }
    }
}
