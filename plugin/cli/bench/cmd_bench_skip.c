/* `weft bench skip`: what a step costs for features a scene does not use. One cloth (default
 * sheet64: a 1 m sheet hanging from two corners) under configurations that each add one feature
 * to a baseline that uses none (no air, no collider, still pins), plus the solver forced to its
 * iteration cap instead of stopping at its tolerance, and the cloth asleep. Per configuration:
 * the median per-stage wall time of a frame, the ratio to the baseline and what the baseline (or
 * the skip) saves. Every configuration is a cloth of the public API (weft_cloth_step on the
 * backend's context: the CPU's and/or, with --backend, a GPU's). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_body.h"
#include "bench_commands.h"
#include "bench_run.h"
#include "bench_table.h"
#include "cli.h"
#include "scene_host.h"

#define FPS 60.0
#define SLEEP_CAP_S 60.0    /* simulated seconds the asleep row waits for the cloth to come to rest */

typedef struct skip_args {
    const char* scene;
    int frames;
    int backends[BENCH_MAX_BACKENDS];
    int n_backends;
    bench_common com;
} skip_args;

void bench_skip_usage(FILE* out) {
    fputs("usage: weft bench skip [--quick] [--scene NAME] [--frames N] [--threads N] [--csv FILE]\n"
          "                       [--md FILE] [--backend LIST] [--quiet]\n"
          "\n"
          "What a step costs for features a scene does not use, on the CPU and/or the GPU (--backend).\n"
          "One cloth, simulated for --frames frames at 60 frames/s from rest, per configuration:\n"
          "  baseline        no wind, no air drag, no collider, still pins, PCG at tolerance 1e-4\n"
          "  + air drag      the default drags (normal 0.5, tangent 0.02 kg/(m^2 s)), no wind\n"
          "  + wind          the drags and a 3 m/s wind\n"
          "  + far collider  a sphere 10 m below: the contact pass runs, finds nothing\n"
          "  + contact       a sphere (radius 0.25 m) 0.3 m under the middle: the cloth drapes on it\n"
          "  + far mesh      a triangle-mesh sphere (UV sphere, 960 triangles, radius 0.25 m) 10 m\n"
          "                  below: its BVH is refitted and queried, finds nothing (CPU only: on\n"
          "                  the GPU, which has no mesh colliders, the row is the baseline again)\n"
          "  + mesh contact  the same mesh sphere where `+ contact` has its sphere: the cloth drapes\n"
          "                  on it (CPU only, as above)\n"
          "  + moving pins   the pinned corners turn about the vertical axis at 1 rad/s\n"
          "  + self-collision  the cloth against itself (thickness 3 mm; on the GPU core's stage\n"
          "                  runs on the host); the hanging sheet never touches itself\n"
          "  full cap        the baseline with tolerance 0: every solve runs all 300 iterations\n"
          "  asleep          the default cloth (+ air drag) with sleeping on (1e-3 m/s for 0.5 s), run\n"
          "                  until it falls asleep (at most 60 s), then timed\n"
          "The configurations (of every backend) are stepped in turn, one frame each, so that a\n"
          "changing machine load weighs on all of them alike.\n"
          "Columns: median ms per frame of each stage (forces, assemble, solve, collide, integrate)\n"
          "and in all, the ratio to the baseline, and what skipping the feature saves per frame (the\n"
          "row's total minus the baseline's; for `full cap`, what stopping at the tolerance saves; for\n"
          "`asleep`, what sleeping saves against the same cloth awake, `+ air drag`).\n"
          "\n"
          "options:\n"
          "  --quick              seconds-long preset: sheet16, 20 frames, 1 thread\n"
          "  --scene NAME         sheetN, hangN, drape, drapeN or garment as in `weft bench accuracy`\n"
          "                       (default sheet64); its own pins and colliders are replaced\n"
          "  --frames N           frames timed per configuration (default 120)\n"
          "  --threads N          OpenMP threads (default 0: OpenMP's default)\n"
          "  --csv FILE           write every configuration as CSV\n"
          "  --md FILE            write the Markdown table to FILE instead of stdout\n"
          BENCH_BACKEND_HELP
          "                       Here positions are read back only before and after the timed\n"
          "                       frames; each backend's rows are compared with its own baseline.\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static void defaults(void* args, int quick) {
    skip_args* a = args;
    memset(a, 0, sizeof *a);
    a->scene = quick ? "sheet16" : "sheet64";
    a->frames = quick ? 20 : 120;
    a->backends[0] = BENCH_CPU;
    a->n_backends = 1;
}

static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    skip_args* a = args;
    int m = 0;
    if ((m = cli_option_value(argc, argv, i, "--scene", v)) != 0) {
        if (m > 0) a->scene = *v;
        return m;
    }
    if ((m = cli_option_value(argc, argv, i, "--frames", v)) != 0)
        return m < 0 ? m : cli_parse_int(*v, 1, 100000, &a->frames) != 0 ? -2 : 1;
    if ((m = cli_option_value(argc, argv, i, "--backend", v)) != 0)
        return m < 0 ? m : (a->n_backends = bench_parse_backends(*v, a->backends)) < 0 ? -2 : 1;
    return 0;
}

