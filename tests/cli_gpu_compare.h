/* A garment scene's whole run GPU against CPU, as a user runs it: `weft run SCENE --frames N
 * --threads 1 --stats FILE` with `--backend cpu` and with `--backend gpu` (llvmpipe through EGL
 * where there is no GPU), the two stats files read back and compared frame by frame. --stats
 * checks every frame's end with weft_cloth_check_collisions. Asserted, with the scene's bounds:
 *  - no failed frame, self-collision on, and at no frame on either backend a crossing edge-triangle
 *    pair, or (`authored_crossings` set) more crossing pairs than the garment has as authored and
 *    sewn (`weft run --frames 0 --stats`: the self-collision stage keeps crossings from forming, it
 *    does not untangle the ones a garment starts with);
 *  - the deepest particle behind a body on the GPU at most penetration_slack deeper than on the CPU,
 *    every frame;
 *  - from frame `settled` on: the largest strain within strain_slack of the CPU's and the particles
 *    in contact within contact_lo-contact_hi times the CPU's;
 *  - the GPU's rollbacks from frame `rollbacks_from` on no more than the CPU's there.
 * The figures are printed (PCG iterations a solve too, not asserted). Header-only (static
 * functions): included by test_cli_gpu_suit.c and test_cli_gpu_dance.c. */
#ifndef WEFT_TESTS_CLI_GPU_COMPARE_H
#define WEFT_TESTS_CLI_GPU_COMPARE_H
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "cli_frames.h"

enum { GC_MAX_FRAMES = 32 };

typedef struct gc_scene {
    const char* name;            /* names the stats files */
    const char* file;            /* under sample_scenes/ */
    int frames;                  /* <= GC_MAX_FRAMES */
    int settled;                 /* 1-based: strain and contacts compared from this frame on */
    int rollbacks_from;          /* 1-based: GPU rollbacks <= CPU's from this frame on */
    int authored_crossings;      /* 1: crossings allowed up to the authored garment's; 0: none */
    double penetration_slack;    /* m */
    double strain_slack;
    double contact_lo, contact_hi;
} gc_scene;

enum { GC_ROLLBACKS, GC_STRAIN, GC_CONTACTS, GC_CROSSINGS, GC_PENETRATION, GC_ITERATIONS, GC_N_VALS };
static const char* const gc_val_names[GC_N_VALS] = {"rollbacks", "max_strain", "contacts", "self_intersections",
                                                    "penetration", "max_iterations"};

typedef struct gc_run {
    int ok;
    char backend[8];
    int self_collision, failed_frames;
    double solves, mean_iterations, not_converged;
    double v[GC_N_VALS][GC_MAX_FRAMES];   /* per frame (0-based) */
} gc_run;

/* One run of the scene on `backend`; `method` NULL: the backend's defaults. */
static void gc_run_scene(const gc_scene* s, const char* backend, const char* method, const char* tag, gc_run* r) {
    memset(r, 0, sizeof *r);
    char name[128], stats[1100], args[2600];
    snprintf(name, sizeof name, "%s_%s_%s.json", s->name, tag, backend);
    snprintf(stats, sizeof stats, "%s", ts_tmp_path(name));
    snprintf(args, sizeof args,
             "run '%s/sample_scenes/%s' --frames %d --threads 1 --quiet --backend %s --stats '%s' %s",
             WEFT_SOURCE_DIR, s->file, s->frames, backend, stats, method ? method : "");
    ts_cli_result cr;
    ts_run_cli(args, &cr);
    CHECK_EQ_INT(cr.rc, 0);
    if (cr.rc != 0) {
        fprintf(stderr, "weft %s: rc %d: %s\n", args, cr.rc, cr.err);
        return;
    }
    cJSON* root = cf_read_json(stats);
    CHECK(root != NULL);
    if (!root) return;
    const cJSON* b = cJSON_GetObjectItemCaseSensitive(root, "backend");
    if (cJSON_IsString(b)) snprintf(r->backend, sizeof r->backend, "%s", b->valuestring);
    const cJSON* self = cJSON_GetObjectItemCaseSensitive(root, "self_collision");
    r->self_collision = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(self, "enabled"));
    r->failed_frames = (int)cf_num(root, "failed_frames");
    r->solves = cf_num(root, "solves");
    r->mean_iterations = cf_num(cJSON_GetObjectItemCaseSensitive(root, "iterations"), "mean");
    r->not_converged = cf_num(root, "not_converged");
    const cJSON* per = cJSON_GetObjectItemCaseSensitive(root, "per_frame");
    r->ok = 1;
    for (int k = 0; k < GC_N_VALS; ++k) {
        const cJSON* a = cJSON_GetObjectItemCaseSensitive(per, gc_val_names[k]);
        CHECK(cJSON_GetArraySize(a) == s->frames);
        if (cJSON_GetArraySize(a) != s->frames) r->ok = 0;
        for (int f = 0; f < s->frames && r->ok; ++f) {
            const cJSON* x = cJSON_GetArrayItem(a, f);
            r->v[k][f] = cJSON_IsNumber(x) ? x->valuedouble : NAN;
        }
    }
    cJSON_Delete(root);
}

