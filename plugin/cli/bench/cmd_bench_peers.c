/* `weft bench peers`: Weft beside Blender's own cloth solver. For every scene, Blender's cloth
 * (its defaults, 5 quality steps per frame; host_glue/blender/peer_cloth_bench.py run by a child
 * `blender -b`, see bench_blender.c) and Weft through the public API (PCG at each --substeps
 * count x preconditioner x integrator x Newton iterations; and once at weft_default_cloth_def(),
 * whatever the library resolves that to) simulate the same mesh, the same pinned particles (held
 * still) and the same number of frames with the same thread count; the table gives both medians
 * of ms per frame, their ratio, and how far each cloth's lowest point hangs below its pins at the
 * end (a sanity number, not an error: the two material models differ). Without Blender the
 * command says so and prints Weft's rows alone. --backend cpu,gpu runs Weft on each backend
 * beside the same Blender run. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_blender.h"
#include "bench_commands.h"
#include "bench_matched.h"
#include "bench_peer_scene.h"
#include "bench_method.h"
#include "bench_run.h"
#include "bench_table.h"
#include "cli.h"
#include "names.h"
#include "scene_host.h"

#ifndef WEFT_SAMPLE_SCENES
#define WEFT_SAMPLE_SCENES "sample_scenes"   /* for the usage text; the default is set in cmd_bench.c */
#endif
#ifndef WEFT_BLENDER_SCRIPT
#define WEFT_BLENDER_SCRIPT "host_glue/blender/peer_cloth_bench.py"
#endif

#define MAX_SCENES 16

typedef struct peers_args {
    const char* scenes[MAX_SCENES];
    int n_scenes;
    char scene_buf[512];
    int substeps[BENCH_MAX_LIST];
    int n_substeps;
    int frames;
    double fps;
    double timeout;
    const char* blender;    /* NULL: `blender` on PATH */
    const char* script;
    int backends[BENCH_MAX_BACKENDS];
    int n_backends;
    bench_methods meth;
    int defaults_row;       /* 1: the row through the public API at weft_default_cloth_def() */
    int matched;            /* --matched: at matched accuracy (cmd_bench_peers_matched.c) */
    int scenes_given, threads_given;
    int qualities[BENCH_MAX_LIST];
    int n_qualities;
    int ref_quality, ref_substeps;
    unsigned settings;
    bench_common com;
} peers_args;