enum { K_BASE, K_DRAG, K_WIND, K_FAR, K_CONTACT, K_MESH_FAR, K_MESH_CONTACT, K_PINS, K_SELF, K_CAP, K_ASLEEP, N_CONFIGS };
static const char* const config_name[N_CONFIGS] = {"baseline", "+ air drag", "+ wind", "+ far collider",
                                                   "+ contact", "+ far mesh", "+ mesh contact", "+ moving pins",
                                                   "+ self-collision", "full cap", "asleep"};
#define MESH_RINGS 16       /* the mesh sphere's latitude bands: 4 x 16 x 15 = 960 triangles */

/* One timed run. */
typedef struct skip_run {
    double stage[6];        /* medians (ms): forces, assemble, solve, collide, integrate, total */
    double iterations;      /* per substep, mean */
    int not_converged;      /* solves stopped at the cap */
    int contacts;           /* particles in contact at the end */
    int frames;             /* frames timed */
    int asleep_frames;      /* timed frames the cloth slept through */
    int warmup;             /* frames before the timed ones (asleep: until it fell asleep; -1: never) */
    int unchanged;          /* 1: positions bit-identical across the timed frames */
    int particles, threads; /* the cloth's (weft_cloth_info) */
} skip_run;

/* One configuration's cloth and its per-frame timings. */
typedef struct skip_cfg {
    scene sc;               /* the scene with this configuration's def and colliders (arrays shared) */
    scene_collider sphere;  /* its sphere collider, when it has one */
    bench_body body;        /* the mesh rows' sphere (a mesh collider of host arrays) */
    scene_host h;
    int live;               /* 1: h holds a cloth */
    double* ms;             /* (6 x frames) */
    float* x0;              /* positions before the timed frames */
    long long iterations, substeps;
} skip_cfg;

static void cfg_free(skip_cfg* c) {
    if (c->live) scene_host_destroy(&c->h);
    bench_body_free(&c->body);
    free(c->ms);
    free(c->x0);
    memset(c, 0, sizeof *c);
}

/* One frame (f: 0-based) with the configuration's pins (turning about the vertical axis at 1 rad/s
 * for `+ moving pins`); -1 with msg when the step is refused (a failed step is not). */
static int cfg_frame(skip_cfg* c, int config, int f, weft_frame_stats* st, char* msg, size_t size) {
    weft_frame fr = scene_host_frame(&c->h, &c->sc, f + 1, 1.0 / FPS);
    if (config == K_PINS) {
        const double angle = (f + 1) / FPS, co = cos(angle), si = sin(angle);
        for (int i = 0; i < c->h.n_attachments; ++i) {
            float* m = c->h.attachment_xf + 16 * (size_t)i;
            memset(m, 0, 16 * sizeof(float));
            m[0] = (float)co, m[2] = (float)-si, m[5] = 1.0f, m[8] = (float)si, m[10] = (float)co, m[15] = 1.0f;
        }
    }
    memset(st, 0, sizeof *st);
    const weft_status s = weft_cloth_step(c->h.ctx, c->h.cloth, &fr, st);
    if (s == WEFT_OK || s == WEFT_ERROR_STEP_FAILED) return 0;
    snprintf(msg, size, "frame %d: %s", f + 1, scene_host_error(&c->h));
    return -1;
}

