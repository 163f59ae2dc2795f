/* Outputs of `weft run`: OBJ frames, the stats JSON and the summary table. */
#define _POSIX_C_SOURCE 200809L
#include "run.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Shortest of %.15g / %.16g / %.17g that reads back as exactly v. buf: 32 chars. */
static const char* fmt_exact(char* buf, double v) {
    for (int prec = 15; prec <= 17; ++prec) {
        snprintf(buf, 32, "%.*g", prec, v);
        if (strtod(buf, NULL) == v) break;
    }
    return buf;
}

int run_write_obj(const char* path, const double* pos, const wc_source_mesh* src, int frame, double time) {
    FILE* f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "# weft frame %d, t = %.9g s: %d vertices, %d polygons (metres, Y up)\n", frame, time, src->n_verts,
            src->n_polys);
    char a[32], b[32], c[32];
    for (int v = 0; v < src->n_verts; ++v) {
        const double* p = pos + 3 * (size_t)v;
        fprintf(f, "v %s %s %s\n", fmt_exact(a, p[0]), fmt_exact(b, p[1]), fmt_exact(c, p[2]));
    }
    for (int q = 0; q < src->n_polys; ++q) {
        fputc('f', f);
        for (int k = src->poly_start[q]; k < src->poly_start[q + 1]; ++k) fprintf(f, " %d", src->poly_verts[k] + 1);
        fputc('\n', f);
    }
    int bad = ferror(f);
    if (fclose(f) != 0) bad = 1;
    return bad ? -1 : 0;
}

int run_make_dirs(const char* path) {
    size_t n = strlen(path);
    char* p = malloc(n + 1);
    if (!p) {
        errno = ENOMEM;
        return -1;
    }
    memcpy(p, path, n + 1);
    int rc = 0;
    for (size_t i = 1; i <= n && rc == 0; ++i) {
        if (p[i] != '/' && p[i] != '\0') continue;
        char saved = p[i];
        p[i] = '\0';
        if (mkdir(p, 0777) != 0 && errno != EEXIST) rc = -1;
        p[i] = saved;
    }
    struct stat st;
    if (rc == 0 && stat(path, &st) != 0) {
        rc = -1;
    } else if (rc == 0 && !S_ISDIR(st.st_mode)) {
        errno = ENOTDIR;
        rc = -1;
    }
    free(p);
    return rc;
}

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

typedef struct summary_stats {
    double median, p95, mean;
} summary_stats;

/* Median, 95th percentile (nearest rank) and mean of n values with the given stride; zeros when
 * n is 0. scratch: n doubles. */
static summary_stats summarise(const double* values, int n, int stride, double* scratch) {
    summary_stats s = {0, 0, 0};
    if (n <= 0) return s;
    double sum = 0;
    for (int i = 0; i < n; ++i) {
        scratch[i] = values[(size_t)i * stride];
        sum += scratch[i];
    }
    qsort(scratch, (size_t)n, sizeof(double), cmp_double);
    s.median = n % 2 ? scratch[n / 2] : 0.5 * (scratch[n / 2 - 1] + scratch[n / 2]);
    int rank = (int)ceil(0.95 * n);
    s.p95 = scratch[(rank > 0 ? rank : 1) - 1];
    s.mean = sum / n;
    return s;
}

static const char* const stage_names[RUN_STAGES] = {"forces", "assemble", "solve", "collide", "integrate", "total"};

static double mean_iterations(const run_record* r) {
    return r->substeps > 0 ? (double)r->iterations / (double)r->substeps : 0.0;
}

/* cJSON_Add* return NULL when out of memory; ok collects that. */
static void add_num(cJSON* o, const char* k, double v, int* ok) {
    if (!cJSON_AddNumberToObject(o, k, isfinite(v) ? v : 0.0)) *ok = 0;
}

static void add_vec3(cJSON* o, const char* k, const double* v, int* ok) {
    cJSON* arr = cJSON_CreateDoubleArray(v, 3);
    if (!arr || !cJSON_AddItemToObject(o, k, arr)) {
        cJSON_Delete(arr);
        *ok = 0;
    }
}