void bench_peers_usage(FILE* out) {
    fputs("usage: weft bench peers [--quick] [--scenes LIST] [--substeps LIST] [--frames N] [--fps F]\n"
          "                        [--preconds LIST] [--integrators LIST] [--newton LIST]\n"
          "                        [--line-search MODE] [--newton-forcing LIST] [--no-defaults]\n"
          "                        [--blender PATH] [--script FILE]\n"
          "                        [--timeout S] [--threads N] [--garment FILE] [--csv FILE] [--md FILE]\n"
          "                        [--backend LIST] [--quiet]\n"
          "       weft bench peers --matched [--scenes LIST] [--frames N] [--qualities LIST]\n"
          "                        [--ref-quality Q] [--settings LIST] [--ref-substeps S] [...]\n"
          "\n"
          "Weft beside Blender's own cloth solver, in the same run; Weft on the CPU and/or the GPU\n"
          "(--backend).\n"
          "Needs Debian's blender (3.4): when no `blender` is on PATH the command says so (stderr and\n"
          "the Markdown) and prints Weft's rows alone, Blender's columns `-`.\n"
          "For each scene Blender runs the driver script (--script) headless on the same mesh (one\n"
          "vertex per Weft particle) with the same pinned vertices held still: a Cloth modifier\n"
          "with Blender's defaults and 5 quality steps per frame, timed frame by frame; then Weft\n"
          "(the scene's defaults: PCG) runs the same frames at each --substeps count x\n"
          "preconditioner x integrator x Newton iterations, and once more at its defaults: through\n"
          "the public API with weft_default_cloth_def() (the `defaults` row, CPU: whatever solver,\n"
          "preconditioner, integrator, Newton iterations and substeps the library chooses; sleeping\n"
          "off). Both use --threads threads (Blender: -t N and OMP_NUM_THREADS=N). Per row:\n"
          "  ms/frame        median wall time of one frame (Weft: weft_cloth_step; Blender: one\n"
          "                  scene.frame_set, its cloth evaluation included)\n"
          "  Blender / Weft  the ratio of the two medians (> 1: Weft is faster)\n"
          "  drop            how far the lowest point hangs below the highest pin at the end (m):\n"
          "                  a sanity number, not an error (the material models differ)\n"
          "  it./solve       Weft's solver iterations per linear solve, mean\n"
          "\n"
          "options (lists are comma-separated):\n"
          "  --quick          seconds-long preset: sheet12, 10 frames, substeps 1, 1 thread, 120 s\n"
          "                   timeout (later options still apply)\n"
          "  --scenes LIST    sheetN (N x N particles, 1 m, flat at first, hanging from two\n"
          "                   corners), hangN (upright from the start), garment (the --garment mesh\n"
          "                   pinned at its waist, held still); default sheet32,sheet64,sheet100,\n"
          "                   garment\n"
          "  --substeps LIST  Weft's substeps per frame (default 1,5; Blender always takes 5 steps)\n",
          out);
    fputs(BENCH_METHOD_HELP("block_jacobi,amg")
          "  --no-defaults    no row through the public API at weft_default_cloth_def()\n"
          "  --frames N       frames simulated by each (default 60)\n"
          "  --fps F          Weft's frames per second (default 30; Blender's cloth ignores the\n"
          "                   frame rate: its frame is a fixed unit, in free fall like 1/31.6 s)\n"
          "  --blender PATH   the blender executable (default: `blender` on PATH)\n"
          "  --script FILE    the driver (default " WEFT_BLENDER_SCRIPT ")\n"
          "  --timeout S      kill a Blender run after S seconds (default 600)\n"
          "  --threads N      threads for both (default 0: each one's own default)\n"
          "  --garment FILE   the garment mesh (default " WEFT_SAMPLE_SCENES "/skirt.obj)\n"
          "  --csv FILE       write every row as CSV\n"
          "  --md FILE        write the Markdown table to FILE instead of stdout\n"
          "  --backend LIST   cpu, gpu or cpu,gpu (default cpu): Weft's rows on each backend beside\n"
          "                   the same Blender run (gpu: weft_cloth_step on a GPU context, headless\n"
          "                   EGL; --threads is then the CPU side's only)\n"
          "  --quiet          no progress lines on stderr\n"
          "  -h, --help       show this help\n"
          "\n"
          "--matched: at matched accuracy. Each simulator is measured against its OWN converged run\n"
          "of the same scene: Blender at each --qualities count, at --ref-quality (its reference) and\n"
          "at half of it (the reference's check); Weft through the public API at each --settings\n"
          "entry, and its reference, TR-BDF2 Newton 3 with every solve to 1e-8 at --ref-substeps\n"
          "(and half of them, its check). Every run keeps every frame's positions; its error is the RMS\n"
          "over all frames and particles of its distance to its reference at the same frame, in % of\n"
          "the diagonal of the reference trajectory's bounding box (and at the last frame alone). The\n"
          "verdict per scene and Blender quality: the fastest Weft setting whose error is no larger,\n"
          "and the ratio of the medians of a frame's CPU time (wall time beside it; goal: >= 10 x on\n"
          "the sheets, >= 3 x on the garment, against quality 5); the same by the last frame's error\n"
          "beside it. The garment's waist twirls (a turn a second after a 0.5 s ramp), Blender's\n"
          "object keyed to turn as Weft's pins do. One thread each unless --threads says otherwise; a\n"
          "Blender run's time\n"
          "limit is --timeout x quality / 5. --substeps, the method options, --no-defaults and\n"
          "--backend do not apply.\n"
          "  --matched        this mode; default scenes sheet64,sheet100,garment\n"
          "  --qualities LIST Blender's qualities measured (default 5,10,20)\n"
          "  --ref-quality Q  Blender's reference quality (default 80; its check Q/2)\n"
          "  --settings LIST  Weft's settings measured (default all):\n"
          "                   " BENCH_MATCHED_SETTING_NAMES "\n"
          "  --ref-substeps S Weft's reference substeps (default 32; its check S/2)\n",
          out);
}