/* The configuration's def and colliders on the scene: the baseline (no air, no collider, still
 * pins, the core of one Baraff-Witkin step: block Jacobi PCG, backward Euler, one Newton
 * iteration, no line search, no self-collision) plus its one feature. */
static int cfg_scene(skip_cfg* c, const bench_scene* bs, int backend, int config, char* msg, size_t size) {
    c->sc = bs->sc;
    weft_cloth_def* d = &c->sc.def;
    *d = bench_run_def(bs);
    const weft_cloth_def dflt = weft_default_cloth_def();
    d->preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    d->integrator = WEFT_INTEGRATOR_BACKWARD_EULER;
    d->newton_iterations = 1;
    d->line_search = 0;
    d->self_collision = config == K_SELF;
    d->air_drag_normal = d->air_drag_tangent = 0.0;
    if (config == K_DRAG || config == K_WIND || config == K_ASLEEP) {
        d->air_drag_normal = dflt.air_drag_normal;
        d->air_drag_tangent = dflt.air_drag_tangent;
    }
    if (config == K_WIND) d->wind[0] = 3.0;
    if (config == K_CAP) d->tolerance = 0.0;
    if (config == K_ASLEEP) d->sleep_speed = dflt.sleep_speed;
    c->sc.fps = FPS;
    c->sc.n_colliders = 0;
    c->sc.n_mesh_colliders = 0;
    /* below the middle of the cloth's rest bounding box (the scene's mesh) */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < bs->sc.mesh.n_vertices; ++v)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], bs->sc.mesh.positions[3 * v + k]);
            hi[k] = fmax(hi[k], bs->sc.mesh.positions[3 * v + k]);
        }
    memset(&c->sphere, 0, sizeof c->sphere);
    c->sphere.type = WEFT_COLLIDER_SPHERE;
    c->sphere.radius = 0.25;
    c->sphere.thickness = 0.005;
    c->sphere.friction = 0.3;
    c->sphere.motion = scene_motion_still();
    c->sphere.center[0] = 0.5 * (lo[0] + hi[0]);
    c->sphere.center[1] = lo[1] - (config == K_FAR || config == K_MESH_FAR ? 10.0 : 0.3);
    c->sphere.center[2] = 0.5 * (lo[2] + hi[2]);
    if (config == K_FAR || config == K_CONTACT) {
        c->sc.colliders = &c->sphere;
        c->sc.n_colliders = 1;
    }
    if ((config == K_MESH_FAR || config == K_MESH_CONTACT) && backend != BENCH_GPU) {
        /* the GPU has no mesh colliders: its rows are the baseline again */
        const double r[3] = {c->sphere.radius, c->sphere.radius, c->sphere.radius};
        if (bench_body_create(&c->body, MESH_RINGS, c->sphere.center, r, msg, size) != 0) return -1;
    }
    return 0;
}

/* The configuration's cloth; the asleep one is stepped until it falls asleep (out->warmup). */
static int cfg_create(skip_cfg* c, const bench_scene* bs, int backend, int config, int frames, skip_run* out,
                      char* msg, size_t size) {
    memset(c, 0, sizeof *c);
    memset(out, 0, sizeof *out);
    if (cfg_scene(c, bs, backend, config, msg, size) != 0) return -1;
    scene_host_opts ho;
    memset(&ho, 0, sizeof ho);
    ho.ctx = bench_backend_context(backend);
    weft_mesh_collider_def mesh = bench_body_collider(&c->body, c->sphere.thickness, c->sphere.friction);
    if (c->body.n_verts > 0) {
        ho.mesh_colliders = &mesh;
        ho.n_mesh_colliders = 1;
    }
    if (scene_host_create(&c->h, &c->sc, &ho, bs->name, msg, size) != WEFT_OK) {
        cfg_free(c);
        return -1;
    }
    c->live = 1;
    const size_t n3 = 3 * (size_t)c->h.info.n_vertices;
    c->ms = malloc(sizeof(double) * 6 * (size_t)frames);
    c->x0 = malloc(sizeof(float) * (n3 > 0 ? n3 : 1));
    if (!c->ms || !c->x0) {
        snprintf(msg, size, "bench skip: out of memory");
        cfg_free(c);
        return -1;
    }
    if (config == K_ASLEEP) {
        out->warmup = -1;
        weft_frame_stats ws;
        for (int f = 0; f < (int)(SLEEP_CAP_S * FPS) && out->warmup < 0; ++f) {
            if (cfg_frame(c, config, f, &ws, msg, size) != 0) {
                cfg_free(c);
                return -1;
            }
            if (ws.fell_asleep) out->warmup = f + 1;
        }
    }
    if (scene_host_read_positions(&c->h) != WEFT_OK) {
        snprintf(msg, size, "%s", scene_host_error(&c->h));
        cfg_free(c);
        return -1;
    }
    memcpy(c->x0, c->h.positions, sizeof(float) * n3);
    return 0;
}

