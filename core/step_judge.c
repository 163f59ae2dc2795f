/* The verdict on a substep (step_judge.h). */
#include "step_judge.h"
#include <math.h>
#include "mesh_collider.h"
#include "vec3.h"

/* Bounding-box diagonal of the rest shape (m). */
static double rest_diagonal(const wc_model* m) {
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) d2 += (m->report.bbox_max[c] - m->report.bbox_min[c]) * (m->report.bbox_max[c] - m->report.bbox_min[c]);
    return sqrt(d2);
}

/* Energy scale below which kinetic-energy growth is not judged: what gravity, moving pins and
 * moving colliders could plausibly put into the cloth. */
static double energy_floor(const wc_state* s) {
    const wc_model* m = s->model;
    double speed2 = 1.0 + 2.0 * v3_norm(s->def.gravity) * rest_diagonal(m) + v3_dot(s->def.air.wind, s->def.air.wind);
    for (int k = 0; k < s->n_colliders; ++k) speed2 += v3_dot(s->colliders[k].velocity, s->colliders[k].velocity);
    for (int k = 0; k < s->n_mesh; ++k) speed2 += s->mesh[k]->max_speed * s->mesh[k]->max_speed;
    return 0.5 * s->total_mass * speed2;
}

/* 1 when nothing in this frame can put energy into the cloth: pins still, colliders still, no
 * host seam ramp, no wind (gravity is in the total energy; drag and friction only take energy out). */
static int sourceless(const wc_state* s, double pin_energy) {
    if (pin_energy > 0 || v3_dot(s->def.air.wind, s->def.air.wind) > 0) return 0;
    if (s->seam_ramping) return 0; /* host seams shortening their rest length do work (sew.h) */
    for (int k = 0; k < s->n_colliders; ++k)
        if (v3_dot(s->colliders[k].velocity, s->colliders[k].velocity) > 0) return 0;
    for (int k = 0; k < s->n_mesh; ++k)
        if (wc_mesh_collider_moving(s->mesh[k])) return 0;
    return 1;
}

double wc_substep_energy_allowance(const wc_state* s, const wc_substep_measure* before) {
    double scale = s->total_mass * v3_norm(s->def.gravity) * rest_diagonal(s->model) + before->elastic;
    return s->def.fail_energy_gain * scale;
}

int wc_substep_judges_energy(const wc_state* s, int judge, double pin_energy) {
    return judge == WC_JUDGE_ALL && s->def.fail_energy_gain > 0 && sourceless(s, pin_energy);
}

wc_status wc_substep_judge(const wc_state* s, const wc_substep_measure* before, const wc_substep_measure* after,
                             int judge, int judge_energy, double pin_energy, double h, const char* solver,
                             wc_diag* diag) {
    if (!after->finite)
        return wc_fail(diag, WC_ERROR_NONFINITE, "substep (h = %g s, %s): non-finite position or velocity", h, solver);
    if (judge == WC_JUDGE_FINITE) return WC_OK;
    if (!(after->strain <= s->def.fail_strain))
        return wc_fail(diag, WC_ERROR_STEP_FAILED, "substep (h = %g s, %s): strain %.3g above fail_strain %.3g", h,
                       solver, after->strain, s->def.fail_strain);
    double floor = energy_floor(s) + pin_energy;
    if (after->kinetic > s->def.fail_energy_growth * (before->kinetic + floor))
        return wc_fail(diag, WC_ERROR_STEP_FAILED, "substep (h = %g s, %s): kinetic energy %.3g J grew from %.3g J", h,
                       solver, after->kinetic, before->kinetic);
    if (judge_energy) {
        double allowed = wc_substep_energy_allowance(s, before);
        if (after->total - before->total > allowed)
            return wc_fail(diag, WC_ERROR_STEP_FAILED,
                           "substep (h = %g s, %s): total energy rose by %.3g J with nothing to supply it (allowed %.3g J)",
                           h, solver, after->total - before->total, allowed);
    }
    return WC_OK;
}