static void set_scenes(peers_args* a, const char* list) {
    a->n_scenes = bench_split_names(list, a->scene_buf, sizeof a->scene_buf, a->scenes, MAX_SCENES);
}

static void defaults(void* args, int quick) {
    peers_args* a = args;
    memset(a, 0, sizeof *a);
    set_scenes(a, quick ? "sheet12" : "sheet32,sheet64,sheet100,garment");
    a->n_substeps = bench_parse_ints(quick ? "1" : "1,5", 1, 1024, a->substeps);
    a->frames = quick ? 10 : 60;
    a->fps = 30;
    a->timeout = quick ? 120 : 600;
    a->script = WEFT_BLENDER_SCRIPT;
    a->backends[0] = BENCH_CPU;
    a->n_backends = 1;
    bench_methods_default(&a->meth, "block_jacobi,amg");
    a->defaults_row = 1;
    a->n_qualities = bench_parse_ints("5,10,20", 1, 1000, a->qualities);
    a->ref_quality = 80;
    a->ref_substeps = 32;
    bench_matched_parse_settings("all", &a->settings);
}

static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    peers_args* a = args;
    int m = 0;
#define OPT(name) ((m = cli_option_value(argc, argv, i, name, v)) != 0)
#define BAD(cond) (m < 0 ? m : (cond) ? -2 : 1) /* m < 0: the value is missing */
    if (OPT("--scenes")) {
        if (m < 0) return m;
        set_scenes(a, *v);
        a->scenes_given = 1;
        return BAD(a->n_scenes == 0);
    }
    if (!strcmp(argv[*i], "--matched")) {
        a->matched = 1;
        return 1;
    }
    if (OPT("--qualities")) return BAD((a->n_qualities = bench_parse_ints(*v, 1, 1000, a->qualities)) < 0);
    if (OPT("--ref-quality")) return BAD(cli_parse_int(*v, 2, 1000, &a->ref_quality) != 0);
    if (OPT("--ref-substeps")) return BAD(cli_parse_int(*v, 2, 1024, &a->ref_substeps) != 0);
    if (OPT("--settings")) return BAD(bench_matched_parse_settings(*v, &a->settings) < 0);
    if (OPT("--substeps")) return BAD((a->n_substeps = bench_parse_ints(*v, 1, 1024, a->substeps)) < 0);
    if (OPT("--frames")) return BAD(cli_parse_int(*v, 1, 1000000, &a->frames) != 0);
    if (OPT("--fps")) return BAD(cli_parse_double(*v, &a->fps) != 0 || !(a->fps >= 1 && a->fps <= 10000));
    if (OPT("--timeout"))
        return BAD(cli_parse_double(*v, &a->timeout) != 0 || !(a->timeout > 0 && a->timeout <= 86400));
    if (OPT("--backend")) return BAD((a->n_backends = bench_parse_backends(*v, a->backends)) < 0);
    if (OPT("--blender")) {
        if (m < 0) return m;
        a->blender = *v;
        return BAD(!**v);
    }
    if (OPT("--script")) {
        if (m < 0) return m;
        a->script = *v;
        return BAD(!**v);
    }
    if (!strcmp(argv[*i], "--no-defaults")) {
        a->defaults_row = 0;
        return 1;
    }
#undef OPT
#undef BAD
    return bench_methods_option(&a->meth, argc, argv, i, v);
}