/* Timed frame f of a configuration; -1 with msg on a refused step. */
static int cfg_step(skip_cfg* c, int config, int f, int frames, skip_run* out, char* msg, size_t size) {
    weft_frame_stats ss;
    /* the asleep row continues from where its warm-up left it */
    if (cfg_frame(c, config, out->warmup > 0 ? out->warmup + f : f, &ss, msg, size) != 0) return -1;
    /* collide: the colliders' passes and self-collision */
    const double stage[6] = {ss.ms_forces, ss.ms_assemble, ss.ms_solve, ss.ms_collide + ss.ms_self_collide,
                             ss.ms_integrate, ss.ms_total};
    for (int k = 0; k < 6; ++k) c->ms[(size_t)k * frames + f] = stage[k];
    c->iterations += ss.iterations;
    c->substeps += ss.substeps;
    out->not_converged += ss.not_converged;
    out->asleep_frames += ss.asleep;
    out->contacts = ss.contacts;
    return 0;
}

static int cfg_finish(skip_cfg* c, int frames, skip_run* out, char* msg, size_t size) {
    if (scene_host_read_positions(&c->h) != WEFT_OK) {
        snprintf(msg, size, "%s", scene_host_error(&c->h));
        return -1;
    }
    out->frames = frames;
    for (int k = 0; k < 6; ++k) out->stage[k] = cli_sort_median(c->ms + (size_t)k * frames, frames);
    out->iterations = c->substeps > 0 ? (double)c->iterations / (double)c->substeps : 0.0;
    out->unchanged = memcmp(c->x0, c->h.positions, sizeof(float) * 3 * (size_t)c->h.info.n_vertices) == 0;
    out->particles = c->h.info.n_particles;
    out->threads = c->h.info.threads;
    return 0;
}

/* What is skipped when the feature is off, in words. */
static const char* const skipped_text[N_CONFIGS] = {   /* no commas: CSV cells are not quoted */
    "air pass (drags 0); contact passes (no collider); pin motion (still)",
    "baseline skips the per-triangle air pass",
    "nothing beyond the air pass: wind is one more term in it",
    "baseline skips the contact passes (here they run and find nothing)",
    "baseline skips contacts and friction re-solves",
    "baseline skips the mesh's BVH refit and its queries (here they find nothing)",
    "baseline skips the mesh contacts (BVH queries) and friction re-solves",
    "nothing: pins cost O(pins) moving or still",
    "baseline skips self-collision (the in-solve pairs' detection; the stage's BVH refits and proximity / CCD queries)",
    "stopping at the tolerance skips the iterations past it",
    "sleeping skips the whole step (forces; assembly; solve; contacts)"};

enum {
    C_BACKEND, C_SCENE, C_PARTICLES, C_CONFIG, C_FRAMES, C_WARMUP, C_ITER, C_NOT_CONV, C_CONTACTS, C_ASLEEP,
    C_UNCHANGED, C_FORCES, C_ASSEMBLE, C_SOLVE, C_COLLIDE, C_INTEGRATE, C_TOTAL, C_RATIO, C_SAVED, C_SKIPPED, N_COLS
};
static const char* const csv_cols[N_COLS] = {
    "backend", "scene", "particles", "config", "frames", "warmup_frames", "iterations_per_substep",
    "not_converged", "contacts", "asleep_frames", "positions_unchanged", "ms_forces", "ms_assemble", "ms_solve",
    "ms_collide", "ms_integrate", "ms_total", "ratio_to_baseline", "ms_saved", "skipped"};
static const char* const md_cols[N_COLS] = {
    NULL /* "backend" with two backends */, NULL, NULL, "configuration", NULL, NULL, "it./substep", NULL,
    "contacts", NULL, NULL, "forces", "assemble", "solve", "collide", "integrate", "total ms", "x baseline", "saved ms/frame", "what is skipped"};

