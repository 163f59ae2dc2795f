/* The linear-solve error of each solver against CHOLMOD on the very system the step solves (a
 * benchmark: prints a table; with --check it also asserts what must hold). `weft bench accuracy`
 * runs through the public API, which does not reach the step's own system: this program steps
 * core's wc_state directly. For every scene x solver x preconditioner (PCG) x tolerance x
 * iteration cap x substeps per frame, the scene is stepped for --seconds (backward Euler, one
 * Newton iteration) and before the first substep of --probes evenly spread frames a second state
 * mirroring the run's (positions, velocities, initial guess, contacts, pins) builds the substep's
 * system exactly as the step will (wc_substep_prepare) and solves it with the run's solver and
 * with CHOLMOD from the same initial guess: ||dv - dv_direct|| / ||dv_direct||, mean and largest.
 *
 *   bench_linear_error [--scenes sheet16,drape16,garment] [--solvers pcg,jacobi,chebyshev,direct]
 *                      [--preconds block_jacobi,amg] [--tolerances 1e-3] [--caps 20,100]
 *                      [--substeps 1,2] [--seconds 0.3] [--fps 30] [--probes 2] [--threads 1]
 *                      [--garment FILE] [--check]
 * --check: every error finite, largest >= mean >= 0, and the direct solver's below 1e-9 (it is
 * CHOLMOD against itself); exit 1 otherwise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core_scene.h"
#include "step.h"

#define MAX_LIST 16

typedef struct args {
    char scenes[MAX_LIST][32];
    int n_scenes;
    wc_solver_type solvers[MAX_LIST];
    int n_solvers;
    wc_precond_type preconds[MAX_LIST];
    int n_preconds;
    double tolerances[MAX_LIST];
    int n_tolerances;
    int caps[MAX_LIST], n_caps;
    int substeps[MAX_LIST], n_substeps;
    double seconds, fps;
    int probes, threads, check;
    const char* garment;
} args;

/* Split a comma list into at most MAX_LIST items of < 32 characters; the count, -1 on a bad list. */
static int split(const char* text, char out[MAX_LIST][32]) {
    int n = 0;
    for (const char* p = text;; ++n) {
        const char* comma = strchr(p, ',');
        const size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == 0 || len >= 32 || n >= MAX_LIST) return -1;
        memcpy(out[n], p, len);
        out[n][len] = '\0';
        if (!comma) return n + 1;
        p = comma + 1;
    }
}

/* One option and its value into a. 0, or -1 (message on stderr). */
static int apply(args* a, const char* key, const char* v) {
    char items[MAX_LIST][32];
    const int n = v ? split(v, items) : -1;
    if (n < 0) return fprintf(stderr, "bench_linear_error: bad or missing value for %s\n", key), -1;
    if (!strcmp(key, "--scenes")) {
        memcpy(a->scenes, items, sizeof items);
        a->n_scenes = n;
    } else if (!strcmp(key, "--solvers") || !strcmp(key, "--preconds")) {
        const int solvers = key[2] == 's';
        for (int k = 0; k < n; ++k) {
            const int t = solvers ? wc_solver_from_name(items[k]) : wc_precond_from_name(items[k]);
            if (t < 0) return fprintf(stderr, "bench_linear_error: unknown name '%s'\n", items[k]), -1;
            if (solvers) a->solvers[k] = (wc_solver_type)t;
            else a->preconds[k] = (wc_precond_type)t;
        }
        *(solvers ? &a->n_solvers : &a->n_preconds) = n;
    } else if (!strcmp(key, "--tolerances")) {
        for (int k = 0; k < n; ++k) a->tolerances[k] = atof(items[k]);
        a->n_tolerances = n;
    } else if (!strcmp(key, "--caps") || !strcmp(key, "--substeps")) {
        const int caps = key[2] == 'c';
        for (int k = 0; k < n; ++k) (caps ? a->caps : a->substeps)[k] = atoi(items[k]);
        *(caps ? &a->n_caps : &a->n_substeps) = n;
    } else if (!strcmp(key, "--seconds")) a->seconds = atof(v);
    else if (!strcmp(key, "--fps")) a->fps = atof(v);
    else if (!strcmp(key, "--probes")) a->probes = atoi(v);
    else if (!strcmp(key, "--threads")) a->threads = atoi(v);
    else if (!strcmp(key, "--garment")) a->garment = v;
    else return fprintf(stderr, "bench_linear_error: unknown option %s\n", key), -1;
    return 0;
}