static cJSON* build_stats(const run_info* info, const run_record* r, double* scratch) {
    int ok = 1;
    cJSON* root = cJSON_CreateObject();
    if (!root) return NULL;
    if (!cJSON_AddStringToObject(root, "scene", info->scene)) ok = 0;
    add_num(root, "frames", r->frames, &ok);
    add_num(root, "particles", info->particles, &ok);
    add_num(root, "triangles", info->triangles, &ok);
    add_num(root, "springs", info->springs, &ok);
    if (!cJSON_AddStringToObject(root, "solver", info->solver)) ok = 0;
    add_num(root, "substeps", info->substeps, &ok);
    add_num(root, "threads", info->threads, &ok);
    add_num(root, "fps", info->fps, &ok);
    summary_stats ms = summarise(r->frame_ms, r->frames, 1, scratch);
    cJSON* o = cJSON_AddObjectToObject(root, "ms_per_frame");
    if (!o) ok = 0;
    add_num(o, "median", ms.median, &ok);
    add_num(o, "p95", ms.p95, &ok);
    add_num(o, "mean", ms.mean, &ok);
    o = cJSON_AddObjectToObject(root, "stage_ms");
    if (!o) ok = 0;
    for (int s = 0; s < RUN_STAGES; ++s)
        add_num(o, stage_names[s], summarise(r->stage_ms + s, r->frames, RUN_STAGES, scratch).median, &ok);
    o = cJSON_AddObjectToObject(root, "iterations");
    if (!o) ok = 0;
    add_num(o, "mean", mean_iterations(r), &ok);
    add_num(o, "max", r->max_iterations, &ok);
    add_num(root, "residual_max", r->residual_max, &ok);
    add_num(root, "not_converged", r->not_converged, &ok);
    add_num(root, "rollbacks", r->rollbacks, &ok);
    add_num(root, "halvings", r->halvings, &ok);
    add_num(root, "direct_fallbacks", r->direct_fallbacks, &ok);
    add_num(root, "failures", r->failures, &ok);
    add_num(root, "failed_frames", r->failed_frames, &ok);
    add_num(root, "nonfinite_outputs", (double)r->nonfinite_outputs, &ok);
    add_num(root, "max_strain", r->max_strain, &ok);
    add_num(root, "final_kinetic_energy", r->final_kinetic_energy, &ok);
    add_vec3(root, "bbox_min", r->bbox_min, &ok);
    add_vec3(root, "bbox_max", r->bbox_max, &ok);
    if (!ok) {
        cJSON_Delete(root);
        return NULL;
    }
    return root;
}

int run_write_stats(const char* path, const run_info* info, const run_record* r) {
    double* scratch = malloc(sizeof(double) * (size_t)(r->frames > 0 ? r->frames : 1));
    cJSON* root = scratch ? build_stats(info, r, scratch) : NULL;
    free(scratch);
    char* text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) return -1;
    FILE* f = fopen(path, "w");
    int bad = !f;
    if (f) {
        bad = fputs(text, f) < 0 || fputc('\n', f) == EOF;
        if (fclose(f) != 0) bad = 1;
    }
    cJSON_free(text);
    return bad ? -1 : 0;
}

void run_print_summary(FILE* out, const run_info* info, const run_record* r) {
    double* scratch = malloc(sizeof(double) * (size_t)(r->frames > 0 ? r->frames : 1));
    summary_stats ms = {0, 0, 0};
    double stage[RUN_STAGES] = {0};
    if (scratch) {
        ms = summarise(r->frame_ms, r->frames, 1, scratch);
        for (int s = 0; s < RUN_STAGES; ++s) stage[s] = summarise(r->stage_ms + s, r->frames, RUN_STAGES, scratch).median;
    }
    free(scratch);
    fprintf(out, "%-13s %s\n", "scene", info->scene);
    fprintf(out, "%-13s %d particles, %d triangles, %d springs\n", "model", info->particles, info->triangles,
            info->springs);
    fprintf(out, "%-13s %d frames at %g fps, %d substep%s per frame, %s solver, %d thread%s\n", "run", r->frames,
            info->fps, info->substeps, info->substeps == 1 ? "" : "s", info->solver, info->threads,
            info->threads == 1 ? "" : "s");
    fprintf(out, "%-13s median %.3f  p95 %.3f  mean %.3f\n", "ms/frame", ms.median, ms.p95, ms.mean);
    fprintf(out, "%-13s", "stage ms");
    for (int s = 0; s < RUN_STAGES; ++s) fprintf(out, " %s %.3f ", stage_names[s], stage[s]);
    fprintf(out, "(medians)\n");
    fprintf(out, "%-13s mean %.1f per substep, max %d; largest residual %.3g; %d not converged\n", "iterations",
            mean_iterations(r), r->max_iterations, r->residual_max, r->not_converged);
    fprintf(out, "%-13s %d rollbacks, %d halvings, %d direct fallbacks, %d failed substeps, %d failed frames\n",
            "recovery", r->rollbacks, r->halvings, r->direct_fallbacks, r->failures, r->failed_frames);
    fprintf(out, "%-13s %lld non-finite positions, max strain %.4g, final kinetic energy %.4g J\n", "result",
            r->nonfinite_outputs, r->max_strain, r->final_kinetic_energy);
    fprintf(out, "%-13s [%.4g, %.4g, %.4g] .. [%.4g, %.4g, %.4g] m\n", "final bbox", r->bbox_min[0], r->bbox_min[1],
            r->bbox_min[2], r->bbox_max[0], r->bbox_max[1], r->bbox_max[2]);
    if (info->out_dir && r->frames > 0)
        fprintf(out, "%-13s %s/frame_0001.obj .. frame_%04d.obj\n", "frames", info->out_dir, r->frames);
}
