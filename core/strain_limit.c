/* Jacobi strain limiting over the stretch springs (see strain_limit.h).
 *
 * One pass: every stretch spring (a, b) of length l > L = (1 + limit) rest computes, along its
 * unit direction u (from a to b), the correction that would bring it back to L with each end
 * moving in proportion to its inverse mass restricted to its free directions:
 *     w_a = inv_mass_a u^T S_a u   (S from the filter: 0 for pinned particles, d d^T for a line
 *                                   pin, I - n n^T for a contact, I when free)
 *     c = (l - L) / (w_a + w_b),   a moves + inv_mass_a S_a u c,   b moves - inv_mass_b S_b u c
 * (exact along u; a spring whose both ends cannot move along u is skipped). scratch[s] holds
 * c u. Then each particle moves by the AVERAGE of the corrections of its incident stretch springs
 * that were too long (the average never overshoots where several springs pull the same
 * particle; a sum would), gathered by rows through the pattern's per-row spring lists, and its
 * velocity changes by the same amount / h. Passes stop early when no spring exceeds the limit.
 * Corrections are projected by S, so pinned particles, line pins and contact normals keep
 * their constraints; a particle pushed into a collider shell this way is not re-projected. */
#include "strain_limit.h"
#include <math.h>
#include "vec3.h"

/* Inverse mass and free-direction projection of particle i (S NULL: free). */
static double particle_w(const wc_model* m, const wc_filter* f, int i, const double** S) {
    *S = NULL;
    if (!f || f->ndof[i] == 0) return m->inv_mass[i];
    if (f->ndof[i] == 3) return 0.0;
    *S = f->S + 9 * i;
    return m->inv_mass[i];
}

/* w u^T S u */
static double eff_w(double w, const double* S, const double* u) {
    if (!S || w == 0.0) return w;
    double su[3];
    m3_mulv(su, S, u);
    return w * v3_dot(u, su);
}

/* Strain of spring s; when above the limit, scratch[s] = c u, else 0. */
static double spring_pass(const wc_model* m, const wc_filter* f, double limit, const double* x, double* scratch,
                          int s, int correct) {
    const wc_spring* sp = &m->springs[s];
    double* out = scratch + 3 * s;
    v3_zero(out);
    double d[3];
    v3_sub(d, x + 3 * sp->b, x + 3 * sp->a);
    double l = v3_norm(d);
    double strain = (l - sp->rest) / sp->rest;
    double L = (1.0 + limit) * sp->rest;
    if (!correct || !(l > L)) return strain;
    const double *Sa, *Sb;
    double wa = particle_w(m, f, sp->a, &Sa), wb = particle_w(m, f, sp->b, &Sb);
    if (wa + wb == 0.0) return strain;
    double u[3];
    v3_scale(u, d, 1.0 / l);
    double wsum = eff_w(wa, Sa, u) + eff_w(wb, Sb, u);
    if (!(wsum > 1e-12 * (wa + wb))) return strain;
    v3_scale(out, u, (l - L) / wsum);
    return strain;
}

/* Move particle i by the average of its springs' corrections. */
static void gather(const wc_model* m, const wc_filter* f, const double* scratch, double h, double* x, double* v,
                   int i) {
    const wc_bsr_pattern* p = &m->pattern;
    int s0 = m->spring_type_start[WC_SPRING_STRETCH], s1 = m->spring_type_start[WC_SPRING_STRETCH + 1];
    const double* S;
    double w = particle_w(m, f, i, &S);
    if (w == 0.0) return;
    double sum[3] = {0.0, 0.0, 0.0};
    int cnt = 0;
    for (int e = p->row_spring_start[i]; e < p->row_spring_start[i + 1]; ++e) {
        int s = p->row_spring[e];
        if (s < s0 || s >= s1) continue;
        const double* c = scratch + 3 * s;
        if (c[0] == 0.0 && c[1] == 0.0 && c[2] == 0.0) continue;
        /* end a moves along +c u, end b along -c u */
        v3_axpy(sum, (double)p->row_spring_sign[e], c);
        ++cnt;
    }
    if (cnt == 0) return;
    double delta[3];
    v3_scale(sum, sum, w / cnt);
    if (S)
        m3_mulv(delta, S, sum);
    else
        v3_copy(delta, sum);
    v3_add(x + 3 * i, x + 3 * i, delta);
    if (v && h > 0.0) v3_axpy(v + 3 * i, 1.0 / h, delta);
}

double wc_strain_limit(const wc_model* m, const wc_filter* f, double limit, int passes, double h, double* x,
                       double* v, double* scratch, wc_par* par) {
    int s0 = m->spring_type_start[WC_SPRING_STRETCH], s1 = m->spring_type_start[WC_SPRING_STRETCH + 1];
    int ns = s1 - s0, n = m->n_particles;
    if (ns <= 0) return 0.0;
    if (passes < 0) passes = 0;
    double worst = 0.0;
    for (int pass = 0; pass <= passes; ++pass) {
        int correct = pass < passes, used = par->threads;
        WC_PAR_REGION(par)
        {
            int t = wc_par_tid(), nt = wc_par_nt(), lo, hi;
            if (t == 0) used = nt;
            wc_par_range(ns, t, nt, &lo, &hi);
            double mx = -HUGE_VAL;
            for (int s = s0 + lo; s < s0 + hi; ++s) {
                double st = spring_pass(m, f, limit, x, scratch, s, correct);
                if (st > mx) mx = st;
            }
            par->partial[8 * t] = mx;
        }
        worst = -HUGE_VAL;
        for (int t = 0; t < used; ++t)
            if (par->partial[8 * t] > worst) worst = par->partial[8 * t];
        if (!correct || !(worst > limit)) break;
        WC_PAR_REGION(par)
        {
            int lo, hi;
            wc_par_range(n, wc_par_tid(), wc_par_nt(), &lo, &hi);
            for (int i = lo; i < hi; ++i) gather(m, f, scratch, h, x, v, i);
        }
    }
    return worst;
}