static int parse(int argc, char** argv, args* a) {
    static const char* const dflt[][2] = {{"--scenes", "sheet16,drape16,garment"},
                                          {"--solvers", "pcg,jacobi,chebyshev,direct"},
                                          {"--preconds", "block_jacobi,amg"}, {"--tolerances", "1e-3"},
                                          {"--caps", "20,100"}, {"--substeps", "1,2"}};
    memset(a, 0, sizeof *a);
    a->seconds = 0.3;
    a->fps = 30;
    a->probes = 2;
    a->threads = 1;
    a->garment = WEFT_SOURCE_DIR "/sample_scenes/skirt.obj";
    for (size_t k = 0; k < sizeof dflt / sizeof dflt[0]; ++k)
        if (apply(a, dflt[k][0], dflt[k][1]) != 0) return -1;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--check")) a->check = 1;
        else if (apply(a, argv[i], i + 1 < argc ? argv[i + 1] : NULL) != 0) return -1;
        else ++i;
    }
    if (!(a->seconds > 0) || !(a->fps > 0) || a->probes < 1 || a->threads < 0)
        return fprintf(stderr, "bench_linear_error: --seconds, --fps > 0, --probes >= 1, --threads >= 0\n"), -1;
    return 0;
}

/* The linear-solve error of the run's next substep (the first of the coming frame): the probe
 * state p takes s's positions, velocities, initial guess, contacts and pins, builds the system
 * exactly as the step will (wc_substep_prepare), and solves it with the run's solver and with
 * CHOLMOD from the same initial guess. ||dv - dv_direct|| / ||dv_direct||, or -1 when it could not
 * be measured. */
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
    if (wc_solve(p->solver, WC_SOLVER_DIRECT, p->A, p->b, &p->filter, dv_ref, &p->par, &r_ref) != WC_OK) return -1.0;
    double num = 0.0, den = 0.0;
    for (size_t k = 0; k < n3; ++k) {
        const double e = dv_it[k] - dv_ref[k];
        num += e * e;
        den += dv_ref[k] * dv_ref[k];
    }
    if (den == 0.0) return num == 0.0 ? 0.0 : INFINITY;
    return sqrt(num / den);
}

typedef struct probe_run {
    int probes;
    double mean, max;
} probe_run;

/* One configuration: the run and its probes. 0, or -1 (message on stderr). */
static int run(const core_scene* cs, const wc_sim_def* sd, const args* a, probe_run* out) {
    memset(out, 0, sizeof *out);
    wc_state *s = NULL, *p = NULL;
    wc_diag d = {0};
    wc_sim_def pd = *sd;
    pd.direct_fallback = 1; /* analyses CHOLMOD at creation whatever the solver */
    if (core_scene_state(&s, cs, sd, &d) != WC_OK || core_scene_state(&p, cs, &pd, &d) != WC_OK) {
        fprintf(stderr, "bench_linear_error: %s: %s\n", cs->name, d.message);
        wc_state_destroy(s);
        return -1;
    }
    const size_t n3 = 3 * (size_t)cs->model.n_particles;
    double* dv_it = malloc(n3 * sizeof(double));
    double* dv_ref = malloc(n3 * sizeof(double));
    wc_pin* pins = malloc(sizeof(wc_pin) * (size_t)(cs->n_pins + 1));
    const int frames = (int)lround(a->seconds * a->fps) > 0 ? (int)lround(a->seconds * a->fps) : 1;
    const double dt = 1.0 / a->fps, h = dt / sd->substeps, alpha1 = 1.0 / sd->substeps;
    int next = 0, rc = dv_it && dv_ref && pins ? 0 : -1;
    for (int f = 0; f < frames && rc == 0; ++f) {
        if (next < a->probes && f == (int)((long long)next * frames / a->probes)) {
            ++next;
            const double e = probe_error(p, s, h, alpha1, dv_it, dv_ref);
            if (e >= 0 || isnan(e)) {
                out->mean += e;
                if (!(e <= out->max)) out->max = e;
                ++out->probes;
            }
        }
        if (cs->spin != 0) {
            core_scene_pins_at(cs, dt * (f + 1), pins);
            wc_state_set_pins(s, pins, cs->n_pins, &d);
        }
        wc_step_frame(s, dt, NULL, &d);
    }
    if (out->probes > 0) out->mean /= out->probes;
    free(dv_it);
    free(dv_ref);
    free(pins);
    wc_state_destroy(s);
    wc_state_destroy(p);
    return rc;
}

