/* `weft run SCENE.json`: load a scene, hand it to the public API (libweft.so, as any host does:
 * host/scene_host.c), step every frame with the transforms of the scene's motions, and write OBJ
 * frames, a stats JSON, a progress line and a summary table. Exit codes: 0 ok (frames whose step
 * failed after every recovery are counted, not fatal), 1 the scene is invalid or something else
 * failed (one line on stderr), 2 bad command line. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "names.h"
#include "run.h"
#include "run_progress.h"
#include "scene.h"
#include "scene_host.h"
#include "weft/weft.h"


typedef struct run_args {
    const char* scene;
    int frames;            /* -1: the scene's */
    int solver;            /* -1: the scene's, else a weft_solver */
    int integrator;        /* -1: the scene's, else a weft_integrator (DEFAULT for "default") */
    int precond;           /* -1: the scene's, else a weft_preconditioner (DEFAULT for "default") */
    int newton;            /* -1: the scene's, else 1..100 */
    int line_search;       /* -2: the scene's, else 0 or 1 */
    const char* out;       /* folder for OBJ frames, NULL: none */
    const char* stats;     /* stats JSON path, NULL: none */
    const char* render;    /* folder for PNG frames, NULL: none */
    int threads;           /* -1: the scene's */
    weft_backend backend;
    int quiet;
    int self_collision;    /* -2: the scene's, else 0 or 1 */
    const char* cache;     /* point cache path (.pc2 or .mdd), NULL: none */
    double forcing;        /* -2: the scene's, -1: the library's, else in [0, 1) */
} run_args;

void cli_run_usage(FILE* out) {
    fputs("usage: weft run SCENE.json [--frames N] [--solver pcg|jacobi|chebyshev|direct]\n"
          "                [--out DIR] [--cache FILE.pc2|FILE.mdd] [--stats FILE.json] [--render DIR]\n"
          "                [--threads N]\n"
          "                [--backend cpu|gpu|auto] [--integrator be|bdf2|trbdf2] [--precond block_jacobi|amg|ic0]\n"
          "                [--newton N] [--newton-forcing X|default] [--line-search on|off]\n"
          "                [--self-collision on|off] [--quiet]\n"
          "\n"
          "Simulate the scene (schema: sample_scenes/README.md) frame by frame at 1/fps seconds\n"
          "through the public API (libweft), showing a progress line on a terminal and printing\n"
          "a summary table at the end.\n"
          "\n"
          "options:\n"
          "  --frames N             frames to simulate (>= 0; default: the scene's time.frames)\n"
          "  --solver NAME          linear solver, overriding the scene's solver.type\n"
          "  --integrator NAME      be, bdf2 or trbdf2 (or default), overriding time.integrator\n"
          "  --precond NAME         block_jacobi, amg or ic0 (or default), overriding solver.preconditioner\n"
          "  --newton N             Newton iterations per substep (1..100), overriding\n"
          "                         solver.newton_iterations\n"
          "  --newton-forcing X     inexact Newton: the first solve of a substep to X in [0, 1) (0: every\n"
          "                         solve to the tolerance; default: the library's), overriding\n"
          "                         solver.newton_forcing\n"
          "  --line-search on|off   line search on the incremental potential, overriding\n"
          "                         solver.line_search\n"
          "  --self-collision on|off  the cloth against itself, overriding self_collision\n"
          "  --out DIR              write DIR/frame_0001.obj ... (created if missing): every host\n"
          "                         vertex in the mesh's own order, then its polygons\n"
          "  --stats FILE.json      write timings, solver and recovery counts as one JSON object\n"
          "                         (and check every frame for crossings and penetration)\n"
          "  --cache FILE           write a point cache of frame 0 (rest) and every frame: FILE.pc2\n"
          "                         (PC2) or FILE.mdd (MDD), host vertices in the mesh's own order\n"
          "                         (an OBJ's v lines), metres, as the OBJ frames; for Blender's\n"
          "                         Mesh Cache modifier, 3ds Max, Maya\n"
          "  --render DIR           write DIR/frame_0001.png ... through weft_render(), seen from\n"
          "                         the scene's camera\n"
          "  --threads N            OpenMP threads (>= 0; 0: OpenMP's default)\n"
          "  --backend NAME         cpu (default), gpu, or auto (the GPU where the cloth is large enough and the\n"
          "                         GPU runs all it uses; the summary says which and why)\n"
          "  --quiet                print nothing on success (no progress line, no summary)\n"
          "  -h, --help             show this help\n",
          out);
}

