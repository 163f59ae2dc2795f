/* Off-pattern rank-one couplings of the implicit system (coupling.h). */
#include "coupling.h"
#include "vec3.h"

void wc_coupling_mul_offdiag_add(const wc_coupling* c, double alpha, const double* x, double* y) {
    if (!c) return;
    for (int k = 0; k < c->n; ++k) {
        const wc_coupling_term* t = &c->t[k];
        if (!(t->c > 0.0)) continue;
        double s[4], sum = 0.0;
        for (int a = 0; a < t->cnt; ++a) {
            s[a] = t->w[a] * v3_dot(t->n, x + 3 * t->p[a]);
            sum += s[a];
        }
        /* row a: c w_a n (sum_b w_b n.x_b - w_a n.x_a) */
        for (int a = 0; a < t->cnt; ++a) v3_axpy(y + 3 * t->p[a], alpha * t->c * t->w[a] * (sum - s[a]), t->n);
    }
}

int wc_coupling_active(const wc_coupling* c) {
    int k = 0;
    if (c)
        for (int i = 0; i < c->n; ++i) k += c->t[i].c > 0.0;
    return k;
}
