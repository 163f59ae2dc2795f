/* The summary table `weft run` prints at the end (stdout, unless --quiet). */
#include <stdlib.h>

#include "run.h"

void run_print_summary(FILE* out, const run_info* info, const run_record* r) {
    double* scratch = malloc(sizeof(double) * (size_t)(r->frames > 0 ? r->frames : 1));
    run_summary_stats ms = {0, 0, 0, 0}, stage[RUN_STAGES];
    for (int s = 0; s < RUN_STAGES; ++s) stage[s] = ms;
    if (scratch) {
        ms = run_summarise(r->frame_ms, r->frames, 1, scratch);
        for (int s = 0; s < RUN_STAGES; ++s) stage[s] = run_summarise(r->stage_ms + s, r->frames, RUN_STAGES, scratch);
    }
    free(scratch);
    /* the stage columns: total first, then the stages in step order */
    static const int order[RUN_STAGES] = {6, 0, 1, 2, 3, 4, 5};
    fprintf(out, "%-13s %s\n", "scene", info->scene);
    fprintf(out, "%-13s %d particles, %d triangles, %d springs\n", "model", info->particles, info->triangles,
            info->springs);
    fprintf(out, "%-13s %d frames at %g fps, %d substep%s per frame, %s solver, %s backend, %d thread%s\n", "run",
            r->frames, info->fps, info->substeps, info->substeps == 1 ? "" : "s", info->solver, info->backend,
            info->threads, info->threads == 1 ? "" : "s");
    fprintf(out, "%-13s %s: %s\n", "backend", info->backend, info->backend_reason);
    fprintf(out, "%-13s %s integrator, %s preconditioner (tolerance %g), Newton iterations %d (forcing %g), line search %s\n",
            "method", info->integrator, info->preconditioner, info->tolerance, info->newton_iterations,
            info->newton_forcing, info->line_search ? "on" : "off");
    fprintf(out, "%-13s median %.3f  p95 %.3f  mean %.3f  max %.3f  (weft_cloth_step wall time)\n", "ms/frame",
            ms.median, ms.p95, ms.mean, ms.max);
    fprintf(out, "%-13s", "stage ms");
    for (int i = 0; i < RUN_STAGES; ++i) fprintf(out, " %12s", run_stage_names[order[i]]);
    fprintf(out, "\n%-13s", "  median");
    for (int i = 0; i < RUN_STAGES; ++i) fprintf(out, " %12.3f", stage[order[i]].median);
    fprintf(out, "\n%-13s", "  max");
    for (int i = 0; i < RUN_STAGES; ++i) fprintf(out, " %12.3f", stage[order[i]].max);
    fputc('\n', out);
    fprintf(out, "%-13s mean %.1f per solve, max %d; largest residual %.3g; %d not converged; %lld linear solves, "
            "%.3f ms building preconditioners\n", "iterations", run_mean_iterations(r), r->max_iterations, r->residual_max,
            r->not_converged, r->solves, r->precond_ms);
    fprintf(out, "%-13s %d rollbacks, %d halvings, %d direct fallbacks, %d failed substeps, %d failed frames\n",
            "recovery", r->rollbacks, r->halvings, r->direct_fallbacks, r->failures, r->failed_frames);
    fprintf(out, "%-13s max %d particles, %d at the end\n", "contacts", r->contacts_max, r->contacts_final);
    fprintf(out, "%-13s max strain %.4g, final kinetic energy %.4g J, %lld non-finite positions\n", "result",
            r->max_strain, r->final_kinetic_energy, r->nonfinite_outputs);
    /* self-collision and the last frame's collision check, on one line */
    if (info->self_collision)
        fprintf(out, "%-13s on (%g m: %lld impacts, %lld zones, %d unresolved, %.3f ms); ", "self-collide",
                info->self_thickness, r->self_impacts, r->self_zones, r->self_unresolved, r->self_ms);
    else
        fprintf(out, "%-13s off; ", "self-collide");
    fprintf(out, "last frame: %d self-intersecting edge-triangle pairs, max penetration %.4g m\n", r->self_intersections,
            r->max_penetration);
    fprintf(out, "%-13s [%.4g, %.4g, %.4g] .. [%.4g, %.4g, %.4g] m\n", "final bbox", r->bbox_min[0], r->bbox_min[1],
            r->bbox_min[2], r->bbox_max[0], r->bbox_max[1], r->bbox_max[2]);
    if (info->out_dir && r->frames > 0)
        fprintf(out, "%-13s %s/frame_0001.obj .. frame_%04d.obj\n", "frames", info->out_dir, r->frames);
    if (info->render_dir && r->frames > 0)
        fprintf(out, "%-13s %s/frame_0001.png .. frame_%04d.png\n", "images", info->render_dir, r->frames);
}
