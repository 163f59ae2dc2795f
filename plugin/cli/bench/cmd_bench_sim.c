/* Benchmark scenes (built through the scene-file parser, so they are ordinary Weft scenes) and one
 * measured run of a scene: frame timings, solver and recovery counts, strain, energy, and the
 * linear-solve error against CHOLMOD on the very system the step solves (wc_substep_prepare on a
 * second state that mirrors the run's; CPU runs only). A run steps core's wc_step_frame (CPU) or
 * gpu/'s wg_sim_step_frame on the process's headless device (GPU), the wc_state serving as the
 * GPU's mirror: its positions are downloaded after every frame for the same checks. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cmd_bench.h"
#include "sort.h"
#include "vec3.h"

/* ---------- scenes ---------- */

/* Copy text into buf as the inside of a JSON string (quotes and backslashes escaped); -1 when it
 * has control characters or does not fit. */
static int json_escape(const char* text, char* buf, size_t size) {
    size_t k = 0;
    for (const char* c = text; *c; ++c) {
        if ((unsigned char)*c < 0x20) return -1;
        if (*c == '"' || *c == '\\') {
            if (k + 1 >= size) return -1;
            buf[k++] = '\\';
        }
        if (k + 1 >= size) return -1;
        buf[k++] = *c;
    }
    buf[k] = '\0';
    return 0;
}

/* The scene's JSON text for name, or -1 (with diag) when the name is unknown. */
static int scene_json(const char* name, const char* garment, char* json, size_t size, wc_diag* diag) {
    int n = 0;
    if (!strncmp(name, "sheet", 5) && cli_parse_int(name + 5, 2, 2048, &n) == 0) {
        /* grid vertex i + n j lies at x = -0.5 + i / (n - 1), z = -0.5 + j / (n - 1) (scene.h) */
        snprintf(json, size,
                 "{\"mesh\": {\"grid\": {\"n\": [%d, %d], \"size\": [1, 1]}},"
                 " \"pins\": [{\"vertices\": [%d, %d]}]}",
                 n, n, n * (n - 1), n * n - 1);
        return 0;
    }
    if (!strncmp(name, "hang", 4) && cli_parse_int(name + 4, 2, 2048, &n) == 0) {
        /* the grid turned upright (z -> -y): vertices 0 and n - 1 (j = 0) are the top corners */
        snprintf(json, size,
                 "{\"mesh\": {\"grid\": {\"n\": [%d, %d], \"size\": [1, 1]}},"
                 " \"transform\": [1, 0, 0, 0,  0, 0, 1, 0,  0, -1, 0, 0,  0, 0, 0, 1],"
                 " \"pins\": [{\"vertices\": [0, %d]}]}",
                 n, n, n - 1);
        return 0;
    }
    if (!strcmp(name, "drape") || (!strncmp(name, "drape", 5) && cli_parse_int(name + 5, 2, 2048, &n) == 0)) {
        if (n == 0) n = 64;
        snprintf(json, size,
                 "{\"mesh\": {\"grid\": {\"n\": [%d, %d], \"size\": [1, 1]}},"
                 " \"transform\": [1, 0, 0, 0,  0, 1, 0, 0,  0, 0, 1, 0,  0, 0.3, 0, 1],"
                 " \"colliders\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.25}]}",
                 n, n);
        return 0;
    }
    if (!strcmp(name, "garment")) {
        char path[1024];
        if (!garment || json_escape(garment, path, sizeof path) != 0) {
            wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "garment: unusable mesh path");
            return -1;
        }
        snprintf(json, size,
                 "{\"mesh\": {\"file\": \"%s\"},"
                 " \"pins\": [{\"select\": {\"axis\": \"y\", \"side\": \"max\", \"tolerance\": 0.001}}]}",
                 path);
        return 0;
    }
    wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
            "unknown scene '%s' (expected sheetN, hangN, drape, drapeN or garment; N from 2 to 2048)", name);
    return -1;
}

/* Every pinned host vertex of the scene's pin groups as one pin of its particle (vertices without
 * a particle skipped, welded twins merged), fully pinned or on its free axis, at rest. */