/* Crossing edge-triangle pairs in the garment as loaded (sewn), before any step; -1 on failure. */
static int gc_authored_crossings(const gc_scene* s) {
    char name[128], stats[1100], args[2600];
    snprintf(name, sizeof name, "%s_authored.json", s->name);
    snprintf(stats, sizeof stats, "%s", ts_tmp_path(name));
    snprintf(args, sizeof args, "run '%s/sample_scenes/%s' --frames 0 --threads 1 --quiet --stats '%s'",
             WEFT_SOURCE_DIR, s->file, stats);
    ts_cli_result cr;
    ts_run_cli(args, &cr);
    CHECK_EQ_INT(cr.rc, 0);
    cJSON* root = cr.rc == 0 ? cf_read_json(stats) : NULL;
    CHECK(root != NULL);
    double n = root ? cf_num(root, "self_intersections") : NAN;
    cJSON_Delete(root);
    CHECK(n >= 0);
    return n >= 0 ? (int)n : -1;
}

/* The two runs' figures printed and checked against the scene's bounds. */
static void gc_check(const gc_scene* s, const char* what, int crossings_bound, const gc_run* cpu, const gc_run* gpu) {
    CHECK(strcmp(cpu->backend, "cpu") == 0 && strcmp(gpu->backend, "gpu") == 0);
    CHECK(cpu->self_collision && gpu->self_collision);
    CHECK_EQ_INT(cpu->failed_frames, 0);
    CHECK_EQ_INT(gpu->failed_frames, 0);
    const int F = s->frames, L = F - 1, S = s->settled, R = s->rollbacks_from;
    int crossings[2] = {0, 0}, most_crossings[2] = {0, 0}, early_rollbacks[2] = {0, 0}, late_rollbacks[2] = {0, 0};
    double deeper = -HUGE_VAL, strain_gap = 0.0, ratio_lo = HUGE_VAL, ratio_hi = 0.0, depth[2] = {0.0, 0.0};
    const gc_run* r[2] = {cpu, gpu};
    for (int b = 0; b < 2; ++b)
        for (int f = 0; f < F; ++f) {
            const double c = r[b]->v[GC_CROSSINGS][f];
            crossings[b] += !(c <= crossings_bound);   /* NaN counts too */
            most_crossings[b] = isnan(c) ? INT_MAX : (int)fmax(most_crossings[b], c);
            if (f + 1 >= R) late_rollbacks[b] += (int)r[b]->v[GC_ROLLBACKS][f];
            else early_rollbacks[b] += (int)r[b]->v[GC_ROLLBACKS][f];
            if (f + 1 >= S) depth[b] = fmax(depth[b], r[b]->v[GC_PENETRATION][f]);
        }
    for (int f = 0; f < F; ++f) {
        double d = gpu->v[GC_PENETRATION][f] - cpu->v[GC_PENETRATION][f];
        deeper = isnan(d) ? HUGE_VAL : fmax(deeper, d);
        if (f + 1 < S) continue;
        double g = fabs(gpu->v[GC_STRAIN][f] - cpu->v[GC_STRAIN][f]);
        strain_gap = isnan(g) ? HUGE_VAL : fmax(strain_gap, g);
        double q = gpu->v[GC_CONTACTS][f] / cpu->v[GC_CONTACTS][f];
        ratio_lo = isnan(q) ? 0.0 : fmin(ratio_lo, q);
        ratio_hi = isnan(q) ? HUGE_VAL : fmax(ratio_hi, q);
    }
    printf("  %s, %s, %d frames:\n", s->file, what, F);
    printf("    crossing pairs, most at a frame: CPU %d, GPU %d (bound %d%s); frames over it CPU %d, GPU %d\n",
           most_crossings[0], most_crossings[1], crossings_bound,
           s->authored_crossings ? ": the authored garment's" : "", crossings[0], crossings[1]);
    printf("    rollbacks before frame %d CPU %d, GPU %d; from it CPU %d, GPU %d\n", R, early_rollbacks[0],
           early_rollbacks[1], late_rollbacks[0], late_rollbacks[1]);
    printf("    deepest behind the body: frame 1 CPU %.4g m, GPU %.4g m; frames %d-%d CPU %.3g m, GPU %.3g m; "
           "GPU deeper by %.3g m at most (bound %g)\n", cpu->v[GC_PENETRATION][0], gpu->v[GC_PENETRATION][0], S, F,
           depth[0], depth[1], deeper, s->penetration_slack);
    printf("    largest strain at frame %d CPU %.4f, GPU %.4f; from frame %d apart by %.3g at most (bound %g)\n", F,
           cpu->v[GC_STRAIN][L], gpu->v[GC_STRAIN][L], S, strain_gap, s->strain_slack);
    printf("    in contact at frame %d CPU %.0f, GPU %.0f; GPU / CPU from frame %d: %.3f-%.3f (bounds %g-%g)\n", F,
           cpu->v[GC_CONTACTS][L], gpu->v[GC_CONTACTS][L], S, ratio_lo, ratio_hi, s->contact_lo, s->contact_hi);
    printf("    linear solves, mean PCG iterations (not converged): CPU %.0f, %.1f (%.0f), GPU %.0f, %.1f (%.0f)\n",
           cpu->solves, cpu->mean_iterations, cpu->not_converged, gpu->solves, gpu->mean_iterations,
           gpu->not_converged);
    printf("    per frame (CPU / GPU): rollbacks, crossings, largest strain, in contact, deepest (m), most PCG "
           "iterations\n");
    for (int f = 0; f < F; ++f)
        printf("      %2d: %.0f / %.0f, %.0f / %.0f, %.4f / %.4f, %.0f / %.0f, %.3g / %.3g, %.0f / %.0f\n", f + 1,
               cpu->v[GC_ROLLBACKS][f], gpu->v[GC_ROLLBACKS][f], cpu->v[GC_CROSSINGS][f], gpu->v[GC_CROSSINGS][f],
               cpu->v[GC_STRAIN][f], gpu->v[GC_STRAIN][f], cpu->v[GC_CONTACTS][f], gpu->v[GC_CONTACTS][f],
               cpu->v[GC_PENETRATION][f], gpu->v[GC_PENETRATION][f], cpu->v[GC_ITERATIONS][f],
               gpu->v[GC_ITERATIONS][f]);
    CHECK_EQ_INT(crossings[0], 0);
    CHECK_EQ_INT(crossings[1], 0);
    CHECK(deeper <= s->penetration_slack);
    CHECK(strain_gap <= s->strain_slack);
    CHECK(ratio_lo >= s->contact_lo && ratio_hi <= s->contact_hi);
    CHECK(late_rollbacks[1] <= late_rollbacks[0]);
}

/* Both backends with `method` (NULL: their defaults); `tag` names the stats files. */
static void gc_compare(const gc_scene* s, const char* what, const char* tag, const char* method) {
    static gc_run cpu, gpu;
    CHECK(s->frames >= 1 && s->frames <= GC_MAX_FRAMES);
    if (s->frames < 1 || s->frames > GC_MAX_FRAMES) return;
    const int bound = s->authored_crossings ? gc_authored_crossings(s) : 0;
    if (bound < 0) return;
    gc_run_scene(s, "cpu", method, tag, &cpu);
    gc_run_scene(s, "gpu", method, tag, &gpu);
    if (cpu.ok && gpu.ok) gc_check(s, what, bound, &cpu, &gpu);
}

#endif