enum {
    C_BACKEND, C_SCENE, C_PARTICLES, C_FRAMES, C_WEFT_THREADS, C_BLENDER_THREADS, C_SOLVER, C_SUBSTEPS,
    C_WEFT_MS, C_BLENDER_MS, C_RATIO, C_WEFT_DROP, C_BLENDER_DROP, C_PIN_DRIFT, C_VERSION, C_NOTES, C_CONFIG,
    C_PRECOND, C_INTEGRATOR, C_NEWTON, C_LINE_SEARCH, C_ITER_SOLVE, C_SETUP_MS, N_COLS
};
static const char* const csv_cols[N_COLS] = {
    "backend", "scene", "particles", "frames", "weft_threads", "blender_threads", "weft_solver", "weft_substeps",
    "weft_ms_per_frame", "blender_ms_per_frame", "ratio_blender_over_weft", "weft_drop_m", "blender_drop_m",
    "blender_pin_drift_m", "blender_version", "notes", "weft_config", "weft_preconditioner", "weft_integrator",
    "weft_newton_iterations", "weft_line_search", "weft_iterations_per_solve", "weft_ms_precond_per_solve"};
static const char* const md_cols[N_COLS] = {
    NULL /* "backend" with two backends */, "scene", "particles", NULL, NULL, NULL, NULL, "Weft substeps", "Weft ms/frame", "Blender ms/frame",
    "Blender / Weft", "Weft drop (m)", "Blender drop (m)", NULL, NULL, "notes", "Weft config", "precond.",
    "integrator", "Newton", NULL, "it./solve", NULL};

/* How far the lowest point of x (n x 3) lies below the highest pinned rest point (rest: the
 * particles' rest positions, pins their indices; with no pin, below the highest rest point). */
static double drop_below_pins(const float* rest, int n_rest, const int* pins, int n_pins, const float* x, int n) {
    double top = -INFINITY, low = INFINITY;
    for (int k = 0; k < n_pins; ++k) top = fmax(top, rest[3 * (size_t)pins[k] + 1]);
    if (n_pins == 0)
        for (int i = 0; i < n_rest; ++i) top = fmax(top, rest[3 * (size_t)i + 1]);
    for (int i = 0; i < n; ++i) low = isnan(x[3 * (size_t)i + 1]) ? NAN : fmin(low, x[3 * (size_t)i + 1]);
    return top - low;
}

/* The largest distance of a pinned particle of Blender's result from its rest position. */
static double pin_drift(const bench_peer_mesh* pm, const double* x) {
    double worst = 0.0;
    for (int k = 0; k < pm->n_pins; ++k) {
        const double* p = x + 3 * (size_t)pm->pins[k];
        const float* r = pm->x + 3 * (size_t)pm->pins[k];
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) d2 += (p[c] - r[c]) * (p[c] - r[c]);
        if (!(sqrt(d2) <= worst)) worst = sqrt(d2);
    }
    return worst;
}

typedef struct header_info {
    const peers_args* a;
    int weft_threads, blender_threads;
    char version[32];
    char settings[768];
    weft_solver solver;     /* Weft's scene rows' (the scenes' default) */
    double tolerance;
    int max_iterations;
    char missing[1024];     /* why there is no Blender ("": there is) */
    struct {
        char scene[32];
        double blender_ms, defaults_ms;   /* NaN: not run */
    } sum[MAX_SCENES];      /* per scene: Blender beside Weft at its defaults */
    int n_sum;
} header_info;

#define PEERS_GOAL 10.0     /* the goal: Weft at its defaults >= 10 x faster than Blender */

