/* One measured run of a benchmark scene through the public API (bench_run.h). The cloth is the
 * scene's, made by the scene host on the backend's context; each frame is one timed
 * weft_cloth_step (its stats' ms_total: what a host pays for the call), then, outside that time,
 * weft_cloth_get_energy (on the GPU it reads the state back) for the energy, strain and finiteness
 * checks and the centre-of-mass track. */
#define _POSIX_C_SOURCE 200809L
#include "bench_run.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench_backend.h"
#include "cli.h"
#include "scene_host.h"

weft_cloth_def bench_run_def(const bench_scene* bs) {
    weft_cloth_def def = bs->sc.def;
    def.sleep_speed = 0.0;   /* a cloth that came to rest is not put to sleep: active steps are timed */
    return def;
}

void bench_distance(const float* a, const float* b, int n, double* rms, double* max) {
    double sum = 0.0, mx = 0.0;
    for (int i = 0; i < n; ++i) {
        double e2 = 0.0;
        for (int c = 0; c < 3; ++c) {
            const double d = (double)a[3 * i + c] - (double)b[3 * i + c];
            e2 += d * d;
        }
        const double e = sqrt(e2);
        sum += e2;
        if (!(e <= mx)) mx = e; /* a NaN distance wins */
    }
    *rms = n > 0 ? sqrt(sum / n) : 0.0;
    *max = mx;
}

static int all_finite(const float* a, int n) {
    for (int i = 0; i < n; ++i)
        if (!isfinite(a[i])) return 0;
    return 1;
}

void bench_run_free(bench_run* r) {
    if (!r) return;
    free(r->x0);
    free(r->x);
    free(r->track);
    free(r->xs);
    r->x0 = r->x = r->xs = NULL;
    r->track = NULL;
}

static double cpu_ms_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * (double)t.tv_sec + 1e-6 * (double)t.tv_nsec;
}

static double total_energy(const weft_cloth_energy* e) { return e->kinetic + e->elastic + e->gravity; }

/* The run's facts from the cloth: sizes, threads, its rest shape and the energy scale. */
static int start(bench_run* out, const scene_host* h, const weft_cloth_def* def, int frames, int record, char* msg,
                 size_t size) {
    const weft_cloth_info* in = &h->info;
    out->particles = in->n_particles;
    out->vertices = in->n_vertices;
    out->threads = in->threads;
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) d2 += (in->bbox_max[k] - in->bbox_min[k]) * (in->bbox_max[k] - in->bbox_min[k]);
    out->diag = sqrt(d2);
    const size_t n3 = 3 * (size_t)(in->n_vertices > 0 ? in->n_vertices : 1);
    out->x0 = malloc(n3 * sizeof(float));
    out->x = malloc(n3 * sizeof(float));
    out->track = calloc((size_t)(frames > 0 ? frames : 1) * 4, sizeof(double));
    if (record) out->xs = malloc(n3 * (size_t)(frames > 0 ? frames : 1) * sizeof(float));
    if (!out->x0 || !out->x || !out->track || (record && !out->xs)) {
        snprintf(msg, size, "bench: out of memory");
        return -1;
    }
    memcpy(out->x0, h->positions, 3 * (size_t)in->n_vertices * sizeof(float));
    const double g = sqrt(def->gravity[0] * def->gravity[0] + def->gravity[1] * def->gravity[1] +
                          def->gravity[2] * def->gravity[2]);
    out->energy_scale = in->total_mass * g * out->diag;
    if (!(out->energy_scale > 0)) out->energy_scale = 1.0;
    return 0;
}

/* One frame's stats into the run's sums. */
static void add_frame(bench_run* out, const weft_frame_stats* st, long long* iterations) {
    *iterations += st->iterations;
    out->substeps += st->substeps;
    out->solves += st->solves;
    out->precond_ms += st->ms_precond;
    out->solve_ms += st->ms_solve;
    if (st->max_iterations > out->max_iterations) out->max_iterations = st->max_iterations;
    out->not_converged += st->not_converged;
    out->rollbacks += st->rollbacks;
    out->halvings += st->halvings;
    out->direct_fallbacks += st->direct_fallbacks;
    out->failures += st->failures;
    if (!(st->max_strain <= out->max_strain)) out->max_strain = st->max_strain;
}

