/* BDF2 history and the per-substep integrator coefficients (formulas and rules in bdf2.h). */
#include "bdf2.h"
#include <string.h>

void wc_integ_begin(wc_state* s, double h, wc_integ* ig) {
    int bdf2_cloth = s->def.integrator == WC_INTEGRATOR_BDF2;
    ig->bdf2 = bdf2_cloth && s->hist_valid && s->hist_h == h;
    ig->h = h;
    ig->he = ig->bdf2 ? 2.0 * h / 3.0 : h;
    ig->xb = s->x;
    ig->vstar = s->v;
    ig->mom = NULL;
    if (bdf2_cloth) memcpy(s->xs, s->x, 3 * (size_t)s->model->n_particles * sizeof(double));
}

void wc_integ_base(const wc_state* s, const wc_integ* ig, int i, double* out) {
    const double* x = s->x + 3 * i;
    const double* xp = s->x_prev + 3 * i;
    for (int c = 0; c < 3; ++c) out[c] = ig->bdf2 ? x[c] + (x[c] - xp[c]) / 3.0 : x[c];
}

void wc_integ_prepare(wc_state* s, wc_integ* ig) {
    if (s->def.integrator != WC_INTEGRATOR_BDF2) return;
    int n3 = 3 * s->model->n_particles;
    if (ig->bdf2) {
        const double inv2h = 1.0 / (2.0 * ig->h);
        for (int k = 0; k < n3; ++k) {
            double back = s->xs[k] - s->x_prev[k];      /* x_n - x_{n-1}, both uncorrected */
            s->xb[k] = s->x[k] + back / 3.0;
            s->vstar[k] = s->v[k] + back * inv2h;      /* v_n + (xb - x_n) / he */
            s->mom[k] = (s->v[k] - s->v_prev[k]) / 3.0;
        }
        ig->xb = s->xb;
        ig->vstar = s->vstar;
        ig->mom = s->mom;
    }
    memcpy(s->x_prev, s->x, (size_t)n3 * sizeof(double));
    memcpy(s->v_prev, s->v, (size_t)n3 * sizeof(double));
    s->hist_h = ig->h;
    s->hist_valid = 1;
}

void wc_integ_save(wc_state* s) {
    if (s->def.integrator != WC_INTEGRATOR_BDF2) return;
    size_t n3 = 3 * (size_t)s->model->n_particles * sizeof(double);
    s->hist_valid0 = s->hist_valid;
    s->hist_h0 = s->hist_h;
    if (s->hist_valid) {
        memcpy(s->x_prev0, s->x_prev, n3);
        memcpy(s->v_prev0, s->v_prev, n3);
    }
}

void wc_integ_restore(wc_state* s) {
    if (s->def.integrator != WC_INTEGRATOR_BDF2) return;
    size_t n3 = 3 * (size_t)s->model->n_particles * sizeof(double);
    s->hist_valid = s->hist_valid0;
    s->hist_h = s->hist_h0;
    if (s->hist_valid) {
        memcpy(s->x_prev, s->x_prev0, n3);
        memcpy(s->v_prev, s->v_prev0, n3);
    }
}