static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    const peers_args* a = h->a;
    char note[1024], tol[96];
    fprintf(out, "## weft bench peers\n\n");
    if (h->missing[0])
        fprintf(out, "**No Blender here** (%s): Weft's rows only, Blender's columns `-`.\n\n", h->missing);
    if (h->n_sum > 0 && a->defaults_row) {
        fprintf(out, "Blender beside Weft at its defaults (weft_default_cloth_def() through the public API, CPU), "
                     "per scene (goal: >= %g x):\n\n| scene | Blender ms/frame | Weft defaults ms/frame | "
                     "Blender / Weft | >= %g x |\n|---|---|---|---|---|\n", PEERS_GOAL, PEERS_GOAL);
        for (int k = 0; k < h->n_sum; ++k) {
            const double ratio = h->sum[k].blender_ms / h->sum[k].defaults_ms;
            char bm[32], rt[32];
            if (isnan(ratio)) snprintf(bm, sizeof bm, "-"), snprintf(rt, sizeof rt, "-");
            else snprintf(bm, sizeof bm, "%.4g", h->sum[k].blender_ms), snprintf(rt, sizeof rt, "%.3g", ratio);
            fprintf(out, "| %s | %s | %.4g | %s | %s |\n", h->sum[k].scene, bm, h->sum[k].defaults_ms, rt,
                    isnan(ratio) ? "-" : ratio >= PEERS_GOAL ? "met" : "not met");
        }
        fputc('\n', out);
    }
    if (h->missing[0])
        fprintf(out, "%s. Weft alone (no Blender), %d frames per row. Threads: Weft %d (OpenMP).\n\n",
                bench_backend_note(a->backends, a->n_backends, note, sizeof note), a->frames, h->weft_threads);
    else
        fprintf(out,
                "%s. Blender %s's cloth solver beside Weft's on the same meshes (one Blender vertex per Weft "
                "particle), the same pinned vertices held still, %d frames each, in one run. Threads: Weft %d "
                "(OpenMP), Blender %d%s.\n\n",
                bench_backend_note(a->backends, a->n_backends, note, sizeof note), h->version, a->frames, h->weft_threads, h->blender_threads,
                a->com.threads > 0 ? " (blender -t, OMP_NUM_THREADS)" : "");
    if (!h->missing[0])
        fprintf(out,
                "- Blender: a Cloth modifier with Blender's defaults and 5 quality steps per frame, a fresh file "
                "(--factory-startup), each frame one timed scene.frame_set (host_glue/blender/peer_cloth_bench.py). "
                "Settings read back: %s.\n",
                h->settings);
    fprintf(out,
            "- Weft: the scene's defaults (default material; %s solver, relative tolerance %s, at most %d "
            "iterations) at %g frames per second, the substeps per frame given in the table; each frame one "
            "timed weft_cloth_step on the CPU's or the GPU's context (positions read back after the frame, "
            "outside its time); precond., integrator and Newton as in the table. The `defaults` row: the "
            "library at weft_default_cloth_def() (its own material, solver, preconditioner, integrator, "
            "Newton iterations and substeps; sleeping off), on the CPU.\n",
            cli_solver_name(h->solver), cli_tolerance_text(h->tolerance, tol, sizeof tol), h->max_iterations, a->fps);
    fputs("- ms/frame: median over the frames. Blender / Weft: the ratio of the medians (> 1: Weft is faster).\n"
          "- Time: Blender's cloth ignores the frame rate; its frame is a fixed unit in which gravity is scaled "
          "by 0.001, i.e. it falls like 1/31.6 s per frame (within 5% of Weft's 1/30 s).\n"
          "- drop: how far the lowest point hangs below the pins at the end (m). A sanity number, not an "
          "error: the material models differ (Blender's default mass is 0.3 kg per vertex, Weft's a "
          "density per area; the stiffnesses are in different units).\n\n",
          out);
}

/* What one Weft row ran: the scene's defaults with a method, or the library's defaults. */
typedef struct weft_row {
    int backend;
    int defaults;           /* 1: through the public API at weft_default_cloth_def() */
    int substeps;
    bench_method method;
} weft_row;