int main(int argc, char** argv) {
    args a;
    if (parse(argc, argv, &a) != 0) return 2;
    int bad = 0;
    printf("| scene | particles | solver | precond. | tol. | cap | substeps | probes | lin. err mean | lin. err max |\n"
           "|---|---|---|---|---|---|---|---|---|---|\n");
    for (int si = 0; si < a.n_scenes; ++si) {
        core_scene cs;
        char msg[512];
        if (core_scene_build(&cs, a.scenes[si], a.garment, msg, sizeof msg) != 0) {
            fprintf(stderr, "bench_linear_error: %s\n", msg);
            return 1;
        }
        for (int s = 0; s < a.n_solvers; ++s) {
            const int pcg = a.solvers[s] == WC_SOLVER_PCG, direct = a.solvers[s] == WC_SOLVER_DIRECT;
            for (int q = 0; q < (pcg ? a.n_preconds : 1); ++q)
                for (int t = 0; t < (direct ? 1 : a.n_tolerances); ++t)
                    for (int c = 0; c < (direct ? 1 : a.n_caps); ++c)
                        for (int u = 0; u < a.n_substeps; ++u) {
                            wc_sim_def sd = wc_default_sim_def();
                            sd.threads = a.threads;
                            sd.sleep_speed = 0.0;
                            sd.solver.type = a.solvers[s];
                            sd.solver.preconditioner = pcg ? a.preconds[q] : WC_PRECOND_BLOCK_JACOBI;
                            if (!direct) {
                                sd.solver.tolerance = a.tolerances[t];
                                sd.solver.max_iterations = a.caps[c];
                            }
                            sd.substeps = a.substeps[u];
                            probe_run r;
                            if (run(&cs, &sd, &a, &r) != 0) {
                                core_scene_free(&cs);
                                return 1;
                            }
                            char tol[32] = "-", cap[32] = "-";
                            if (!direct) {
                                snprintf(tol, sizeof tol, "%g", sd.solver.tolerance);
                                snprintf(cap, sizeof cap, "%d", sd.solver.max_iterations);
                            }
                            printf("| %s | %d | %s | %s | %s | %s | %d | %d | %.3g | %.3g |\n", cs.name,
                                   cs.model.n_particles, wc_solver_name(sd.solver.type),
                                   pcg ? wc_precond_name(sd.solver.preconditioner) : "-", tol, cap, sd.substeps,
                                   r.probes, r.mean, r.max);
                            const int ok = r.probes > 0 && isfinite(r.mean) && isfinite(r.max) && r.max >= r.mean &&
                                           r.mean >= 0 && (!direct || r.max < 1e-9);
                            if (!ok) fprintf(stderr, "  check failed on the row above\n");
                            bad += !ok;
                        }
        }
        core_scene_free(&cs);
    }
    if (a.check && bad) fprintf(stderr, "bench_linear_error: %d row(s) failed the check\n", bad);
    return a.check && bad ? 1 : 0;
}
