/* BDF2 history and the per-substep (TR-BDF2: per-stage) integrator coefficients (formulas and
 * rules in bdf2.h). */
#include "bdf2.h"
#include <string.h>
#include "vec3.h"

#define TR_C2 WC_TRBDF2_C2

static void trbdf2_begin(const wc_state* s, double h, int stage, wc_integ* ig) {
    const double g = WC_TRBDF2_GAMMA;
    ig->bdf2 = 0;
    ig->stage = stage;
    ig->xb_form = 1;
    ig->h = stage == 1 ? g * h : (1.0 - g) * h;
    ig->he = stage == 1 ? 0.5 * g * h : (1.0 - g) / (2.0 - g) * h;
    ig->xb = s->xb;
    ig->vstar = s->vstar;
    ig->mom = s->mom;
    ig->air_implicit = s->model->n_tris > 0 && (s->def.air.normal_drag != 0.0 || s->def.air.tangent_drag != 0.0);
}

void wc_integ_solved(wc_state* s, const wc_integ* ig) {
    if (ig->stage != 1) return;
    memcpy(s->xs, s->x, 3 * (size_t)s->model->n_particles * sizeof(double));
}

void wc_integ_begin_stage2(wc_state* s, double h, wc_integ* ig) { trbdf2_begin(s, h, 2, ig); }

void wc_integ_coefficients(const wc_state* s, double h, int stage, wc_integ* ig) {
    if (s->def.integrator == WC_INTEGRATOR_TRBDF2) {
        trbdf2_begin(s, h, stage == 2 ? 2 : 1, ig);
        return;
    }
    ig->stage = 0;
    ig->xb_form = 0;
    ig->air_implicit = 0;
    int bdf2_cloth = s->def.integrator == WC_INTEGRATOR_BDF2;
    ig->bdf2 = bdf2_cloth && s->hist_valid && s->hist_h == h;
    ig->h = h;
    ig->he = ig->bdf2 ? 2.0 * h / 3.0 : h;
    ig->xb_form = ig->bdf2;
    ig->xb = s->x;
    ig->vstar = s->v;
    ig->mom = NULL;
}

void wc_integ_begin(wc_state* s, double h, wc_integ* ig) {
    wc_integ_coefficients(s, h, 1, ig);
    if (s->def.integrator == WC_INTEGRATOR_BDF2) memcpy(s->xs, s->x, 3 * (size_t)s->model->n_particles * sizeof(double));
}

void wc_integ_base(const wc_state* s, const wc_integ* ig, int i, double* out) {
    const double* x = s->x + 3 * i;
    const double* xp = s->x_prev + 3 * i;
    if (ig->stage == 1) {
        for (int c = 0; c < 3; ++c) out[c] = x[c] + ig->he * s->v[3 * i + c];
        return;
    }
    if (ig->stage == 2) {
        for (int c = 0; c < 3; ++c) out[c] = x[c] + TR_C2 * (x[c] - xp[c]);
        return;
    }
    for (int c = 0; c < 3; ++c) out[c] = ig->bdf2 ? x[c] + (x[c] - xp[c]) / 3.0 : x[c];
}

/* TR-BDF2's xb, vstar, mom after the stage's contact correction (bdf2.h). */
static void trbdf2_prepare(wc_state* s, const wc_integ* ig) {
    int n3 = 3 * s->model->n_particles;
    const double he = ig->he;
    if (ig->stage == 1) {
        for (int k = 0; k < n3; ++k) {
            s->xb[k] = s->x[k] + he * s->v[k];
            s->vstar[k] = 2.0 * s->v[k];
            s->mom[k] = 0.0;   /* wc_integ_forces, after the assembly */
        }
        memcpy(s->x_prev, s->x, (size_t)n3 * sizeof(double));
        memcpy(s->v_prev, s->v, (size_t)n3 * sizeof(double));
        memset(s->stage1_impulse, 0, (size_t)n3 * sizeof(double));   /* a stage 1 without contacts */
        return;
    }
    for (int k = 0; k < n3; ++k) {
        double back = TR_C2 * (s->xs[k] - s->x_prev[k]);   /* c2 (x_g - x_n), x_g as stage 1 solved it */
        s->xb[k] = s->x[k] + back;
        s->vstar[k] = s->v[k] + back / he;
        s->mom[k] = TR_C2 * (s->v[k] - s->v_prev[k]);     /* c2 (v_g - v_n), v_g corrected */
    }
}