static int add_row(bench_table* t, const weft_row* w, const bench_scene* bs, const peers_args* a,
                   const bench_peer_mesh* pm, const bench_blender_result* br, const bench_run* r) {
    char b[N_COLS][96];
    const char* cell[N_COLS];
    const int blender = br->x != NULL; /* 0: no Blender on this machine */
    snprintf(b[C_BACKEND], 96, "%s", bench_backend_name(w->backend));
    snprintf(b[C_SCENE], 96, "%s", bs->name);
    snprintf(b[C_PARTICLES], 96, "%d", r->particles);
    snprintf(b[C_FRAMES], 96, "%d", a->frames);
    snprintf(b[C_WEFT_THREADS], 96, "%d", r->threads);
    snprintf(b[C_BLENDER_THREADS], 96, blender ? "%d" : "-", br->threads);
    snprintf(b[C_SOLVER], 96, "%s", w->defaults ? "default" : cli_solver_name(bs->sc.def.solver));
    if (w->defaults) snprintf(b[C_SUBSTEPS], 96, "default");
    else snprintf(b[C_SUBSTEPS], 96, "%d", w->substeps);
    bench_fmt(b[C_WEFT_MS], 96, "%.4g", r->ms_median);
    if (blender) {
        bench_fmt(b[C_BLENDER_MS], 96, "%.4g", br->ms_median);
        bench_fmt(b[C_RATIO], 96, "%.3g", br->ms_median / r->ms_median);
    } else {
        snprintf(b[C_BLENDER_MS], 96, "-");
        snprintf(b[C_RATIO], 96, "-");
    }
    bench_fmt(b[C_WEFT_DROP], 96, "%.3f", drop_below_pins(pm->x, pm->n, pm->pins, pm->n_pins, r->x, r->vertices));
    const double drift = blender ? pin_drift(pm, br->x) : 0.0;
    if (blender) {
        float* bx = malloc(sizeof(float) * 3 * (size_t)(br->n_verts > 0 ? br->n_verts : 1));
        for (int i = 0; bx && i < 3 * br->n_verts; ++i) bx[i] = (float)br->x[i];
        bench_fmt(b[C_BLENDER_DROP], 96, "%.3f",
                  bx ? drop_below_pins(pm->x, pm->n, pm->pins, pm->n_pins, bx, br->n_verts) : NAN);
        free(bx);
        bench_fmt(b[C_PIN_DRIFT], 96, "%.3g", drift);
        snprintf(b[C_VERSION], 96, "%s", br->version);
    } else {
        snprintf(b[C_BLENDER_DROP], 96, "-");
        snprintf(b[C_PIN_DRIFT], 96, "-");
        snprintf(b[C_VERSION], 96, "-");
    }
    char* notes = b[C_NOTES];
    notes[0] = '\0';
    if (!strcmp(bs->name, "garment")) snprintf(notes, 96, "waist pinned, still");
    if (r->failures > 0 || r->nonfinite)
        snprintf(notes + strlen(notes), 96 - strlen(notes), "%sWeft: %d failed substeps%s", notes[0] ? "; " : "",
                 r->failures, r->nonfinite ? ", non-finite" : "");
    if (!(drift <= 1e-3))
        snprintf(notes + strlen(notes), 96 - strlen(notes), "%sBlender's pins moved %.3g m", notes[0] ? "; " : "",
                 drift);
    snprintf(b[C_CONFIG], 96, "%s", w->defaults ? "defaults" : "scene");
    if (w->defaults) {
        for (int k = C_PRECOND; k <= C_LINE_SEARCH; ++k) snprintf(b[k], 96, "default");
    } else {
        snprintf(b[C_PRECOND], 96, "%s", bench_precond_label(bs->sc.def.solver, &w->method));
        snprintf(b[C_INTEGRATOR], 96, "%s", cli_integrator_name(w->method.integrator));
        snprintf(b[C_NEWTON], 96, "%d", w->method.newton);
        snprintf(b[C_LINE_SEARCH], 96, "%s", w->method.line_search ? "on" : "off");
    }
    bench_fmt(b[C_ITER_SOLVE], 96, "%.1f", bench_run_iterations_per_solve(r));
    bench_fmt(b[C_SETUP_MS], 96, "%.3g", bench_run_precond_ms_per_solve(r));
    for (int k = 0; k < N_COLS; ++k) cell[k] = b[k];
    return bench_table_add(t, cell);
}

/* One Weft run of a row: the scene's def with the row's method and substeps, or (the defaults
 * row) the scene's def as it is, the library's defaults. 0, or -1 with the message on stderr. */