static wc_status bench_pins_resolve(bench_pins* out, const scene* sc, const wc_model* m, wc_diag* diag) {
    int total = 0;
    for (int g = 0; g < sc->n_pin_groups; ++g) total += sc->pin_groups[g].n_vertices;
    out->pins = calloc((size_t)total + 1, sizeof(wc_pin));
    out->start = calloc(3 * (size_t)total + 3, sizeof(double));
    unsigned char* seen = calloc((size_t)m->n_particles + 1, 1);
    if (!out->pins || !out->start || !seen) {
        free(seen);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "bench: out of memory for %d pins", total);
    }
    out->n = 0;
    for (int g = 0; g < sc->n_pin_groups; ++g) {
        const scene_pin_group* pg = &sc->pin_groups[g];
        for (int k = 0; k < pg->n_vertices; ++k) {
            int v = pg->vertices[k];
            int p = (v >= 0 && v < m->n_host_verts) ? m->host_to_particle[v] : -1;
            if (p < 0 || seen[p]) continue;
            seen[p] = 1;
            wc_pin* pin = &out->pins[out->n];
            pin->particle = p;
            v3_copy(pin->target, m->rest_pos + 3 * p);
            v3_copy(pin->free_axis, pg->free_axis);
            v3_copy(out->start + 3 * out->n, m->rest_pos + 3 * p);
            ++out->n;
        }
    }
    free(seen);
    return WC_OK;
}

static void bench_pins_free(bench_pins* p) {
    free(p->pins);
    free(p->start);
    memset(p, 0, sizeof *p);
}

/* The scene's mesh, model def, sim def and colliders in core's forms. */
static wc_status scene_to_core(bench_scene* bs, wc_diag* diag) {
    const scene* s = &bs->sc;
    const weft_cloth_def* d = &s->def;
    wc_status st = wc_source_mesh_from_arrays(&bs->src, NULL, s->mesh.positions, s->mesh.n_vertices,
                                              s->mesh.face_sizes, s->mesh.n_faces, s->mesh.indices, 1.0, diag);
    if (st != WC_OK) return st;
    bs->model_def = wc_default_model_def();
    bs->model_def.weld_tolerance = d->weld_tolerance;
    bs->model_def.material.density = d->material.density;
    for (int t = 0; t < 3; ++t) {
        bs->model_def.material.k[t] = d->material.stiffness[t];
        bs->model_def.material.d[t] = d->material.damping[t];
    }
    bs->sim = wc_default_sim_def();
    for (int k = 0; k < 3; ++k) {
        bs->sim.gravity[k] = d->gravity[k];
        bs->sim.air.wind[k] = d->wind[k];
    }
    bs->sim.air.normal_drag = d->air_drag_normal;
    bs->sim.air.tangent_drag = d->air_drag_tangent;
    bs->sim.solver.type = (wc_solver_type)d->solver;
    bs->sim.solver.tolerance = d->tolerance;
    bs->sim.solver.max_iterations = d->max_iterations;
    bs->sim.substeps = d->substeps;
    bs->sim.strain_limit = d->strain_limit;
    bs->sim.threads = s->threads;
    bs->n_colliders = s->n_colliders;
    bs->colliders = calloc((size_t)s->n_colliders + 1, sizeof(wc_collider));
    if (!bs->colliders) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "bench: out of memory");
    for (int i = 0; i < s->n_colliders; ++i) {
        const scene_collider* c = &s->colliders[i];
        wc_collider* w = &bs->colliders[i];
        w->type = (int)c->type;   /* the same numbering */
        v3_copy(w->normal, c->normal);
        w->offset = c->offset;
        v3_copy(w->center, c->center);
        v3_copy(w->a, c->a);
        v3_copy(w->b, c->b);
        w->radius = c->radius;
        w->thickness = c->thickness;
        w->friction = c->friction;
    }
    return WC_OK;
}

wc_status bench_scene_build(bench_scene* out, const char* name, const char* garment, double k_scale,
                              double mass_scale, wc_diag* diag) {
    memset(out, 0, sizeof *out);
    char json[1536];
    if (scene_json(name, garment, json, sizeof json, diag) != 0) return diag->status;
    snprintf(out->name, sizeof out->name, "%s", name);
    cli_diag sd = {0};
    if (scene_parse(&out->sc, json, strlen(json), name, &sd) != WEFT_OK)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "%s", sd.message);
    wc_status st = scene_to_core(out, diag);
    if (st != WC_OK) {
        bench_scene_free(out);
        return st;
    }
    wc_material* mat = &out->model_def.material;
    for (int t = 0; t < WC_SPRING_TYPE_COUNT; ++t) mat->k[t] *= k_scale;
    mat->density *= mass_scale;
    st = wc_model_build(&out->model, &out->src, &out->model_def, NULL, diag);
    if (st == WC_OK) st = bench_pins_resolve(&out->pins, &out->sc, &out->model, diag);
    if (st != WC_OK) {
        bench_scene_free(out);
        return st;
    }
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) {
        double e = out->model.report.bbox_max[c] - out->model.report.bbox_min[c];
        d2 += e * e;
    }
    out->diag = sqrt(d2);
    if (!strcmp(name, "garment")) out->spin = BENCH_GARMENT_SPIN;
    return WC_OK;
}

