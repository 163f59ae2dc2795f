/* `weft run`: accumulating the per-frame statistics, and their summaries. */
#include "run.h"

#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char* const run_stage_names[RUN_STAGES] = {"forces", "assemble", "solve", "collide", "integrate",
                                                   "self_collide", "total"};
const char* const run_frame_val_names[RUN_FRAME_VALS] = {
    "rollbacks", "max_strain", "max_iterations", "not_converged", "self_impacts", "contacts", "self_intersections",
    "penetration"};

int run_record_init(run_record* r, int frames) {
    memset(r, 0, sizeof *r);
    const size_t n = (size_t)(frames > 0 ? frames : 1);
    r->frame_ms = calloc(n, sizeof(double));
    r->stage_ms = calloc(n * RUN_STAGES, sizeof(double));
    r->frame_vals = calloc(n * RUN_FRAME_VALS, sizeof(double));
    for (int k = 0; k < 3; ++k) {
        r->bbox_min[k] = INFINITY;
        r->bbox_max[k] = -INFINITY;
    }
    return r->frame_ms && r->stage_ms && r->frame_vals ? 0 : -1;
}

void run_record_free(run_record* r) {
    free(r->frame_ms);
    free(r->stage_ms);
    free(r->frame_vals);
    r->frame_ms = r->stage_ms = r->frame_vals = NULL;
}

void run_record_frame(run_record* r, int f, double ms, const weft_frame_stats* s) {
    r->frame_ms[f] = ms;
    double* st = r->stage_ms + (size_t)f * RUN_STAGES;
    st[0] = s->ms_forces;
    st[1] = s->ms_assemble;
    st[2] = s->ms_solve;
    st[3] = s->ms_collide;
    st[4] = s->ms_integrate;
    st[5] = s->ms_self_collide;
    st[6] = s->ms_total;
    double* fv = r->frame_vals + (size_t)f * RUN_FRAME_VALS;
    fv[0] = s->rollbacks;
    fv[1] = s->max_strain;
    fv[2] = s->max_iterations;
    fv[3] = s->not_converged;
    fv[4] = s->self_impacts;
    fv[5] = s->contacts;
    r->iterations += s->iterations;
    r->solves += s->solves;
    r->precond_ms += s->ms_precond;
    r->substeps += s->substeps;
    r->newton_steps += s->newton_steps;
    r->energy_steps += s->energy_steps;
    r->friction_passes += s->friction_passes;
    if (s->max_iterations > r->max_iterations) r->max_iterations = s->max_iterations;
    if (s->residual > r->residual_max) r->residual_max = s->residual;
    r->not_converged += s->not_converged;
    r->rollbacks += s->rollbacks;
    r->halvings += s->halvings;
    r->direct_fallbacks += s->direct_fallbacks;
    r->failures += s->failures;
    if (s->max_strain > r->max_strain) r->max_strain = s->max_strain;
    if (s->contacts > r->contacts_max) r->contacts_max = s->contacts;
    r->contacts_final = s->contacts;
    r->final_kinetic_energy = s->kinetic_energy;
    r->self_impacts += s->self_impacts;
    r->self_zones += s->self_zones;
    r->self_unresolved += s->self_unresolved;
    r->self_ms += s->ms_self_collide;
    r->frames = f + 1;
}

void run_record_check(run_record* r, int f, const weft_collision_check* chk) {
    double* fv = r->frame_vals + (size_t)f * RUN_FRAME_VALS;
    fv[6] = chk->self_intersections;
    fv[7] = chk->max_penetration;
}

void run_record_failed_frame(run_record* r, int f, double ms) {
    r->frame_ms[f] = ms;
    memset(r->stage_ms + (size_t)f * RUN_STAGES, 0, RUN_STAGES * sizeof(double));
    memset(r->frame_vals + (size_t)f * RUN_FRAME_VALS, 0, RUN_FRAME_VALS * sizeof(double));
    ++r->failed_frames;
    ++r->failures;
    r->frames = f + 1;
}

long long run_record_bbox(run_record* r, const float* pos, int n) {
    long long nonfinite = 0;
    for (int k = 0; k < 3; ++k) {
        r->bbox_min[k] = INFINITY;
        r->bbox_max[k] = -INFINITY;
    }
    for (int v = 0; v < n; ++v) {
        const float* p = pos + 3 * (size_t)v;
        if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]))) {
            ++nonfinite;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            r->bbox_min[k] = fmin(r->bbox_min[k], p[k]);
            r->bbox_max[k] = fmax(r->bbox_max[k], p[k]);
        }
    }
    return nonfinite;
}

run_summary_stats run_summarise(const double* values, int n, int stride, double* scratch) {
    run_summary_stats s = {0, 0, 0, 0};
    if (n <= 0) return s;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        scratch[i] = values[(size_t)i * stride];
        sum += scratch[i];
    }
    s.median = cli_sort_median(scratch, n);   /* sorts scratch: p95 and max read it below */
    int rank = (int)ceil(0.95 * n);   /* nearest rank */
    s.p95 = scratch[(rank > 0 ? rank : 1) - 1];
    s.mean = sum / n;
    s.max = scratch[n - 1];
    return s;
}

double run_mean_iterations(const run_record* r) {
    return r->solves > 0 ? (double)r->iterations / (double)r->solves : 0.0;
}
