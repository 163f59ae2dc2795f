/* A benchmark scene run through the public API (weft/weft.h) at weft_default_cloth_def(): the
 * library resolves every default choice (solver, tolerance, preconditioner, integrator, Newton
 * iterations, line search, substeps, material) exactly as for a host that sets nothing. Only
 * the mesh (the scene's, as host arrays in world space), the pins (one attachment per pin group,
 * held still) and sleeping (off, as in every benchmark run: active frames are timed) are set.
 * `weft bench peers` uses it for its "Weft at its defaults" row. CPU backend; no colliders. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cmd_bench.h"
#include "sort.h"
#include "weft/weft.h"

static int fail(char* msg, size_t size, const char* what, weft_context* ctx, weft_status st) {
    snprintf(msg, size, "%s: %s (%s)", what, ctx ? weft_context_last_error(ctx) : "", weft_status_string(st));
    return -1;
}

/* The pin groups as attachments (their vertices that have a particle), vertex lists in verts. */
static int make_attachments(const bench_scene* bs, weft_attachment_def* att, int* verts) {
    int at = 0;
    for (int g = 0; g < bs->sc.n_pin_groups; ++g) {
        const scene_pin_group* pg = &bs->sc.pin_groups[g];
        att[g] = weft_default_attachment_def();
        att[g].vertices = verts + at;
        for (int k = 0; k < pg->n_vertices; ++k) {
            const int v = pg->vertices[k];
            if (v >= 0 && v < bs->model.n_host_verts && bs->model.host_to_particle[v] >= 0) verts[at++] = v;
        }
        att[g].n_vertices = (int)(verts + at - att[g].vertices);
        for (int c = 0; c < 3; ++c) att[g].free_axis[c] = (float)pg->free_axis[c];
    }
    return bs->sc.n_pin_groups;
}

int bench_api_run_defaults(const bench_scene* bs, double fps, int frames, int threads, bench_run* out, char* msg,
                           size_t size) {
    memset(out, 0, sizeof *out);
    if (bs->n_colliders > 0) {
        snprintf(msg, size, "%s: the defaults run has no colliders", bs->name);
        return -1;
    }
    const wc_source_mesh* src = &bs->src;
    const int nv = src->n_verts, np = bs->model.n_particles;
    int n_pinned = 0;
    for (int g = 0; g < bs->sc.n_pin_groups; ++g) n_pinned += bs->sc.pin_groups[g].n_vertices;
    float* pos = malloc(sizeof(float) * 3 * (size_t)(nv > 0 ? nv : 1));
    int* sizes = malloc(sizeof(int) * (size_t)(src->n_polys > 0 ? src->n_polys : 1));
    int* verts = malloc(sizeof(int) * (size_t)(n_pinned + 1));
    weft_attachment_def* att = calloc((size_t)bs->sc.n_pin_groups + 1, sizeof *att);
    double* ms = malloc(sizeof(double) * (size_t)(frames > 0 ? frames : 1));
    out->x = malloc(sizeof(double) * 3 * (size_t)(np > 0 ? np : 1));
    if (!pos || !sizes || !verts || !att || !ms || !out->x) {
        free(pos), free(sizes), free(verts), free(att), free(ms);
        bench_run_free(out);
        snprintf(msg, size, "out of memory");
        return -1;
    }
    for (int i = 0; i < 3 * nv; ++i) pos[i] = (float)src->pos[i];
    for (int q = 0; q < src->n_polys; ++q) sizes[q] = src->poly_start[q + 1] - src->poly_start[q];

    int rc = 0;
    weft_context* ctx = NULL;
    weft_cloth cloth = {0};
    weft_context_def cd = weft_default_context_def();
    cd.backend = WEFT_BACKEND_CPU;
    cd.threads = threads;
    weft_status st = weft_context_create(WEFT_ABI, &cd, &ctx);
    if (st != WEFT_OK) rc = fail(msg, size, "weft_context_create", ctx, st);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh.positions = pos;
    def.mesh.n_vertices = nv;
    def.mesh.face_sizes = sizes;
    def.mesh.n_faces = src->n_polys;
    def.mesh.indices = src->poly_verts;
    def.sleep_speed = 0.0;
    if (def.max_frame_time < 1.0 / fps) def.max_frame_time = 1.0 / fps;
    if (rc == 0 && (st = weft_cloth_create(ctx, &def, &cloth)) != WEFT_OK) rc = fail(msg, size, "weft_cloth_create", ctx, st);
    const int n_att = make_attachments(bs, att, verts);
    if (rc == 0 && n_att > 0 && (st = weft_cloth_set_attachments(ctx, cloth, att, n_att)) != WEFT_OK)
        rc = fail(msg, size, "weft_cloth_set_attachments", ctx, st);
    long long iterations = 0;
    for (int f = 0; f < frames && rc == 0; ++f) {
        weft_frame fr = weft_default_frame();
        fr.dt = 1.0 / fps;
        weft_frame_stats fs;
        memset(&fs, 0, sizeof fs);
        st = weft_cloth_step(ctx, cloth, &fr, &fs);
        if (st != WEFT_OK && st != WEFT_ERROR_STEP_FAILED) {
            rc = fail(msg, size, "weft_cloth_step", ctx, st);
            break;
        }
        ms[f] = fs.ms_total;
        out->frames = f + 1;
        iterations += fs.iterations;
        out->substeps += fs.substeps;
        out->solves += fs.solves;
        out->precond_ms += fs.ms_precond;
        out->solve_ms += fs.ms_solve;
        if (fs.max_iterations > out->max_iterations) out->max_iterations = fs.max_iterations;
        out->not_converged += fs.not_converged;
        out->rollbacks += fs.rollbacks;
        out->halvings += fs.halvings;
        out->direct_fallbacks += fs.direct_fallbacks;
        out->failures += fs.failures + (st == WEFT_ERROR_STEP_FAILED);
        if (!(fs.max_strain <= out->max_strain)) out->max_strain = fs.max_strain;
    }
    if (rc == 0) {
        /* world positions by host vertex, then per particle (the CLI's model of the same mesh) */
        int count = 0;
        st = weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, pos, NULL, nv, &count);
        if (st != WEFT_OK) rc = fail(msg, size, "weft_cloth_get_vertices", ctx, st);
        for (int v = 0; v < nv && rc == 0; ++v) {
            const int p = v < bs->model.n_host_verts ? bs->model.host_to_particle[v] : -1;
            if (p < 0) continue;
            for (int c = 0; c < 3; ++c) out->x[3 * p + c] = pos[3 * v + c];
            for (int c = 0; c < 3; ++c) out->nonfinite |= !isfinite(out->x[3 * p + c]);
        }
    }
    if (out->frames > 0) out->ms_median = wc_sort_median(ms, out->frames);
    out->iterations = out->substeps > 0 ? (double)iterations / (double)out->substeps : 0.0;
    out->iterations_total = iterations;
    if (ctx) {
        if (cloth.id) weft_cloth_destroy(ctx, cloth);
        weft_context_destroy(ctx);
    }
    free(pos), free(sizes), free(verts), free(att), free(ms);
    if (rc != 0) bench_run_free(out);
    return rc;
}