void bench_scene_free(bench_scene* s) {
    if (!s) return;
    bench_pins_free(&s->pins);
    if (s->model.n_particles > 0) wc_model_free(&s->model);
    wc_source_mesh_free(&s->src);
    free(s->colliders);
    scene_free(&s->sc);
    memset(s, 0, sizeof *s);
}

/* ---------- measurements ---------- */

void bench_distance(const double* a, const double* b, int n, double* rms, double* max) {
    double sum = 0.0, mx = 0.0;
    for (int i = 0; i < n; ++i) {
        double d[3];
        v3_sub(d, a + 3 * i, b + 3 * i);
        double e = v3_norm(d);
        sum += e * e;
        if (!(e <= mx)) mx = e; /* a NaN distance wins */
    }
    *rms = n > 0 ? sqrt(sum / n) : 0.0;
    *max = mx;
}

static int all_finite(const double* a, int n) {
    for (int i = 0; i < n; ++i)
        if (!isfinite(a[i])) return 0;
    return 1;
}

/* The linear-solve error of the run's next substep (the first of the coming frame): the probe
 * state p takes s's positions, velocities, initial guess and contacts, builds the system exactly
 * as the step will (wc_substep_prepare), and solves it with the run's solver and with CHOLMOD
 * from the same initial guess. Returns ||dv - dv_direct|| / ||dv_direct||, or -1 when it could
 * not be measured. */
static double probe_error(wc_state* p, const wc_state* s, double h, double alpha1, double* dv_it, double* dv_ref) {
    const int n = s->model->n_particles;
    const size_t n3 = 3 * (size_t)n;
    wc_diag d = {0};
    if (wc_state_set_positions(p, s->x, s->v, &d) != WC_OK) return -1.0;
    memcpy(p->dv, s->dv, n3 * sizeof(double));
    memcpy(p->contacts.collider, s->contacts.collider, 2 * (size_t)n * sizeof(int));
    memcpy(p->contacts.normal, s->contacts.normal, 6 * (size_t)n * sizeof(double));
    memcpy(p->contacts.released, s->contacts.released, (size_t)n);
    p->contacts.active = s->contacts.active;
    memcpy(p->pins, s->pins, (size_t)s->n_pins * sizeof(wc_pin));
    memcpy(p->pin_from, s->pin_from, 3 * (size_t)s->n_pins * sizeof(double));
    wc_step_stats st;
    memset(&st, 0, sizeof st);
    wc_substep_prepare(p, h, alpha1, &st);
    memcpy(dv_it, p->dv, n3 * sizeof(double));
    memcpy(dv_ref, p->dv, n3 * sizeof(double));
    wc_solve_result r_it, r_ref;
    wc_solve(p->solver, s->def.solver.type, p->A, p->b, &p->filter, dv_it, &p->par, &r_it);
    if (wc_solve(p->solver, WC_SOLVER_DIRECT, p->A, p->b, &p->filter, dv_ref, &p->par, &r_ref) != WC_OK)
        return -1.0;
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < n3; ++k) {
        double e = dv_it[k] - dv_ref[k];
        num += e * e;
        den += dv_ref[k] * dv_ref[k];
    }
    if (den == 0.0) return num == 0.0 ? 0.0 : INFINITY;
    return sqrt(num / den);
}

/* A fixed pseudo-random number in [-1, 1) from a 64-bit key (splitmix64's finaliser). */
static double hash_unit(unsigned long long z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) * 0x1.0p-52 - 1.0;
}

/* Every particle the scene does not pin moved by eps along its own direction (bench_run_opts.
 * displace): the same displacement on every run, whatever the solver or the step. */