#define usage_error(...) cli_usage_error("weft run", cli_run_usage, __VA_ARGS__)

static int parse_backend(const char* name, weft_backend* out) {
    static const char* const names[] = {"auto", "cpu", "gpu"};
    static const weft_backend values[] = {WEFT_BACKEND_AUTO, WEFT_BACKEND_CPU, WEFT_BACKEND_GPU};
    for (int i = 0; i < 3; ++i)
        if (strcmp(name, names[i]) == 0) {
            *out = values[i];
            return 0;
        }
    return -1;
}

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
            a->solver = cli_solver_from_name(value);
            if (a->solver < 0)
                return usage_error("unknown solver '%s' (expected pcg, jacobi, chebyshev or direct)", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--integrator", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            a->integrator = strcmp(value, "default") == 0 ? WEFT_INTEGRATOR_DEFAULT : cli_integrator_from_name(value);
            if (a->integrator < 0)
                return usage_error("--integrator: unknown integrator '%s' (expected be, bdf2, trbdf2 or default)", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--precond", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            a->precond = strcmp(value, "default") == 0 ? WEFT_PRECOND_DEFAULT : cli_precond_from_name(value);
            if (a->precond < 0)
                return usage_error("--precond: unknown preconditioner '%s' (expected block_jacobi, amg, ic0 or default)",
                                   value);
        } else if ((m = cli_option_value(argc, argv, &i, "--newton", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_int(value, 1, 100, &a->newton) != 0)
                return usage_error("--newton must be an integer in [1, 100], not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--newton-forcing", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (strcmp(value, "default") == 0) a->forcing = -1.0;
            else if (cli_parse_double(value, &a->forcing) != 0 || !(a->forcing >= 0 && a->forcing < 1))
                return usage_error("--newton-forcing must be a number in [0, 1) or default, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--line-search", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (strcmp(value, "on") == 0) a->line_search = 1;
            else if (strcmp(value, "off") == 0) a->line_search = 0;
            else return usage_error("--line-search must be on or off, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--self-collision", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (strcmp(value, "on") == 0) a->self_collision = 1;
            else if (strcmp(value, "off") == 0) a->self_collision = 0;
            else return usage_error("--self-collision must be on or off, not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--threads", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (cli_parse_int(value, 0, 1024, &a->threads) != 0)
                return usage_error("--threads must be an integer in [0, 1024], not '%s'", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--backend", &value)) != 0) {
            if (m < 0) return usage_error("%s needs a value", arg);
            if (parse_backend(value, &a->backend) != 0)
                return usage_error("unknown backend '%s' (expected cpu, gpu or auto)", value);
        } else if ((m = cli_option_value(argc, argv, &i, "--out", &value)) != 0) {
            if (m < 0 || !value[0]) return usage_error("%s needs a folder", arg);
            a->out = value;
        } else if ((m = cli_option_value(argc, argv, &i, "--cache", &value)) != 0) {
            if (m < 0 || !value[0]) return usage_error("%s needs a file name", arg);
            if (run_cache_kind(value) < 0)
                return usage_error("--cache: '%s' must end in .pc2 or .mdd", value);
            a->cache = value;
        } else if ((m = cli_option_value(argc, argv, &i, "--stats", &value)) != 0) {
            if (m < 0 || !value[0]) return usage_error("%s needs a file name", arg);
            a->stats = value;
        } else if ((m = cli_option_value(argc, argv, &i, "--render", &value)) != 0) {
            if (m < 0 || !value[0]) return usage_error("%s needs a folder", arg);
            a->render = value;
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
    scene_host host;
    char* path;            /* output path buffer */
    size_t path_cap;
    run_record rec;
    run_progress progress;
    run_cache cache;       /* --cache, while open */
} run_ctx;

static void run_release(run_ctx* c) {
    scene_host_destroy(&c->host);
    scene_free(&c->sc);
    free(c->path);
    run_record_free(&c->rec);
    run_cache_close(&c->cache, 0);   /* a run that did not finish leaves no cache */
}

static int fail(run_ctx* c, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(run_ctx* c, const char* fmt, ...) {
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (c) run_progress_end(&c->progress);
    cli_error(line);
    return CLI_EXIT_FAILURE;
}

static weft_render_def render_def(const scene_camera* cam, const char* png_path) {
    weft_render_def rd = weft_default_render_def();
    rd.width = cam->width;
    rd.height = cam->height;
    for (int k = 0; k < 3; ++k) {   /* eye == target (zeros): framed automatically */
        rd.eye[k] = cam->framed ? (float)cam->eye[k] : 0.0f;
        rd.target[k] = cam->framed ? (float)cam->target[k] : 0.0f;
        rd.up[k] = (float)cam->up[k];
    }
    rd.fov_y_deg = (float)cam->fov_deg;
    rd.png_path = png_path;
    return rd;
}

/* Make the output folders and the path buffer. */
static int prepare_outputs(run_ctx* c, const run_args* a) {
    const char* dirs[2] = {a->out, a->render};
    for (int i = 0; i < 2; ++i) {
        if (!dirs[i]) continue;
        if (run_make_dirs(dirs[i]) != 0) return fail(c, "cannot create the folder '%s': %s", dirs[i], strerror(errno));
        const size_t need = strlen(dirs[i]) + 32;
        if (need > c->path_cap) c->path_cap = need;
    }
    if (c->path_cap) {
        c->path = malloc(c->path_cap);
        if (!c->path) return fail(c, "out of memory");
    }
    if (a->cache) {   /* frame 0 (the rest shape) and every frame */
        const int n = c->host.info.n_vertices;
        if (run_cache_open(&c->cache, a->cache, n, c->sc.frames + 1, c->sc.fps) != 0 ||
            run_cache_sample(&c->cache, c->host.positions, n) != 0)
            return fail(c, "cannot write '%s': %s", a->cache, strerror(errno));
    }
    return CLI_EXIT_OK;
}

/* Frame f's outputs (1-based): OBJ and PNG. */
static int write_frame(run_ctx* c, const run_args* a, int f, double t) {
    if (a->out) {
        snprintf(c->path, c->path_cap, "%s/frame_%04d.obj", a->out, f);
        if (run_write_obj(c->path, c->host.positions, &c->sc.mesh, f, t) != 0)
            return fail(c, "cannot write '%s': %s", c->path, strerror(errno));
    }
    if (a->cache && run_cache_sample(&c->cache, c->host.positions, c->host.info.n_vertices) != 0)
        return fail(c, "cannot write '%s': %s", a->cache, strerror(errno));
    if (a->render) {
        snprintf(c->path, c->path_cap, "%s/frame_%04d.png", a->render, f);
        const weft_render_def rd = render_def(&c->sc.camera, c->path);
        if (weft_render(c->host.ctx, c->host.cloth, &rd) != WEFT_OK)
            return fail(c, "%s: frame %d: render: %s", a->scene, f, scene_host_error(&c->host));
    }
    return CLI_EXIT_OK;
}

static int simulate(run_ctx* c, const run_args* a) {
    const double dt = 1.0 / c->sc.fps;
    int rc = prepare_outputs(c, a);
    run_progress_begin(&c->progress, stderr, !a->quiet, c->sc.frames);
    weft_collision_check chk;  /* the latest check; valid while `checked` (nothing stepped since) */
    int checked = 0;
    for (int f = 1; f <= c->sc.frames && rc == CLI_EXIT_OK; ++f) {
        checked = 0;
        const weft_frame fr = scene_host_frame(&c->host, &c->sc, f, dt);
        weft_frame_stats stats;
        memset(&stats, 0, sizeof stats);
        const double t0 = run_now_ms();
        weft_status st = weft_cloth_step(c->host.ctx, c->host.cloth, &fr, &stats);
        const double ms = run_now_ms() - t0;
        if (st == WEFT_ERROR_STEP_FAILED)   /* the cloth is as before the call; the run goes on */
            run_record_failed_frame(&c->rec, f - 1, ms);
        else if (st != WEFT_OK)
            return fail(c, "%s: frame %d: %s", a->scene, f, scene_host_error(&c->host));
        else
            run_record_frame(&c->rec, f - 1, ms, &stats);
        st = scene_host_read_positions(&c->host);
        if (st != WEFT_OK) return fail(c, "%s: frame %d: %s", a->scene, f, scene_host_error(&c->host));
        c->rec.nonfinite_outputs += run_record_bbox(&c->rec, c->host.positions, c->host.info.n_vertices);
        if (a->stats) { /* the stats' per-frame crossings and penetration: a check at every frame */
            if (weft_cloth_check_collisions(c->host.ctx, c->host.cloth, &chk) != WEFT_OK)
                return fail(c, "%s: frame %d: collision check: %s", a->scene, f, scene_host_error(&c->host));
            run_record_check(&c->rec, f - 1, &chk);
            checked = 1;
        }
        rc = write_frame(c, a, f, f * dt);
        run_progress_update(&c->progress, f);
    }
    run_progress_end(&c->progress);
    if (rc == CLI_EXIT_OK && a->cache && run_cache_close(&c->cache, 1) != 0)
        return fail(c, "cannot write '%s': %s", a->cache, strerror(errno));
    /* the collision check of the last frame (the rest shape when no frame ran; --stats' check of
       the last frame when it made one) */
    if (rc == CLI_EXIT_OK) {
        if (!checked && weft_cloth_check_collisions(c->host.ctx, c->host.cloth, &chk) != WEFT_OK)
            return fail(c, "%s: collision check: %s", a->scene, scene_host_error(&c->host));
        c->rec.self_intersections = chk.self_intersections;
        c->rec.max_penetration = chk.max_penetration;
    }
    return rc;
}

int cli_run_run(int argc, char** argv) {
    run_args a = {NULL, -1, -1, -1, -1, -1, -2, NULL, NULL, NULL, -1, WEFT_BACKEND_CPU, 0, -2, NULL, -2.0};
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0) return rc;

    run_ctx c;
    memset(&c, 0, sizeof c);
    cli_diag d = {0};
    weft_status st = scene_load(&c.sc, a.scene, &d);
    if (st != WEFT_OK) return fail(NULL, "%s", d.message[0] ? d.message : weft_status_string(st));
    if (a.frames >= 0) c.sc.frames = a.frames;
    weft_cloth_def* def = &c.sc.def;
    if (a.solver >= 0) def->solver = (weft_solver)a.solver;
    if (a.threads >= 0) c.sc.threads = a.threads;
    if (a.integrator >= 0) def->integrator = (weft_integrator)a.integrator;
    if (a.precond >= 0) def->preconditioner = (weft_preconditioner)a.precond;
    if (a.newton > 0) def->newton_iterations = a.newton;
    if (a.forcing > -2) def->newton_forcing = a.forcing;
    if (a.line_search > -2) def->line_search = a.line_search;
    if (a.self_collision > -2) def->self_collision = a.self_collision;
    cli_blas_threads(c.sc.threads); /* CHOLMOD's BLAS: as many threads as the run (0: its own) */

    char msg[1024];
    scene_host_opts opts;
    memset(&opts, 0, sizeof opts);
    opts.backend = a.backend;
    opts.threads = c.sc.threads;
    if (scene_host_create(&c.host, &c.sc, &opts, a.scene, msg, sizeof msg) != WEFT_OK) {
        rc = fail(NULL, "%s", msg);
    } else if (run_record_init(&c.rec, c.sc.frames) != 0) {
        rc = fail(NULL, "%s: out of memory", a.scene);
    } else {
        run_record_bbox(&c.rec, c.host.positions, c.host.info.n_vertices);   /* frames 0: the rest shape */
        rc = simulate(&c, &a);
    }
    if (rc == CLI_EXIT_OK) {
        const weft_cloth_info* in = &c.host.info;
        const run_info info = {a.scene,
                               in->n_particles,
                               in->n_triangles,
                               in->n_springs[0] + in->n_springs[1] + in->n_springs[2],
                               cli_solver_name(def->solver),
                               /* what the library resolved the scene's choices (or its defaults) to */
                               cli_precond_name(in->preconditioner),
                               in->integrator == WEFT_INTEGRATOR_BDF2     ? "bdf2"
                               : in->integrator == WEFT_INTEGRATOR_TRBDF2 ? "trbdf2"
                                                                          : "be",
                               in->newton_iterations,
                               in->line_search,
                               in->newton_forcing,
                               in->tolerance,
                               in->backend == WEFT_BACKEND_GPU ? "gpu" : "cpu",
                               in->backend_reason,
                               def->substeps,
                               in->threads,
                               c.sc.fps,
                               a.out,
                               a.render,
                               in->self_collision,
                               in->self_collision_thickness};
        errno = 0;
        if (a.stats && run_write_stats(a.stats, &info, &c.rec) != 0)
            rc = fail(NULL, "cannot write '%s': %s", a.stats, errno ? strerror(errno) : "out of memory");
        else if (!a.quiet)
            run_print_summary(stdout, &info, &c.rec);
    }
    run_release(&c);
    return rc;
}
