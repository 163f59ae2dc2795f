/* The energy judge's memo (energy_memo.h). */
#include "energy_memo.h"
#include <string.h>
#include "forces.h"
#include "state.h"
#include "vec3.h"

double wc_total_energy_xv(const wc_model* m, const double* x, const double* v, const double g[3], double seam_scale,
                          double* elastic) {
    double kin = 0.0;
    for (int i = 0; i < m->n_particles; ++i) kin += 0.5 * m->mass[i] * v3_dot(v + 3 * i, v + 3 * i);
    double e = kin + wc_spring_energy_at(m, x, seam_scale);
    if (elastic) *elastic = e;
    for (int i = 0; i < m->n_particles; ++i) e -= m->mass[i] * v3_dot(g, x + 3 * i);
    return e;
}

/* 1 when the memo holds a measure of exactly these inputs (bitwise: -0 and +0 differ, a NaN
 * equals its own bits; either way the same bits in give the same bits out) */
static int memo_holds(const wc_energy_memo* mo, size_t n3, const double* x, const double* v, const double g[3],
                      double seam_scale) {
    return mo->valid && memcmp(mo->gravity, g, sizeof mo->gravity) == 0 &&
           memcmp(&mo->seam_scale, &seam_scale, sizeof seam_scale) == 0 && memcmp(mo->x, x, n3 * sizeof(double)) == 0 &&
           memcmp(mo->v, v, n3 * sizeof(double)) == 0;
}

double wc_state_judge_energy(wc_state* s, const double* x, const double* v, double* elastic) {
    const wc_model* m = s->model;
    wc_energy_memo* mo = &s->energy_memo;
    size_t n3 = 3 * (size_t)m->n_particles;
    if (!s->judge_fresh && memo_holds(mo, n3, x, v, s->def.gravity, s->seam_scale)) {
        ++mo->hits;
        if (elastic) *elastic = mo->elastic;
        return mo->total;
    }
    ++mo->misses;
    double el;
    double e = wc_total_energy_xv(m, x, v, s->def.gravity, s->seam_scale, &el);
    if (elastic) *elastic = el;
    if (!s->judge_fresh) {
        if (mo->x != x) memcpy(mo->x, x, n3 * sizeof(double));
        if (mo->v != v) memcpy(mo->v, v, n3 * sizeof(double));
        memcpy(mo->gravity, s->def.gravity, sizeof mo->gravity);
        mo->seam_scale = s->seam_scale;
        mo->total = e;
        mo->elastic = el;
        mo->valid = 1;
    }
    return e;
}
