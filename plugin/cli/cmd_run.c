/* `weft run SCENE.json`: load a scene, build the model and state, step every frame, and write OBJ
 * frames, a stats JSON and a summary table. Exit codes: 0 ok (frames whose step failed after every
 * recovery are counted, not fatal), 1 the scene is invalid or something else failed (one line on
 * stderr), 2 bad command line. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "clock.h"
#include "model.h"
#include "run.h"
#include "scene.h"
#include "state.h"
#include "step.h"
#include "weft/weft.h"

typedef struct run_args {
    const char* scene;
    int frames;            /* -1: the scene's */
    int solver;            /* -1: the scene's, else wc_solver_type */
    const char* out;       /* folder for OBJ frames, NULL: none */
    const char* stats;     /* stats JSON path, NULL: none */
    int threads;           /* -1: the scene's */
    int quiet;
} run_args;

void cli_run_usage(FILE* out) {
    fputs("usage: weft run SCENE.json [--frames N] [--solver pcg|jacobi|chebyshev|direct]\n"
          "                [--out DIR] [--stats FILE.json] [--threads N] [--quiet]\n"
          "\n"
          "Simulate the scene (schema: sample_scenes/README.md) frame by frame at 1/fps seconds\n"
          "and print a summary table at the end.\n"
          "\n"
          "options:\n"
          "  --frames N             frames to simulate (>= 0; default: the scene's time.frames)\n"
          "  --solver NAME          linear solver, overriding the scene's solver.type\n"
          "  --out DIR              write DIR/frame_0001.obj ... (created if missing): every host\n"
          "                         vertex in the mesh's own order, then its polygons\n"
          "  --stats FILE.json      write timings, solver and recovery counts as one JSON object\n"
          "  --threads N            OpenMP threads (>= 0; 0: OpenMP's default)\n"
          "  --quiet                print nothing on success\n"
          "  -h, --help             show this help\n",
          out);
}

#define usage_error(...) cli_usage_error("weft run", cli_run_usage, __VA_ARGS__)