typedef struct header_info {
    const skip_args* a;
    int particles, threads;
    const skip_run (*runs)[N_CONFIGS];   /* [backend index][config] */
} header_info;

static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    char note[1024], blas[64];
    fprintf(out, "## weft bench skip\n\n%s. %d OpenMP thread(s), %s. Scene %s (%d particles), %d frames timed "
                 "per configuration at 60 frames/s, one substep per frame; medians of the per-stage wall time "
                 "weft_cloth_step reports (weft_frame_stats, ms per frame; total: the whole call).\n\n",
            bench_backend_note(h->a->backends, h->a->n_backends, note, sizeof note), h->threads,
            bench_blas_note(&h->a->com, blas, sizeof blas), h->a->scene,
            h->particles, h->a->frames);
    for (int b = 0; b < h->a->n_backends; ++b) {
        const skip_run* r = h->runs[b];
        if (h->a->n_backends > 1) fprintf(out, "%s: ", h->a->backends[b] == BENCH_GPU ? "GPU" : "CPU");
        if (r[K_ASLEEP].warmup > 0)
            fprintf(out, "Asleep: the cloth fell asleep after %d frames (%.2f s); a sleeping frame costs %.3g us, "
                         "%.3g%% of the same cloth's active frame (+ air drag: %.3f ms; target < 2%%); positions %s over the %d timed "
                         "frames. Stopping at the tolerance: %.1f iterations per solve instead of %.0f.\n\n",
                    r[K_ASLEEP].warmup, r[K_ASLEEP].warmup / FPS, 1e3 * r[K_ASLEEP].stage[5],
                    100.0 * r[K_ASLEEP].stage[5] / r[K_DRAG].stage[5], r[K_DRAG].stage[5],
                    r[K_ASLEEP].unchanged ? "bit-identical" : "CHANGED", r[K_ASLEEP].frames, r[K_BASE].iterations,
                    r[K_CAP].iterations);
        else
            fprintf(out, "Asleep: the cloth did not come to rest within %g s.\n\n", SLEEP_CAP_S);
    }
    fputs("A feature also changes the motion (wind blows the sheet, moving pins swing it, contacts add "
          "constraints) and with it the solver's iterations: the pass a feature adds shows in its own "
          "stage (air: forces; colliders: collide), the rest of the difference is the solve of a "
          "different motion. Stages do not add up to the total: the rest is bookkeeping (failure "
          "checks, energy, strain, and the library's backup of the state for a failed call).\n\n",
          out);
}

