/* Outputs of `weft run`: OBJ frames, the stats JSON, output folders. */
#define _POSIX_C_SOURCE 200809L
#include "run.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* Shortest %.6g .. %.9g that reads back as exactly the float v (9 digits always do). buf: 32. */
static const char* fmt_float(char* buf, float v) {
    for (int prec = 6; prec <= 9; ++prec) {
        snprintf(buf, 32, "%.*g", prec, (double)v);
        if (strtof(buf, NULL) == v) break;
    }
    return buf;
}

int run_write_obj(const char* path, const float* pos, const scene_mesh* mesh, int frame, double time) {
    FILE* f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "# weft frame %d, t = %.9g s: %d vertices, %d polygons (metres, Y up)\n", frame, time, mesh->n_vertices,
            mesh->n_faces);
    char a[32], b[32], c[32];
    for (int v = 0; v < mesh->n_vertices; ++v) {
        const float* p = pos + 3 * (size_t)v;
        fprintf(f, "v %s %s %s\n", fmt_float(a, p[0]), fmt_float(b, p[1]), fmt_float(c, p[2]));
    }
    for (int q = 0; q < mesh->n_faces; ++q) {
        fputc('f', f);
        for (int k = mesh->face_start[q]; k < mesh->face_start[q + 1]; ++k) fprintf(f, " %d", mesh->indices[k] + 1);
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
    if (!cJSON_AddStringToObject(root, "backend", info->backend)) ok = 0;
    if (!cJSON_AddStringToObject(root, "backend_reason", info->backend_reason)) ok = 0;
    if (!cJSON_AddStringToObject(root, "preconditioner", info->preconditioner)) ok = 0;
    if (!cJSON_AddStringToObject(root, "integrator", info->integrator)) ok = 0;
    add_num(root, "newton_iterations", info->newton_iterations, &ok);
    if (!cJSON_AddBoolToObject(root, "line_search", info->line_search)) ok = 0;
    add_num(root, "newton_forcing", info->newton_forcing, &ok);
    add_num(root, "tolerance", info->tolerance, &ok);
    add_num(root, "substeps", info->substeps, &ok);
    add_num(root, "threads", info->threads, &ok);
    add_num(root, "fps", info->fps, &ok);
    run_summary_stats ms = run_summarise(r->frame_ms, r->frames, 1, scratch);
    cJSON* o = cJSON_AddObjectToObject(root, "ms_per_frame");
    if (!o) ok = 0;
    add_num(o, "median", ms.median, &ok);
    add_num(o, "p95", ms.p95, &ok);
    add_num(o, "mean", ms.mean, &ok);
    add_num(o, "max", ms.max, &ok);
    /* the means add up (a frame's stages to its total, less what no stage times); the medians do not */
    cJSON* med = cJSON_AddObjectToObject(root, "stage_ms");
    cJSON* max = cJSON_AddObjectToObject(root, "stage_ms_max");
    cJSON* mean = cJSON_AddObjectToObject(root, "stage_ms_mean");
    if (!med || !max || !mean) ok = 0;
    for (int s = 0; s < RUN_STAGES; ++s) {
        run_summary_stats st = run_summarise(r->stage_ms + s, r->frames, RUN_STAGES, scratch);
        add_num(med, run_stage_names[s], st.median, &ok);
        add_num(max, run_stage_names[s], st.max, &ok);
        add_num(mean, run_stage_names[s], st.mean, &ok);
    }
    o = cJSON_AddObjectToObject(root, "iterations");
    if (!o) ok = 0;
    add_num(o, "mean", run_mean_iterations(r), &ok);
    add_num(o, "max", r->max_iterations, &ok);
    add_num(root, "solves", (double)r->solves, &ok);
    /* the solves by kind (the rest: each substep's first solve, and Newton solves whose step the
       line search refused) */
    o = cJSON_AddObjectToObject(root, "solve_kinds");
    if (!o) ok = 0;
    add_num(o, "newton_steps", (double)r->newton_steps, &ok);
    add_num(o, "energy_steps", (double)r->energy_steps, &ok);
    add_num(o, "friction_passes", (double)r->friction_passes, &ok);
    add_num(root, "ms_precond", r->precond_ms, &ok);
    add_num(root, "residual_max", r->residual_max, &ok);
    add_num(root, "not_converged", r->not_converged, &ok);
    add_num(root, "rollbacks", r->rollbacks, &ok);
    add_num(root, "halvings", r->halvings, &ok);
    add_num(root, "direct_fallbacks", r->direct_fallbacks, &ok);
    add_num(root, "failures", r->failures, &ok);
    add_num(root, "failed_frames", r->failed_frames, &ok);
    add_num(root, "nonfinite_outputs", (double)r->nonfinite_outputs, &ok);
    add_num(root, "max_strain", r->max_strain, &ok);
    o = cJSON_AddObjectToObject(root, "contacts");
    if (!o) ok = 0;
    add_num(o, "max", r->contacts_max, &ok);
    add_num(o, "final", r->contacts_final, &ok);
    add_num(root, "final_kinetic_energy", r->final_kinetic_energy, &ok);
    add_vec3(root, "bbox_min", r->bbox_min, &ok);
    add_vec3(root, "bbox_max", r->bbox_max, &ok);
    o = cJSON_AddObjectToObject(root, "self_collision");
    if (!o) ok = 0;
    if (o && !cJSON_AddBoolToObject(o, "enabled", info->self_collision)) ok = 0;
    add_num(o, "thickness", info->self_thickness, &ok);
    add_num(o, "impacts", (double)r->self_impacts, &ok);
    add_num(o, "zones", (double)r->self_zones, &ok);
    add_num(o, "unresolved", r->self_unresolved, &ok);
    add_num(o, "ms", r->self_ms, &ok);
    /* checked at the last frame whether self-collision is on or not */
    add_num(root, "self_intersections", r->self_intersections, &ok);
    add_num(root, "max_penetration", r->max_penetration, &ok);
    /* every frame's wall time and values, in frame order (a failed frame: zeros but its collision check) */
    o = cJSON_AddObjectToObject(root, "per_frame");
    if (!o || !cJSON_AddItemToObject(o, "ms", cJSON_CreateDoubleArray(r->frame_ms, r->frames))) ok = 0;
    for (int k = 0; k < RUN_FRAME_VALS && o; ++k) {
        cJSON* a = cJSON_AddArrayToObject(o, run_frame_val_names[k]);
        if (!a) ok = 0;
        for (int f = 0; f < r->frames && a; ++f)
            if (!cJSON_AddItemToArray(a, cJSON_CreateNumber(r->frame_vals[(size_t)f * RUN_FRAME_VALS + k]))) ok = 0;
    }
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