/* Returns -1 to continue, or an exit code (help printed, or a usage error). */
static int parse_args(int argc, char** argv, run_args* a) {
    int only_files = 0;
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        const char* value = NULL;
        int m;
        if (only_files || arg[0] != '-' || strcmp(arg, "-") == 0) {
            if (a->scene) return usage_error("more than one SCENE ('%s')", arg);
            a->scene = arg;
        } else if (strcmp(arg, "--") == 0) {
            only_files = 1;
        } else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            cli_run_usage(stdout);
            return CLI_EXIT_OK;
        } else if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0) {
            a->quiet = 1;
        } else if ((m = cli_option_value(argc, argv, &i, "--frames", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_int(value, 0, 100000000, &a->frames) != 0)
                return usage_error("--frames must be an integer in [0, 100000000], not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--solver", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            a->solver = wc_solver_from_name(value);
            if (a->solver < 0)
                return usage_error("unknown solver '%s' (expected pcg, jacobi, chebyshev or direct)", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--threads", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_int(value, 0, 1024, &a->threads) != 0)
                return usage_error("--threads must be an integer in [0, 1024], not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0 || !value[0]) return usage_error("%s needs a folder", arg);
            a->out = value;
        } else if ((m = cli_option_value(argc, argv, &i, "--stats", &value)) != 0) {
            if (m < 0 || !value[0]) return usage_error("%s needs a file name", arg);
            a->stats = value;
        } else {
            return usage_error("unknown option '%s'", arg);
        }
    }
    if (!a->scene) return usage_error("missing SCENE");
    return -1;
}

/* Everything a run owns, released by run_release. */
typedef struct run_ctx {
    scene sc;
    wc_model model;
    scene_pins pins;
    wc_state* state;
    double* host_pos;      /* (sc.src.n_verts x 3) output positions of one frame */
    char* path;            /* OBJ path buffer */
    run_record rec;
} run_ctx;

static void run_release(run_ctx* c) {
    wc_state_destroy(c->state);
    scene_pins_free(&c->pins);
    wc_model_free(&c->model);
    scene_free(&c->sc);
    free(c->host_pos);
    free(c->path);
    free(c->rec.frame_ms);
    free(c->rec.stage_ms);
}

static int fail(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
static int fail(const char* fmt, ...) {
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    cli_error(line);
    return CLI_EXIT_FAILURE;
}

static const char* diag_text(const wc_diag* d, weft_status st) {
    return d->message[0] ? d->message : weft_status_string(st);
}

/* Host positions: a vertex with a particle follows it, one without keeps its source position.
 * Returns the number of host vertices with a non-finite coordinate. */
static long long host_positions(const wc_model* m, const wc_source_mesh* src, const double* x, double* out) {
    long long nonfinite = 0;
    for (int v = 0; v < src->n_verts; ++v) {
        const int p = m->host_to_particle[v];
        const double* from = p >= 0 ? x + 3 * (size_t)p : src->pos + 3 * (size_t)v;
        double* to = out + 3 * (size_t)v;
        to[0] = from[0];
        to[1] = from[1];
        to[2] = from[2];
        nonfinite += !(isfinite(to[0]) && isfinite(to[1]) && isfinite(to[2]));
    }
    return nonfinite;
}

static void record_frame(run_record* r, int f, double ms, const wc_step_stats* s) {
    r->frame_ms[f] = ms;
    double* st = r->stage_ms + (size_t)f * RUN_STAGES;
    st[0] = s->ms.forces;
    st[1] = s->ms.assemble;
    st[2] = s->ms.solve;
    st[3] = s->ms.collide;
    st[4] = s->ms.integrate;
    st[5] = s->ms.total;
    r->iterations += s->iterations;
    r->substeps += s->substeps;
    if (s->max_iterations > r->max_iterations) r->max_iterations = s->max_iterations;
    if (s->residual > r->residual_max) r->residual_max = s->residual;
    r->not_converged += s->not_converged;
    r->rollbacks += s->rollbacks;
    r->halvings += s->halvings;
    r->direct_fallbacks += s->direct_fallbacks;
    r->failures += s->failures;
    if (s->max_strain > r->max_strain) r->max_strain = s->max_strain;
    r->frames = f + 1;
}

/* Build the model, the pins and the state of a loaded scene. */
static int prepare(run_ctx* c, const char* name) {
    wc_diag d = {0};
    weft_status st = wc_model_build(&c->model, &c->sc.src, &c->sc.model_def, NULL, &d);
    if (st != WEFT_OK) return fail("%s: mesh: %s", name, diag_text(&d, st));
    st = scene_pins_resolve(&c->pins, &c->sc, &c->model, name, &d);
    if (st != WEFT_OK) return fail("%s", diag_text(&d, st));
    st = wc_state_create(&c->state, &c->model, &c->sc.sim, NULL, &d);
    if (st != WEFT_OK) return fail("%s: %s", name, diag_text(&d, st));
    if (c->pins.n > 0) {
        scene_pins_at(&c->pins, 0.0);
        st = wc_state_set_pins(c->state, c->pins.pins, c->pins.n, &d);
        if (st != WEFT_OK) return fail("%s: pins: %s", name, diag_text(&d, st));
    }
    if (c->sc.n_colliders > 0) {
        st = wc_state_set_colliders(c->state, c->sc.colliders, c->sc.n_colliders, &d);
        if (st != WEFT_OK) return fail("%s: colliders: %s", name, diag_text(&d, st));
    }
    const size_t frames = (size_t)(c->sc.frames > 0 ? c->sc.frames : 1);
    c->host_pos = malloc(sizeof(double) * 3 * (size_t)(c->sc.src.n_verts > 0 ? c->sc.src.n_verts : 1));
    c->rec.frame_ms = calloc(frames, sizeof(double));
    c->rec.stage_ms = calloc(frames * RUN_STAGES, sizeof(double));
    if (!c->host_pos || !c->rec.frame_ms || !c->rec.stage_ms) return fail("%s: out of memory", name);
    return CLI_EXIT_OK;
}

static int simulate(run_ctx* c, const run_args* a) {
    const double dt = 1.0 / c->sc.fps;
    size_t path_cap = 0;
    if (a->out) {
        if (run_make_dirs(a->out) != 0) return fail("cannot create the folder '%s': %s", a->out, strerror(errno));
        path_cap = strlen(a->out) + 32;
        c->path = malloc(path_cap);
        if (!c->path) return fail("out of memory");
    }
    for (int f = 0; f < c->sc.frames; ++f) {
        wc_diag d = {0};
        weft_status st;
        if (c->pins.moving) {
            scene_pins_at(&c->pins, (f + 1) * dt);
            st = wc_state_set_pins(c->state, c->pins.pins, c->pins.n, &d);
            if (st != WEFT_OK) return fail("%s: frame %d: pins: %s", a->scene, f + 1, diag_text(&d, st));
        }
        wc_step_stats stats;
        memset(&stats, 0, sizeof stats);
        const double t0 = wc_now_ms();
        st = wc_step_frame(c->state, dt, &stats, &d);
        const double ms = wc_now_ms() - t0;
        if (st == WEFT_ERROR_STEP_FAILED)
            ++c->rec.failed_frames;
        else if (st != WEFT_OK)
            return fail("%s: frame %d: %s", a->scene, f + 1, diag_text(&d, st));
        record_frame(&c->rec, f, ms, &stats);
        c->rec.nonfinite_outputs += host_positions(&c->model, &c->sc.src, c->state->x, c->host_pos);
        if (a->out) {
            snprintf(c->path, path_cap, "%s/frame_%04d.obj", a->out, f + 1);
            if (run_write_obj(c->path, c->host_pos, &c->sc.src, f + 1, (f + 1) * dt) != 0)
                return fail("cannot write '%s': %s", c->path, strerror(errno));
        }
    }
    return CLI_EXIT_OK;
}

/* Final kinetic energy and bounding box of the particles. */
static void finish_record(run_ctx* c) {
    run_record* r = &c->rec;
    r->final_kinetic_energy = wc_state_kinetic_energy(c->state);
    for (int k = 0; k < 3; ++k) {
        r->bbox_min[k] = INFINITY;
        r->bbox_max[k] = -INFINITY;
    }
    for (int p = 0; p < c->model.n_particles; ++p)
        for (int k = 0; k < 3; ++k) {
            double x = c->state->x[3 * (size_t)p + k];
            r->bbox_min[k] = fmin(r->bbox_min[k], x);
            r->bbox_max[k] = fmax(r->bbox_max[k], x);
        }
}

int cli_run_run(int argc, char** argv) {
    run_args a = {NULL, -1, -1, NULL, NULL, -1, 0};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0) return rc;

    run_ctx c;
    memset(&c, 0, sizeof c);
    wc_diag d = {0};
    weft_status st = scene_load(&c.sc, a.scene, &d);
    if (st != WEFT_OK) return fail("%s", diag_text(&d, st));
    if (a.frames >= 0) c.sc.frames = a.frames;
    if (a.solver >= 0) c.sc.sim.solver.type = (wc_solver_type)a.solver;
    if (a.threads >= 0) c.sc.sim.threads = a.threads;

    rc = prepare(&c, a.scene);
    if (rc == CLI_EXIT_OK) rc = simulate(&c, &a);
    if (rc == CLI_EXIT_OK) {
        finish_record(&c);
        const run_info info = {a.scene, c.model.n_particles, c.model.n_tris, c.model.n_springs,
                               wc_solver_name(c.sc.sim.solver.type), c.sc.sim.substeps, c.state->par.threads,
                               c.sc.fps, a.out};
        errno = 0;
        if (a.stats && run_write_stats(a.stats, &info, &c.rec) != 0)
            rc = fail("cannot write '%s': %s", a.stats, errno ? strerror(errno) : "out of memory");
        else if (!a.quiet)
            run_print_summary(stdout, &info, &c.rec);
    }
    run_release(&c);
    return rc;
}