static int run_weft(const peers_args* a, const bench_scene* bs, const weft_row* w, bench_run* r) {
    bench_run_opts o;
    memset(&o, 0, sizeof o);
    o.backend = w->backend;
    o.def = bench_run_def(bs);
    if (!w->defaults) {
        o.def.substeps = w->substeps;
        bench_method_apply(&w->method, &o.def);
    }
    o.fps = a->fps;
    o.frames = a->frames;
    char msg[1024];
    if (bench_run_scene(bs, &o, r, msg, sizeof msg) == 0) return 0;
    cli_error(msg);
    return -1;
}

/* The cloth as Blender gets it: the library's rest positions of the scene's cloth, welded twins
 * merged (a cloth made on the CPU context for the purpose). 0, or -1 with the message on stderr. */
/* One scene: Blender once (when there is one), then Weft's rows. */
static int run_scene(const peers_args* a, const char* blender, const char* name, bench_table* t, header_info* h) {
    bench_scene bs;
    char msg[1024];
    if (bench_scene_build(&bs, name, a->com.garment, 1.0, 1.0, msg, sizeof msg) != 0) {
        cli_error(msg);
        return CLI_EXIT_FAILURE;
    }
    bs.spin = 0.0; /* the garment's waist held still: Blender's pins do not move */
    bench_peer_mesh pm;
    if (bench_peers_mesh(&bs, &pm) != 0) {
        bench_scene_free(&bs);
        return CLI_EXIT_FAILURE;
    }
    bench_blender_result br;
    memset(&br, 0, sizeof br);
    if (blender) {
        if (!a->com.quiet) fprintf(stderr, "%s (%d particles): blender...\n", bs.name, pm.n);
        if (bench_blender_run(blender, a->script, &pm, a->frames, a->com.threads, a->timeout, &br, msg, sizeof msg) != 0) {
            cli_error(msg);
            bench_peer_mesh_free(&pm);
            bench_scene_free(&bs);
            return CLI_EXIT_FAILURE;
        }
        snprintf(h->version, sizeof h->version, "%s", br.version);
        snprintf(h->settings, sizeof h->settings, "%s", br.settings);
        h->blender_threads = br.threads;
    }
    h->solver = bs.sc.def.solver;
    h->tolerance = bs.sc.def.tolerance;
    h->max_iterations = bs.sc.def.max_iterations;
    /* the rows: backend x method x substeps, then the library's defaults (CPU) */
    static weft_row rows[BENCH_MAX_BACKENDS * BENCH_MAX_LIST * BENCH_MAX_LIST + 1];
    bench_method meth[BENCH_MAX_LIST];
    const int n_meth = bench_methods_expand(&a->meth, bs.sc.def.solver, meth, BENCH_MAX_LIST);
    int n_rows = 0;
    for (int bi = 0; bi < a->n_backends; ++bi)
        for (int mi = 0; mi < n_meth; ++mi) {
            const bench_method* m = &meth[mi];
            if (a->backends[bi] == BENCH_GPU && !bench_method_on_gpu(m)) continue;   /* what the GPU runs */
            for (int k = 0; k < a->n_substeps; ++k)
                rows[n_rows++] = (weft_row){a->backends[bi], 0, a->substeps[k], *m};
        }
    if (a->defaults_row) rows[n_rows++] = (weft_row){BENCH_CPU, 1, 0, meth[0]};
    int rc = CLI_EXIT_OK;
    for (int q = 0; q < n_rows && rc == CLI_EXIT_OK; ++q) {
        bench_run r;
        if (run_weft(a, &bs, &rows[q], &r) != 0) {
            rc = CLI_EXIT_FAILURE;
            break;
        }
        h->weft_threads = r.threads;
        if (!a->com.quiet) {
            char label[64];
            if (rows[q].defaults) snprintf(label, sizeof label, "defaults (weft_default_cloth_def)");
            else
                snprintf(label, sizeof label, "%d substep(s) %s", rows[q].substeps,
                         bench_method_short(bs.sc.def.solver, &rows[q].method, msg, sizeof msg));
            fprintf(stderr, "  weft (%s) %s: %.3g ms/frame, %.1f it./solve; blender: %.3g ms/frame\n",
                    bench_backend_name(rows[q].backend), label, r.ms_median, bench_run_iterations_per_solve(&r),
                    blender ? br.ms_median : NAN);
        }
        if (rows[q].defaults && h->n_sum < MAX_SCENES) {
            snprintf(h->sum[h->n_sum].scene, sizeof h->sum[h->n_sum].scene, "%s", bs.name);
            h->sum[h->n_sum].blender_ms = blender ? br.ms_median : NAN;
            h->sum[h->n_sum++].defaults_ms = r.ms_median;
        }
        if (add_row(t, &rows[q], &bs, a, &pm, &br, &r) != 0) {
            cli_error("out of memory");
            rc = CLI_EXIT_FAILURE;
        }
        bench_run_free(&r);
    }
    if (blender) bench_blender_free(&br);
    bench_peer_mesh_free(&pm);
    bench_scene_free(&bs);
    return rc;
}