int bench_skip_run(int argc, char** argv) {
    skip_args a;
    int rc = bench_parse_args(argc, argv, "weft bench skip", bench_skip_usage, defaults, own_option, &a, &a.com);
    if (rc >= 0) return rc;
    if (a.com.plot) return cli_usage_error("weft bench skip", bench_skip_usage, "--plot: this command has no plot");
    if (bench_open_backends(a.backends, a.n_backends, a.com.threads) != CLI_EXIT_OK) return CLI_EXIT_FAILURE;
    bench_scene bs;
    char msg[1024];
    if (bench_scene_build(&bs, a.scene, a.com.garment, 1.0, 1.0, msg, sizeof msg) != 0) {
        cli_error(msg);
        return CLI_EXIT_FAILURE;
    }
    /* every configuration of every backend is stepped in turn, one frame each, so that the
       machine's load, which changes over seconds, weighs on all of them alike */
    const int nb = a.n_backends;
    static skip_run runs[BENCH_MAX_BACKENDS][N_CONFIGS];
    static skip_cfg cfg[BENCH_MAX_BACKENDS][N_CONFIGS];
    memset(cfg, 0, sizeof cfg);
    memset(runs, 0, sizeof runs);
    for (int q = 0; q < nb * N_CONFIGS && rc < 0; ++q) {
        const int b = q / N_CONFIGS, k = q % N_CONFIGS;
        if (!a.com.quiet)
            fprintf(stderr, "[%d/%d] %s%s%s%s\n", q + 1, nb * N_CONFIGS, nb > 1 ? bench_backend_name(a.backends[b]) : "",
                    nb > 1 ? " " : "", config_name[k], k == K_ASLEEP ? ": stepping until it falls asleep" : "");
        if (cfg_create(&cfg[b][k], &bs, a.backends[b], k, a.frames, &runs[b][k], msg, sizeof msg) != 0) {
            cli_error(msg);
            rc = CLI_EXIT_FAILURE;
        }
    }
    if (rc < 0 && !a.com.quiet) fprintf(stderr, "timing %d frames of each, in turn\n", a.frames);
    for (int f = 0; f < a.frames && rc < 0; ++f)
        for (int q = 0; q < nb * N_CONFIGS && rc < 0; ++q) {
            const int b = q / N_CONFIGS, k = q % N_CONFIGS;
            if (cfg_step(&cfg[b][k], k, f, a.frames, &runs[b][k], msg, sizeof msg) != 0) {
                cli_error(msg);
                rc = CLI_EXIT_FAILURE;
            }
        }
    for (int q = 0; q < nb * N_CONFIGS; ++q) {
        const int b = q / N_CONFIGS, k = q % N_CONFIGS;
        if (rc < 0 && cfg_finish(&cfg[b][k], a.frames, &runs[b][k], msg, sizeof msg) != 0) {
            cli_error(msg);
            rc = CLI_EXIT_FAILURE;
        }
        cfg_free(&cfg[b][k]);
    }
    bench_table t;
    const char* md[N_COLS];
    memcpy(md, md_cols, sizeof md);
    if (nb > 1) md[C_BACKEND] = "backend";
    bench_table_init(&t, N_COLS, csv_cols, md);
    for (int q = 0; q < nb * N_CONFIGS && rc < 0; ++q) {
        const int b = q / N_CONFIGS, k = q % N_CONFIGS;
        const skip_run* r = &runs[b][k];
        const double base = runs[b][K_BASE].stage[5];
        /* what the baseline saves by skipping the feature (full cap: what stopping at the tolerance
           saves); asleep: what sleeping saves; each against its own backend's rows */
        const double saved = k == K_ASLEEP ? runs[b][K_DRAG].stage[5] - r->stage[5] : r->stage[5] - base;
        char c[N_COLS][96];
        snprintf(c[C_BACKEND], 96, "%s", bench_backend_name(a.backends[b]));
        snprintf(c[C_SCENE], 96, "%s", bs.name);
        snprintf(c[C_PARTICLES], 96, "%d", r->particles);
        snprintf(c[C_CONFIG], 96, "%s", config_name[k]);
        snprintf(c[C_FRAMES], 96, "%d", r->frames);
        snprintf(c[C_WARMUP], 96, "%d", r->warmup);
        bench_fmt(c[C_ITER], 96, "%.1f", r->iterations);
        snprintf(c[C_NOT_CONV], 96, "%d", r->not_converged);
        snprintf(c[C_CONTACTS], 96, "%d", r->contacts);
        snprintf(c[C_ASLEEP], 96, "%d", r->asleep_frames);
        snprintf(c[C_UNCHANGED], 96, "%d", r->unchanged);
        for (int j = 0; j < 6; ++j) bench_fmt(c[C_FORCES + j], 96, r->stage[j] < 1e-2 ? "%.2g" : "%.3f", r->stage[j]);
        bench_fmt(c[C_RATIO], 96, "%.3g", base > 0 ? r->stage[5] / base : NAN);
        if (k == K_BASE) snprintf(c[C_SAVED], 96, "-");
        else bench_fmt(c[C_SAVED], 96, "%.3f", saved);
        snprintf(c[C_SKIPPED], 96, "%s",
                 (k == K_MESH_FAR || k == K_MESH_CONTACT) && a.backends[b] == BENCH_GPU
                     ? "GPU: no mesh colliders (the baseline again)"
                     : skipped_text[k]);
        const char* cell[N_COLS];
        for (int j = 0; j < N_COLS; ++j) cell[j] = c[j];
        if (bench_table_add(&t, cell) != 0) rc = CLI_EXIT_FAILURE;
    }
    if (rc < 0) {
        const header_info h = {&a, runs[0][K_BASE].particles, runs[0][K_BASE].threads,
                               (const skip_run(*)[N_CONFIGS])runs};
        rc = bench_write_tables(&a.com, &t, print_header, &h);
    }
    bench_table_free(&t);
    bench_scene_free(&bs);
    return rc;
}