/* TR-BDF2's collider contacts in the xb form (bdf2.h "Contacts"): a particle in contact moves along
 * the normals as the collider does over the stage, plus the gap begin left it to close, and ends
 * with the collider's normal velocity. */
void wc_integ_contacts(wc_state* s, const wc_integ* ig) {
    const wc_contacts* ct = &s->contacts;
    if (!ig->stage || !ct->vel || ct->active == 0) return;
    const double he = ig->he, h = ig->h;
    for (int i = 0; i < s->model->n_particles; ++i) {
        const int* cid = ct->collider + 2 * i;
        if (cid[0] < 0) continue;
        int two = cid[1] >= 0;
        const double* n = ct->normal + 6 * i;
        const double* vc = ct->vel + 6 * i;
        double* v = s->v + 3 * i;
        const double* x = s->x + 3 * i;
        double* xb = s->xb + 3 * i;
        double* z = s->filter.z + 3 * i;
        double a[2] = {0.0, 0.0}, gap[2] = {0.0, 0.0}, d[3], back[3];
        v3_sub(back, xb, x);
        for (int c = 0; c < 1 + two; ++c) {
            double vr[3];
            v3_sub(vr, v, vc + 3 * c);
            a[c] = -v3_dot(vr, n + 3 * c);                       /* the relative normal speed -> 0 */
            double close = -h * (v3_dot(z, n + 3 * c) - a[c]);   /* begin's z: -max(gap, 0) / h - vr.n */
            gap[c] = h * v3_dot(vc + 3 * c, n + 3 * c) - close - he * v3_dot(vc + 3 * c, n + 3 * c) -
                     v3_dot(back, n + 3 * c);
        }
        v3_span2(n, a[0], n + 3, a[1], two, d);
        v3_add(v, v, d);
        v3_span2(n, gap[0], n + 3, gap[1], two, d);
        v3_add(xb, xb, d);
        v3_zero(z);   /* v_new.n = vc.n: x_new = xb + he v_new lands on the shell */
        for (int c = 0; c < 3; ++c) {
            s->vstar[3 * i + c] = v[c] + (xb[c] - x[c]) / he;
            if (ig->stage == 1) s->v_prev[3 * i + c] = v[c];
            else s->mom[3 * i + c] = TR_C2 * (v[c] - s->v_prev[3 * i + c]);
        }
    }
}

int wc_integ_contact_impulses(wc_state* s, const wc_integ* ig) {
    if (!ig->stage) return 1;
    int n = s->model->n_particles;
    const int* cid = s->contacts.collider;
    if (ig->stage == 1) {
        for (int i = 0; i < n; ++i) {
            double* q = s->stage1_impulse + 3 * i;
            if (cid[2 * i] >= 0) v3_copy(q, s->r + 3 * i);
            else v3_zero(q);
        }
        return 0;
    }
    for (int k = 0; k < 3 * n; ++k) s->r[k] += s->stage1_impulse[k];
    return 1;
}

void wc_integ_forces(wc_state* s, const wc_integ* ig) {
    const wc_model* m = s->model;
    if (ig->air_implicit) {
        wc_air_lumped(m, s->x, &s->def.air, &s->par, s->air_lump);
        for (int i = 0; i < m->n_particles; ++i)
            m3_axpy(s->A + 9 * (size_t)m->pattern.diag[i], ig->he, s->air_lump + 9 * (size_t)i);
    }
    if (ig->stage != 1) return;
    for (int i = 0; i < m->n_particles; ++i) {
        double k = m->mass[i] > 0.0 ? ig->he / m->mass[i] : 0.0;
        for (int c = 0; c < 3; ++c) s->mom[3 * i + c] = k * s->f[3 * i + c];
    }
}

void wc_integ_prepare(wc_state* s, wc_integ* ig) {
    if (ig->stage) {
        trbdf2_prepare(s, ig);
        return;
    }
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
