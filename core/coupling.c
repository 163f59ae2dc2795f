/* Off-pattern rank-one couplings of the implicit system (coupling.h). */
#include <string.h>
#include "coupling.h"
#include "vec3.h"

/* f[a] = alpha c w_a (sum_b w_b n.x_b - w_a n.x_a): row a of term t's product is f[a] n */
static void term_factors(const wc_coupling_term* t, double alpha, const double* x, double f[4]) {
    double s[4], sum = 0.0;
    for (int a = 0; a < t->cnt; ++a) {
        s[a] = t->w[a] * v3_dot(t->n, x + 3 * t->p[a]);
        sum += s[a];
    }
    for (int a = 0; a < t->cnt; ++a) f[a] = alpha * t->c * t->w[a] * (sum - s[a]);
}

void wc_coupling_mul_offdiag_add(const wc_coupling* c, double alpha, const double* x, double* y) {
    if (!c) return;
    for (int k = 0; k < c->n; ++k) {
        const wc_coupling_term* t = &c->t[k];
        if (!(t->c > 0.0)) continue;
        double f[4];
        term_factors(t, alpha, x, f);
        for (int a = 0; a < t->cnt; ++a) v3_axpy(y + 3 * t->p[a], f[a], t->n);
    }
}

int wc_coupling_active(const wc_coupling* c) {
    int k = 0;
    if (c)
        for (int i = 0; i < c->n; ++i) k += c->t[i].c > 0.0;
    return k;
}

wc_coupling_rows* wc_coupling_rows_create(int n_rows, int cap_terms, const wc_allocator* a) {
    if (n_rows < 1 || cap_terms < 1 || cap_terms > (1 << 28)) return NULL;
    wc_coupling_rows* r = WC_NEW(a, wc_coupling_rows, 1);
    if (!r) return NULL;
    r->n_rows = n_rows;
    r->cap_terms = cap_terms;
    r->row_start = WC_NEW(a, int, (size_t)n_rows + 1);
    r->slot = WC_NEW(a, int, 4 * (size_t)cap_terms);
    r->coef = WC_NEW(a, double, 4 * (size_t)cap_terms);
    if (!r->row_start || !r->slot || !r->coef) {
        wc_coupling_rows_destroy(r, a);
        return NULL;
    }
    return r;
}

void wc_coupling_rows_destroy(wc_coupling_rows* r, const wc_allocator* a) {
    if (!r) return;
    wc_free(a, r->row_start);
    wc_free(a, r->slot);
    wc_free(a, r->coef);
    wc_free(a, r);
}

int wc_coupling_rows_build(wc_coupling_rows* r, const wc_coupling* c) {
    if (!r || !c || c->n > r->cap_terms) return 0;
    int* start = r->row_start;
    const int n = r->n_rows;
    memset(start, 0, sizeof(int) * ((size_t)n + 1));
    for (int k = 0; k < c->n; ++k) { /* counts, row i's in start[i + 1] */
        const wc_coupling_term* t = &c->t[k];
        if (!(t->c > 0.0)) continue;
        if (t->cnt < 0 || t->cnt > 4) return 0;
        for (int a = 0; a < t->cnt; ++a) {
            if (t->p[a] < 0 || t->p[a] >= n) return 0;
            ++start[t->p[a] + 1];
        }
    }
    for (int i = 0; i < n; ++i) start[i + 1] += start[i];
    /* fill in term order with start[i] as row i's cursor (it ends at row i + 1's start), then
       shift the starts back one row */
    for (int k = 0; k < c->n; ++k) {
        const wc_coupling_term* t = &c->t[k];
        if (!(t->c > 0.0)) continue;
        for (int a = 0; a < t->cnt; ++a) r->slot[start[t->p[a]]++] = 4 * k + a;
    }
    for (int i = n; i > 0; --i) start[i] = start[i - 1];
    start[0] = 0;
    return 1;
}

void wc_coupling_scale_terms(const wc_coupling* c, wc_coupling_rows* r, double alpha, const double* x, int k0,
                             int k1) {
    for (int k = k0; k < k1; ++k) {
        const wc_coupling_term* t = &c->t[k];
        if (t->c > 0.0) term_factors(t, alpha, x, r->coef + 4 * (size_t)k);
    }
}

void wc_coupling_rows_add(const wc_coupling* c, const wc_coupling_rows* r, double* y, int i0, int i1) {
    const int* start = r->row_start;
    const int* slot = r->slot;
    const double* coef = r->coef;
    const wc_coupling_term* t = c->t;
    for (int i = i0; i < i1; ++i) {
        if (start[i] == start[i + 1]) continue;
        /* y_i in registers (the same additions, in the same order, as v3_axpy on y) */
        double y0 = y[3 * i], y1 = y[3 * i + 1], y2 = y[3 * i + 2];
        for (int e = start[i]; e < start[i + 1]; ++e) {
            const int sl = slot[e];
            const double f = coef[sl], *n = t[sl >> 2].n;
            y0 += f * n[0];
            y1 += f * n[1];
            y2 += f * n[2];
        }
        y[3 * i] = y0;
        y[3 * i + 1] = y1;
        y[3 * i + 2] = y2;
    }
}