static void displace_start(wc_state* s, const bench_scene* bs, double eps) {
    const wc_model* m = &bs->model;
    for (int i = 0; i < m->n_particles; ++i) {
        int pinned = 0;
        for (int k = 0; k < bs->pins.n && !pinned; ++k) pinned = bs->pins.pins[k].particle == i;
        if (pinned) continue;
        double d[3];
        for (int c = 0; c < 3; ++c) d[c] = hash_unit(3ULL * (unsigned long long)i + (unsigned long long)c);
        const double len = v3_norm(d);
        if (len > 0)
            for (int c = 0; c < 3; ++c) s->x[3 * i + c] += eps * d[c] / len;
    }
}

static wc_status make_state(wc_state** out, const bench_scene* bs, const wc_sim_def* sd, wc_diag* diag) {
    wc_status st = wc_state_create(out, &bs->model, sd, NULL, diag);
    if (st == WC_OK) st = wc_state_set_pins(*out, bs->pins.pins, bs->pins.n, diag);
    if (st == WC_OK) st = wc_state_set_colliders(*out, bs->colliders, bs->n_colliders, diag);
    if (st != WC_OK) {
        wc_state_destroy(*out);
        *out = NULL;
    }
    return st;
}

void bench_run_free(bench_run* r) {
    if (!r) return;
    free(r->x);
    free(r->track);
    r->x = NULL;
    r->track = NULL;
}