/* The frame loop; -1 with msg when a call fails (a failed step is counted). */
static int simulate(bench_run* out, scene_host* h, const bench_scene* bs, const scene* sc, const bench_run_opts* o,
                    double* ms, char* msg, size_t size) {
    const double dt = 1.0 / o->fps;
    const int frames = o->frames > 0 ? o->frames : 1;
    long long iterations = 0;
    weft_cloth_energy e;
    if (weft_cloth_get_energy(h->ctx, h->cloth, &e) != WEFT_OK) {
        snprintf(msg, size, "%s: %s", bs->name, scene_host_error(h));
        return -1;
    }
    out->energy0 = out->energy_max = out->energy_end = total_energy(&e);
    for (int f = 0; f < frames; ++f) {
        weft_frame fr = scene_host_frame(h, sc, f + 1, dt);
        if (bs->spin != 0)   /* the twirl: every pin group bound at rest, turned about y */
            for (int i = 0; i < h->n_attachments; ++i)
                bench_scene_pin_transform(bs, dt * (f + 1), h->attachment_xf + 16 * (size_t)i);
        weft_frame_stats st;
        memset(&st, 0, sizeof st);
        const double cpu0 = cpu_ms_now();
        const weft_status s = weft_cloth_step(h->ctx, h->cloth, &fr, &st);
        ms[(size_t)6 * frames + f] = cpu_ms_now() - cpu0;
        if (s != WEFT_OK && s != WEFT_ERROR_STEP_FAILED) {
            snprintf(msg, size, "%s: frame %d: %s", bs->name, f + 1, scene_host_error(h));
            return -1;
        }
        if (s == WEFT_ERROR_STEP_FAILED) ++out->failures;   /* no stats: the cloth is as before the call */
        const double stage[6] = {st.ms_forces, st.ms_assemble, st.ms_solve, st.ms_collide, st.ms_integrate, st.ms_total};
        for (int k = 0; k < 6; ++k) ms[(size_t)k * frames + f] = stage[k];
        out->frames = f + 1;
        add_frame(out, &st, &iterations);
        if (weft_cloth_get_energy(h->ctx, h->cloth, &e) != WEFT_OK) {
            snprintf(msg, size, "%s: frame %d: %s", bs->name, f + 1, scene_host_error(h));
            return -1;
        }
        const double en = total_energy(&e);
        double* tr = out->track + 4 * (size_t)f;
        for (int c = 0; c < 3; ++c) tr[c] = e.center_of_mass[c];
        tr[3] = e.kinetic;
        out->energy_end = en;
        if (!(en <= out->energy_max)) out->energy_max = en;
        if (!isfinite(en) || !isfinite(st.max_strain)) out->nonfinite = 1;
        if (o->record_frames) {
            if (scene_host_read_positions(h) != WEFT_OK) {
                snprintf(msg, size, "%s: frame %d: %s", bs->name, f + 1, scene_host_error(h));
                return -1;
            }
            const size_t n3 = 3 * (size_t)out->vertices;
            memcpy(out->xs + n3 * (size_t)f, h->positions, n3 * sizeof(float));
        }
        if (out->nonfinite || (o->fail_strain > 0 && st.max_strain > o->fail_strain) ||
            (o->fail_energy > 0 && (en - out->energy0) / out->energy_scale > o->fail_energy))
            break;
    }
    out->iterations = out->substeps > 0 ? (double)iterations / (double)out->substeps : 0.0;
    out->iterations_total = iterations;
    return 0;
}

int bench_run_scene(const bench_scene* bs, const bench_run_opts* o, bench_run* out, char* msg, size_t size) {
    memset(out, 0, sizeof *out);
    scene sc = bs->sc;   /* the scene with the run's def and frame rate (its arrays shared, read only) */
    sc.def = o->def;
    sc.fps = o->fps;
    scene_host_opts ho;
    memset(&ho, 0, sizeof ho);
    ho.ctx = bench_backend_context(o->backend);
    if (!ho.ctx) {
        snprintf(msg, size, "bench: the %s backend is not open", bench_backend_name(o->backend));
        return -1;
    }
    scene_host h;
    if (scene_host_create(&h, &sc, &ho, bs->name, msg, size) != WEFT_OK) return -1;
    const int frames = o->frames > 0 ? o->frames : 1;
    double* ms = malloc(sizeof(double) * (size_t)frames * 7);   /* 5 stages, the total, CPU time */
    int rc = ms ? start(out, &h, &sc.def, frames, o->record_frames, msg, size) : -1;
    if (!ms) snprintf(msg, size, "bench: out of memory");
    if (rc == 0) rc = simulate(out, &h, bs, &sc, o, ms, msg, size);
    if (rc == 0 && scene_host_read_positions(&h) != WEFT_OK) {
        snprintf(msg, size, "%s: %s", bs->name, scene_host_error(&h));
        rc = -1;
    }
    if (rc == 0) {
        memcpy(out->x, h.positions, 3 * (size_t)out->vertices * sizeof(float));
        if (!all_finite(out->x, 3 * out->vertices)) out->nonfinite = 1;
        if (out->frames > 0) {
            out->ms_median = cli_sort_median(ms + (size_t)5 * frames, out->frames);
            out->cpu_ms_median = cli_sort_median(ms + (size_t)6 * frames, out->frames);
            for (int k = 0; k < 5; ++k) out->stage_median[k] = cli_sort_median(ms + (size_t)k * frames, out->frames);
        }
    }
    free(ms);
    scene_host_destroy(&h);
    if (rc != 0) bench_run_free(out);
    return rc;
}

/* Solves, or the substeps when the stats counted none. */
static double solves_of(const bench_run* r) {
    return r->solves > 0 ? (double)r->solves : (double)r->substeps;
}

double bench_run_iterations_per_solve(const bench_run* r) {
    const double n = solves_of(r);
    return n > 0 ? (double)r->iterations_total / n : 0.0;
}

double bench_run_precond_ms_per_solve(const bench_run* r) {
    const double n = solves_of(r);
    return n > 0 ? r->precond_ms / n : 0.0;
}

double bench_run_solve_ms_per_solve(const bench_run* r) {
    const double n = solves_of(r);
    return n > 0 ? r->solve_ms / n : 0.0;
}

double bench_run_converged_fraction(const bench_run* r) {
    const double n = solves_of(r);
    return n > 0 ? 1.0 - (double)r->not_converged / n : 1.0;
}