int bench_peers_run(int argc, char** argv) {
    peers_args a;
    int rc = bench_parse_args(argc, argv, "weft bench peers", bench_peers_usage, defaults, own_option, &a, &a.com);
    if (rc >= 0) return rc;
    if (a.com.plot) return cli_usage_error("weft bench peers", bench_peers_usage, "--plot: this command draws no plot");
    int quick = 0;
    for (int i = 1; i < argc; ++i) {
        a.threads_given |= !strncmp(argv[i], "--threads", 9);
        quick |= !strcmp(argv[i], "--quick");
    }
    if (a.matched && (a.n_backends != 1 || a.backends[0] != BENCH_CPU))
        return cli_usage_error("weft bench peers", bench_peers_usage, "--matched runs Weft on the CPU only");
    if (a.matched && !a.threads_given) {   /* one thread each, unless asked otherwise */
        a.com.threads = 1;
        a.com.blas_threads = cli_blas_threads(1);
    }
    if (a.matched && !a.scenes_given && !quick) set_scenes(&a, "sheet64,sheet100,garment");
    char blender[1024], msg[1024];
    header_info h;
    memset(&h, 0, sizeof h);
    h.a = &a;
    if (bench_blender_find(a.blender, blender, sizeof blender, msg, sizeof msg) != 0) {
        if (a.blender) { /* asked for by path: that one must run */
            cli_error(msg);
            return CLI_EXIT_FAILURE;
        }
        fprintf(stderr, "weft: %s: Weft's rows only\n", msg);
        snprintf(h.missing, sizeof h.missing, "%s", msg);
    }
    if (a.matched) {
        const bench_matched_opts mo = {a.scenes, a.n_scenes, a.frames, a.fps, a.timeout, h.missing[0] ? NULL : blender,
                                       h.missing, a.script, {0}, a.n_qualities, a.ref_quality, a.ref_substeps,
                                       a.settings, &a.com};
        bench_matched_opts m = mo;
        memcpy(m.qualities, a.qualities, sizeof m.qualities);
        return bench_peers_matched(&m);
    }
    h.weft_threads = a.com.threads;
    bench_table t;
    const char* md[N_COLS];
    memcpy(md, md_cols, sizeof md);
    if (a.n_backends > 1) md[C_BACKEND] = "backend";
    bench_table_init(&t, N_COLS, csv_cols, md);
    /* the peer mesh and the defaults row run on the CPU whatever --backend says */
    int open[BENCH_MAX_BACKENDS + 1] = {BENCH_CPU};
    memcpy(open + 1, a.backends, sizeof(int) * (size_t)a.n_backends);
    rc = bench_open_backends(open, 1 + a.n_backends, a.com.threads);
    for (int s = 0; s < a.n_scenes && rc == CLI_EXIT_OK; ++s)
        rc = run_scene(&a, h.missing[0] ? NULL : blender, a.scenes[s], &t, &h);
    if (rc == CLI_EXIT_OK) rc = bench_write_tables(&a.com, &t, print_header, &h);
    bench_table_free(&t);
    return rc;
}