int bench_run_scene(const bench_scene* bs, const bench_run_opts* o, bench_run* out, wc_diag* diag) {
    memset(out, 0, sizeof *out);
    const wc_model* m = &bs->model;
    const int n = m->n_particles;
    const size_t n3 = 3 * (size_t)n;
    wc_sim_def sd = o->sim;
    sd.max_pins = bs->pins.n > 0 ? bs->pins.n : 1;
    sd.max_colliders = bs->n_colliders > 16 ? bs->n_colliders : 16;
    sd.sleep_speed = 0.0; /* these benchmarks time active steps: a cloth that came to rest is not put to sleep */
    const int gpu = o->backend == BENCH_GPU;
    wc_state *s = NULL, *p = NULL;
    bench_gpu_sim* g = NULL;
    if (make_state(&s, bs, &sd, diag) != WC_OK) return -1;
    if (o->displace > 0) displace_start(s, bs, o->displace);
    /* the GPU's sim mirrors s: s keeps pins, colliders, time and stats; x, v, dv live on the GPU */
    if (gpu && bench_gpu_sim_create(s, &g, diag) != WC_OK) {
        wc_state_destroy(s);
        return -1;
    }
    if (o->probe_frames > 0 && !gpu) { /* the linear-solve error is the CPU's only */
        wc_sim_def pd = sd;
        pd.direct_fallback = 1; /* analyses CHOLMOD at creation whatever the solver */
        if (make_state(&p, bs, &pd, diag) != WC_OK) {
            wc_state_destroy(s);
            bench_gpu_sim_destroy(g);
            return -1;
        }
    }
    const int frames = o->frames > 0 ? o->frames : 1;
    double* ms = malloc(sizeof(double) * (size_t)frames * 6);
    wc_pin* pins = malloc(sizeof(wc_pin) * (size_t)(bs->pins.n > 0 ? bs->pins.n : 1));
    double* dv_it = p ? malloc(n3 * sizeof(double)) : NULL;
    double* dv_ref = p ? malloc(n3 * sizeof(double)) : NULL;
    out->x = malloc(n3 * sizeof(double));
    out->track = calloc((size_t)frames * 4, sizeof(double));
    if (!ms || !pins || !out->x || !out->track || (p && (!dv_it || !dv_ref))) {
        free(ms);
        free(pins);
        free(dv_it);
        free(dv_ref);
        bench_run_free(out);
        bench_gpu_sim_destroy(g);
        wc_state_destroy(s);
        wc_state_destroy(p);
        wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "bench: out of memory");
        return -1;
    }
    const double dt = 1.0 / o->fps;
    const double h = sd.substep_dt > 0 ? sd.substep_dt : dt / sd.substeps;
    const double alpha1 = sd.substep_dt > 0 ? fmin(1.0, sd.substep_dt / dt) : 1.0 / sd.substeps;
    out->energy0 = out->energy_max = out->energy_end = wc_state_total_energy(s, NULL);
    out->energy_scale = s->total_mass * v3_norm(sd.gravity) * bs->diag;
    if (!(out->energy_scale > 0)) out->energy_scale = 1.0;
    long long iterations = 0;
    int next_probe = 0, gpu_error = 0;
    for (int f = 0; f < frames; ++f) {
        if (p && next_probe < o->probe_frames && f == (int)((long long)next_probe * frames / o->probe_frames)) {
            ++next_probe;
            double e = probe_error(p, s, h, alpha1, dv_it, dv_ref);
            if (e >= 0 || isnan(e)) {
                out->lin_err_mean += e;
                if (!(e <= out->lin_err_max)) out->lin_err_max = e;
                ++out->probes;
            }
        }
        wc_step_stats st;
        wc_diag d = {0};
        if (bs->spin != 0) {
            /* the pins' targets at the end of this frame: their rest positions turned about y, the
             * turning rate ramped up linearly from 0 over the first BENCH_GARMENT_RAMP seconds */
            const double t = dt * (f + 1), ramp = BENCH_GARMENT_RAMP;
            const double angle = bs->spin * (t < ramp ? 0.5 * t * t / ramp : t - 0.5 * ramp);
            const double c = cos(angle), sn = sin(angle);
            for (int k = 0; k < bs->pins.n; ++k) {
                const double* r = bs->pins.start + 3 * k;
                pins[k] = bs->pins.pins[k];
                v3_set(pins[k].target, c * r[0] + sn * r[2], r[1], -sn * r[0] + c * r[2]);
            }
            wc_state_set_pins(s, pins, bs->pins.n, &d); /* the GPU uploads s's pins every frame */
        }
        if (gpu) {
            /* timed by the step's own stats (st.ms); the download is outside them */
            const wc_status fs = bench_gpu_sim_step(g, s, dt, &st, &d);
            wc_status ds = WC_OK;
            if (fs == WC_OK || fs == WC_ERROR_STEP_FAILED) ds = bench_gpu_sim_download(g, s, &d);
            if ((fs != WC_OK && fs != WC_ERROR_STEP_FAILED) || ds != WC_OK) {
                wc_fail(diag, d.status, "%s (frame %d on the GPU)", d.message, f + 1);
                gpu_error = 1;
                break;
            }
        } else {
            wc_step_frame(s, dt, &st, &d);
        }
        const double stage[6] = {st.ms.forces, st.ms.assemble, st.ms.solve, st.ms.collide, st.ms.integrate, st.ms.total};
        for (int k = 0; k < 6; ++k) ms[(size_t)k * frames + f] = stage[k];
        out->frames = f + 1;
        iterations += st.iterations;
        out->substeps += st.substeps;
        out->solves += st.solves;
        out->precond_ms += st.precond_ms;
        out->solve_ms += st.ms.solve;
        if (st.max_iterations > out->max_iterations) out->max_iterations = st.max_iterations;
        out->not_converged += st.not_converged;
        out->rollbacks += st.rollbacks;
        out->halvings += st.halvings;
        out->direct_fallbacks += st.direct_fallbacks;
        out->failures += st.failures;
        if (!(st.max_strain <= out->max_strain)) out->max_strain = st.max_strain;
        const double e = wc_state_total_energy(s, NULL);
        double* tr = out->track + 4 * (size_t)f;
        for (int i = 0; i < s->model->n_particles; ++i)
            for (int c = 0; c < 3; ++c) tr[c] += s->model->mass[i] * s->x[3 * i + c] / s->total_mass;
        tr[3] = wc_state_kinetic_energy(s);
        out->energy_end = e;
        if (!(e <= out->energy_max)) out->energy_max = e;
        if (!isfinite(e) || !isfinite(st.max_strain) || !all_finite(s->x, (int)n3)) out->nonfinite = 1;
        if (out->nonfinite || (o->fail_strain > 0 && st.max_strain > o->fail_strain) ||
            (o->fail_energy > 0 && (e - out->energy0) / out->energy_scale > o->fail_energy))
            break;
    }
    if (out->frames > 0) {
        out->ms_median = wc_sort_median(ms + (size_t)5 * frames, out->frames);
        for (int k = 0; k < 5; ++k) out->stage_median[k] = wc_sort_median(ms + (size_t)k * frames, out->frames);
    }
    out->iterations = out->substeps > 0 ? (double)iterations / (double)out->substeps : 0.0;
    out->iterations_total = iterations;
    if (out->probes > 0) out->lin_err_mean /= out->probes;
    memcpy(out->x, s->x, n3 * sizeof(double));
    free(ms);
    free(pins);
    free(dv_it);
    free(dv_ref);
    bench_gpu_sim_destroy(g);
    wc_state_destroy(s);
    wc_state_destroy(p);
    if (gpu_error) {
        bench_run_free(out);
        return -1;
    }
    return 0;
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
