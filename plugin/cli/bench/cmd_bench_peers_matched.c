/* `weft bench peers --matched` (bench_matched.h): Blender's cloth and Weft at matched accuracy.
 * Per scene, Blender runs at each --qualities count and at its reference quality (and half of it,
 * the reference's check); Weft runs each --settings entry through the public API and its
 * reference, TR-BDF2 Newton 3 with every solve to 1e-8 at --ref-substeps (and half of them). Every
 * run keeps every frame's positions, by particle (Blender's vertex k is Weft's particle k). A
 * run's error is its RMS distance to its own simulator's reference over all frames and particles,
 * in % of the reference trajectory's bounding-box diagonal; the verdict per scene and Blender
 * quality is the fastest Weft run (by median ms a frame) whose error is no larger. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_backend.h"
#include "bench_matched.h"
#include "bench_peer_scene.h"
#include "bench_run.h"
#include "bench_table.h"
#include "bench_traj_error.h"
#include "cli.h"
#include "names.h"

/* ---------- Weft's settings ---------- */

typedef struct matched_setting {
    const char* name;       /* --settings name */
    const char* label;      /* in the tables */
    weft_integrator integrator;   /* DEFAULT: the library's */
    int newton;             /* 0: the library's */
    int line_search;        /* -1: the library's */
    int substeps;
    double tolerance;       /* 0: the library's */
    double forcing;         /* the first Newton solve's relative residual; < 0: the library's (1e-2) */
} matched_setting;

/* The first eight are the original table; the rest screen the second-order methods at one solve
 * a stage or a Newton iteration, and the linear solves' share of the error (forcing 0: every solve
 * to the tolerance; "tight": every solve to 1e-6; Newton 6: past the stall at the third iterate). */
static const matched_setting k_settings[] = {
    {"defaults", "defaults", WEFT_INTEGRATOR_DEFAULT, 0, -1, 1, 0, -1},
    {"defaults_s2", "defaults at 2 substeps", WEFT_INTEGRATOR_DEFAULT, 0, -1, 2, 0, -1},
    {"defaults_s4", "defaults at 4 substeps", WEFT_INTEGRATOR_DEFAULT, 0, -1, 4, 0, -1},
    {"newton1", "Newton 1 (one Baraff-Witkin step)", WEFT_INTEGRATOR_DEFAULT, 1, 0, 1, 0, -1},
    {"trbdf2_n2", "TR-BDF2 Newton 2", WEFT_INTEGRATOR_TRBDF2, 2, -1, 1, 0, -1},
    {"trbdf2_n2_s2", "TR-BDF2 Newton 2 at 2 substeps", WEFT_INTEGRATOR_TRBDF2, 2, -1, 2, 0, -1},
    {"trbdf2_n3", "TR-BDF2 Newton 3", WEFT_INTEGRATOR_TRBDF2, 3, -1, 1, 0, -1},
    {"trbdf2_n3_s2", "TR-BDF2 Newton 3 at 2 substeps", WEFT_INTEGRATOR_TRBDF2, 3, -1, 2, 0, -1},
    {"defaults_f0", "defaults forcing 0", WEFT_INTEGRATOR_DEFAULT, 0, -1, 1, 0, 0.0},
    {"defaults_tight", "defaults tol. 1e-6 forcing 0", WEFT_INTEGRATOR_DEFAULT, 0, -1, 1, 1e-6, 0.0},
    {"bdf2_n1", "BDF2 Newton 1 (no line search)", WEFT_INTEGRATOR_BDF2, 1, 0, 1, 0, -1},
    {"bdf2_n1_s2", "BDF2 Newton 1 (no line search) at 2 substeps", WEFT_INTEGRATOR_BDF2, 1, 0, 2, 0, -1},
    {"bdf2_n2", "BDF2 Newton 2", WEFT_INTEGRATOR_BDF2, 2, -1, 1, 0, -1},
    {"bdf2_n2_f0", "BDF2 Newton 2 forcing 0", WEFT_INTEGRATOR_BDF2, 2, -1, 1, 0, 0.0},
    {"bdf2_n2_s2", "BDF2 Newton 2 at 2 substeps", WEFT_INTEGRATOR_BDF2, 2, -1, 2, 0, -1},
    {"trbdf2_n1", "TR-BDF2 Newton 1 (no line search)", WEFT_INTEGRATOR_TRBDF2, 1, 0, 1, 0, -1},
    {"trbdf2_n1_tight", "TR-BDF2 Newton 1 (no line search) tol. 1e-6", WEFT_INTEGRATOR_TRBDF2, 1, 0, 1, 1e-6, -1},
    {"trbdf2_n1_s2", "TR-BDF2 Newton 1 (no line search) at 2 substeps", WEFT_INTEGRATOR_TRBDF2, 1, 0, 2, 0, -1},
    {"trbdf2_n2_f0", "TR-BDF2 Newton 2 forcing 0", WEFT_INTEGRATOR_TRBDF2, 2, -1, 1, 0, 0.0},
    {"trbdf2_n2_tight", "TR-BDF2 Newton 2 tol. 1e-6 forcing 0", WEFT_INTEGRATOR_TRBDF2, 2, -1, 1, 1e-6, 0.0},
    {"trbdf2_n3_f0", "TR-BDF2 Newton 3 forcing 0", WEFT_INTEGRATOR_TRBDF2, 3, -1, 1, 0, 0.0},
    {"trbdf2_n3_tight", "TR-BDF2 Newton 3 tol. 1e-6 forcing 0", WEFT_INTEGRATOR_TRBDF2, 3, -1, 1, 1e-6, 0.0},
    {"trbdf2_n6", "TR-BDF2 Newton 6", WEFT_INTEGRATOR_TRBDF2, 6, -1, 1, 0, -1},
    {"trbdf2_n6_tight", "TR-BDF2 Newton 6 tol. 1e-6 forcing 0", WEFT_INTEGRATOR_TRBDF2, 6, -1, 1, 1e-6, 0.0},
};
enum { N_SETTINGS = (int)(sizeof k_settings / sizeof k_settings[0]) };
_Static_assert(N_SETTINGS <= 32, "--settings is a 32-bit mask");

#define REF_TOLERANCE 1e-8
#define REF_MAX_ITERATIONS 2000

static int one_setting(const char* item, void* ctx, int k) {
    (void)k;
    unsigned* mask = ctx;
    if (!strcmp(item, "all")) {
        *mask |= (1u << N_SETTINGS) - 1u;
        return 0;
    }
    for (int s = 0; s < N_SETTINGS; ++s)
        if (!strcmp(item, k_settings[s].name)) {
            *mask |= 1u << s;
            return 0;
        }
    return -1;
}

int bench_matched_parse_settings(const char* list, unsigned* mask) {
    *mask = 0;
    return bench_for_each_item(list, one_setting, mask);
}

/* ---------- the runs of a scene ---------- */

enum { ROLE_RUN, ROLE_CHECK, ROLE_REF };
static const char* const k_roles[] = {"run", "reference's check", "reference"};

typedef struct matched_row {
    int blender;            /* 1: Blender's, 0: Weft's */
    int role;
    char setting[64];
    int steps;              /* Blender's quality, Weft's substeps */
    double ms;              /* median wall time of a frame */
    double cpu_ms;          /* median CPU time of a frame (the process's; NaN: not known) */
    float* xs;              /* (frames x particles x 3), by particle */
    double err_all, err_end;   /* % of the reference's diagonal */
    double it_solve;        /* Weft: iterations per linear solve (NaN: Blender) */
    char notes[96];         /* no commas: the CSV has no quoted fields */
} matched_row;

#define MAX_ROWS (BENCH_MAX_LIST + N_SETTINGS + 4)

typedef struct matched_scene {
    char name[32];
    int particles;
    double diag[2];         /* the references' trajectory diagonals: [0] Weft, [1] Blender (m) */
    double motion[2];       /* the references' RMS distance from the rest positions over all frames
                               and particles, % of diag: how much there is to get wrong */
    matched_row rows[MAX_ROWS];
    int n_rows;
} matched_scene;

typedef struct matched_ctx {
    const bench_matched_opts* o;
    matched_scene* scenes;
    int n_scenes;
    int weft_threads, blender_threads;
    char blender_omp[16];   /* OMP_NUM_THREADS as Blender saw it */
    char version[32];
    char settings[768];     /* Blender's read back at its first quality */
    weft_solver solver;
    double tolerance;
    int max_iterations;
} matched_ctx;

static void rows_free(matched_scene* s) {
    for (int k = 0; k < s->n_rows; ++k) free(s->rows[k].xs);
    s->n_rows = 0;
}

static int blender_row(matched_ctx* c, const bench_scene* bs, const bench_peer_mesh* pm, int quality, int role,
                       matched_scene* s) {
    const bench_matched_opts* o = c->o;
    char msg[1024];
    const bench_blender_job job = {o->frames, o->com->threads, quality, 1,
                                   o->timeout * (quality > 5 ? quality / 5.0 : 1.0),
                                   bs->spin, BENCH_GARMENT_RAMP, o->fps};
    bench_blender_result br;
    if (!o->com->quiet) fprintf(stderr, "%s (%d particles): blender quality %d...\n", s->name, pm->n, quality);
    if (bench_blender_run_job(o->blender, o->script, pm, &job, &br, msg, sizeof msg) != 0) {
        cli_error(msg);
        return -1;
    }
    matched_row* r = &s->rows[s->n_rows++];
    memset(r, 0, sizeof *r);
    r->blender = 1;
    r->role = role;
    snprintf(r->setting, sizeof r->setting, "quality %d", quality);
    r->steps = quality;
    r->ms = br.ms_median;
    r->cpu_ms = br.cpu_ms_median;
    r->xs = br.xs;
    br.xs = NULL;
    r->it_solve = NAN;
    if (!c->version[0]) {
        snprintf(c->version, sizeof c->version, "%s", br.version);
        snprintf(c->settings, sizeof c->settings, "%s", br.settings);
    }
    c->blender_threads = br.threads;
    snprintf(c->blender_omp, sizeof c->blender_omp, "%s", br.omp_threads[0] ? br.omp_threads : "unset");
    if (!o->com->quiet) fprintf(stderr, "  %.4g ms/frame (CPU %.4g)\n", r->ms, r->cpu_ms);
    bench_blender_free(&br);
    return 0;
}

/* A Weft run: setting `st` (NULL: the reference at `substeps`), its frames by particle. */
static int weft_row(matched_ctx* c, const bench_scene* bs, const bench_peer_mesh* pm, const int* rep,
                    const matched_setting* st, int substeps, int role, matched_scene* s) {
    const bench_matched_opts* o = c->o;
    bench_run_opts ro;
    memset(&ro, 0, sizeof ro);
    ro.backend = BENCH_CPU;
    ro.def = bench_run_def(bs);
    if (st) {
        if (st->integrator != WEFT_INTEGRATOR_DEFAULT) ro.def.integrator = st->integrator;
        if (st->newton > 0) ro.def.newton_iterations = st->newton;
        if (st->line_search >= 0) ro.def.line_search = st->line_search;
        ro.def.substeps = st->substeps;
        if (st->tolerance > 0) ro.def.tolerance = st->tolerance;
        if (st->forcing >= 0) ro.def.newton_forcing = st->forcing;
    } else {   /* converged: every Newton solve to 1e-8 */
        ro.def.integrator = WEFT_INTEGRATOR_TRBDF2;
        ro.def.newton_iterations = 3;
        ro.def.tolerance = REF_TOLERANCE;
        ro.def.max_iterations = REF_MAX_ITERATIONS;
        ro.def.newton_forcing = 0.0;
        ro.def.substeps = substeps;
    }
    ro.fps = o->fps;
    ro.frames = o->frames;
    ro.record_frames = 1;
    matched_row* r = &s->rows[s->n_rows];
    memset(r, 0, sizeof *r);
    if (st) snprintf(r->setting, sizeof r->setting, "%s", st->label);
    else snprintf(r->setting, sizeof r->setting, "TR-BDF2 Newton 3 tol. 1e-8 at %d substeps", substeps);
    if (!o->com->quiet) fprintf(stderr, "%s (%d particles): weft %s...\n", s->name, pm->n, r->setting);
    char msg[1024];
    bench_run run;
    if (bench_run_scene(bs, &ro, &run, msg, sizeof msg) != 0) {
        cli_error(msg);
        return -1;
    }
    if (run.vertices != bs->sc.mesh.n_vertices) {
        snprintf(msg, sizeof msg, "%s: the cloth has %d host vertices, the scene %d", s->name, run.vertices,
                 bs->sc.mesh.n_vertices);
        bench_run_free(&run);
        cli_error(msg);
        return -1;
    }
    const size_t n3 = 3 * (size_t)pm->n;
    r->xs = malloc(sizeof(float) * n3 * (size_t)o->frames);
    if (!r->xs) {
        bench_run_free(&run);
        cli_error("out of memory");
        return -1;
    }
    for (int f = 0; f < o->frames; ++f)   /* frames never reached (a non-finite stop) stay NaN */
        for (int p = 0; p < pm->n; ++p)
            for (int k = 0; k < 3; ++k)
                r->xs[n3 * (size_t)f + 3 * (size_t)p + (size_t)k] =
                    f < run.frames ? run.xs[3 * ((size_t)run.vertices * (size_t)f + (size_t)rep[p]) + (size_t)k] : NAN;
    s->n_rows++;
    r->role = role;
    r->steps = ro.def.substeps;
    r->ms = run.ms_median;
    r->cpu_ms = run.cpu_ms_median;
    r->it_solve = bench_run_iterations_per_solve(&run);
    if (run.failures > 0 || run.nonfinite)
        snprintf(r->notes, sizeof r->notes, "%d failed substeps%s", run.failures, run.nonfinite ? "; non-finite" : "");
    if (run.not_converged > 0)
        snprintf(r->notes + strlen(r->notes), sizeof r->notes - strlen(r->notes), "%s%d solves at the cap",
                 r->notes[0] ? "; " : "", run.not_converged);
    c->weft_threads = run.threads;
    if (!o->com->quiet) fprintf(stderr, "  %.4g ms/frame (CPU %.4g), %.1f it./solve\n", r->ms, r->cpu_ms, r->it_solve);
    bench_run_free(&run);
    return 0;
}

/* Each row's error against its simulator's reference (the last row of its simulator), and each
 * reference's motion from the rest positions (rest: n x 3). */
static void errors(matched_scene* s, int frames, int n, const float* rest) {
    for (int b = 0; b < 2; ++b) {
        const matched_row* ref = NULL;
        for (int k = 0; k < s->n_rows; ++k)
            if (s->rows[k].blender == b && s->rows[k].role == ROLE_REF) ref = &s->rows[k];
        s->diag[b] = ref ? bench_traj_diag(ref->xs, frames, n) : NAN;
        s->motion[b] = NAN;
        if (ref) {
            double sum = 0.0;
            for (int f = 0; f < frames; ++f) {
                double all, end;
                bench_traj_error(rest, ref->xs + 3 * (size_t)n * (size_t)f, 1, n, &all, &end);
                sum += all * all;
            }
            s->motion[b] = 100.0 * sqrt(sum / frames) / s->diag[b];
        }
        for (int k = 0; k < s->n_rows; ++k) {
            matched_row* r = &s->rows[k];
            if (r->blender != b) continue;
            r->err_all = r->err_end = NAN;
            if (!ref || !(s->diag[b] > 0)) continue;
            bench_traj_error(ref->xs, r->xs, frames, n, &r->err_all, &r->err_end);
            r->err_all *= 100.0 / s->diag[b];
            r->err_end *= 100.0 / s->diag[b];
        }
    }
}

static int run_scene(matched_ctx* c, const char* name, matched_scene* s) {
    const bench_matched_opts* o = c->o;
    bench_scene bs;
    char msg[1024];
    if (bench_scene_build(&bs, name, o->com->garment, 1.0, 1.0, msg, sizeof msg) != 0) {
        cli_error(msg);
        return CLI_EXIT_FAILURE;
    }
    snprintf(s->name, sizeof s->name, "%s", bs.name);
    c->solver = bs.sc.def.solver;
    c->tolerance = bs.sc.def.tolerance;
    c->max_iterations = bs.sc.def.max_iterations;
    bench_peer_mesh pm;
    if (bench_peers_mesh(&bs, &pm) != 0) {
        bench_scene_free(&bs);
        return CLI_EXIT_FAILURE;
    }
    s->particles = pm.n;
    int* rep = malloc(sizeof(int) * (size_t)(pm.n > 0 ? pm.n : 1));   /* a host vertex of each particle */
    int rc = rep ? 0 : -1;
    if (!rep) cli_error("out of memory");
    const int n_vertices = bs.sc.mesh.n_vertices;
    for (int v = n_vertices - 1; rc == 0 && v >= 0; --v) rep[pm.of_vertex[v]] = v;
    if (o->blender) {
        for (int q = 0; q < o->n_qualities && rc == 0; ++q) rc = blender_row(c, &bs, &pm, o->qualities[q], ROLE_RUN, s);
        if (rc == 0) rc = blender_row(c, &bs, &pm, o->ref_quality / 2, ROLE_CHECK, s);
        if (rc == 0) rc = blender_row(c, &bs, &pm, o->ref_quality, ROLE_REF, s);
    }
    for (int k = 0; k < N_SETTINGS && rc == 0; ++k)
        if (o->settings & (1u << k)) rc = weft_row(c, &bs, &pm, rep, &k_settings[k], 0, ROLE_RUN, s);
    if (rc == 0) rc = weft_row(c, &bs, &pm, rep, NULL, o->ref_substeps / 2, ROLE_CHECK, s);
    if (rc == 0) rc = weft_row(c, &bs, &pm, rep, NULL, o->ref_substeps, ROLE_REF, s);
    if (rc == 0) errors(s, o->frames, pm.n, pm.x);
    free(rep);
    bench_peer_mesh_free(&pm);
    bench_scene_free(&bs);
    return rc == 0 ? CLI_EXIT_OK : CLI_EXIT_FAILURE;
}

/* ---------- the verdict and the tables ---------- */

/* The goal of a scene: Weft >= this x faster than Blender at matched accuracy. */
static double goal_of(const char* scene) { return strncmp(scene, "sheet", 5) && strncmp(scene, "hang", 4) ? 3.0 : 10.0; }

/* A row's time for the verdict: its CPU time (wall time where that is not known). On a shared
 * machine the wall time of a one-thread run grows with the other processes' load; its CPU time
 * is what the run itself needed. */
static double verdict_ms(const matched_row* r) { return isfinite(r->cpu_ms) && r->cpu_ms > 0 ? r->cpu_ms : r->ms; }

/* The fastest Weft row (not the reference) whose error (all frames; end: the last frame's) is no
 * larger than Blender row b's, or NULL. */
static const matched_row* fastest_within(const matched_scene* s, const matched_row* b, int end) {
    const matched_row* best = NULL;
    for (int k = 0; k < s->n_rows; ++k) {
        const matched_row* r = &s->rows[k];
        const int within = end ? r->err_end <= b->err_end : r->err_all <= b->err_all;
        if (r->blender || r->role == ROLE_REF || !within || !(verdict_ms(r) > 0)) continue;
        if (!best || verdict_ms(r) < verdict_ms(best)) best = r;
    }
    return best;
}

static const matched_row* row_of(const matched_scene* s, int blender, int role) {
    for (int k = 0; k < s->n_rows; ++k)
        if (s->rows[k].blender == blender && s->rows[k].role == role) return &s->rows[k];
    return NULL;
}

static void print_header(FILE* out, const void* ctx) {
    const matched_ctx* c = ctx;
    const bench_matched_opts* o = c->o;
    char tol[96];
    fprintf(out, "## weft bench peers --matched\n\n");
    if (!o->blender)
        fprintf(out, "**No Blender here** (%s): Weft's rows only, no verdict.\n\n", o->missing ? o->missing : "");
    if (o->blender) {
        fputs("Blender at a quality beside the fastest Weft setting whose error (all frames) is no larger, "
                "per scene (goal: Weft >= 10 x faster on the sheets, >= 3 x on the garment, decided against "
                "Blender's defaults, quality 5; the other qualities for reference; the last two columns: the "
              "same choice by the last frame's error):\n\n"
                "| scene | Blender quality | Blender error % | Blender CPU ms/frame | fastest Weft within it | Weft "
                "error % | Weft CPU ms/frame | Blender / Weft (CPU) | (wall) | goal | met | by the end-only error: "
                "fastest Weft within it | its Blender / Weft (CPU) |\n"
                "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
              out);
        for (int i = 0; i < c->n_scenes; ++i) {
            const matched_scene* s = &c->scenes[i];
            for (int k = 0; k < s->n_rows; ++k) {
                const matched_row* b = &s->rows[k];
                if (!b->blender || b->role != ROLE_RUN) continue;
                const matched_row *w = fastest_within(s, b, 0), *we = fastest_within(s, b, 1);
                const double goal = goal_of(s->name);
                char end[160];
                if (we)
                    snprintf(end, sizeof end, "%s (%.3g %% against %.3g %%) | %.3g", we->setting, we->err_end, b->err_end,
                             verdict_ms(b) / verdict_ms(we));
                else snprintf(end, sizeof end, "none | -");
                if (!w) {
                    fprintf(out, "| %s | %d | %.3g | %.4g | none | - | - | - | - | >= %g x | not met | %s |\n", s->name,
                            b->steps, b->err_all, verdict_ms(b), goal, end);
                    continue;
                }
                const double ratio = verdict_ms(b) / verdict_ms(w);
                fprintf(out, "| %s | %d | %.3g | %.4g | %s | %.3g | %.4g | %.3g | %.3g | >= %g x | %s | %s |\n",
                        s->name, b->steps, b->err_all, verdict_ms(b), w->setting, w->err_all, verdict_ms(w), ratio,
                        b->ms / w->ms, goal, ratio >= goal ? "met" : "not met", end);
            }
        }
        fputc('\n', out);
    }
    fputs("How converged the references are (each reference's check against it, % of its diagonal, all "
          "frames / last frame), and how far each reference moves from the rest positions (RMS over all frames "
          "and particles, % of its diagonal: an error is small or large beside this):\n\n| scene | simulator | "
          "reference | check | error % all frames | error % end | reference's diagonal (m) | its motion % |\n"
          "|---|---|---|---|---|---|---|---|\n",
          out);
    for (int i = 0; i < c->n_scenes; ++i)
        for (int b = 1; b >= 0; --b) {
            const matched_scene* s = &c->scenes[i];
            const matched_row *ref = row_of(s, b, ROLE_REF), *chk = row_of(s, b, ROLE_CHECK);
            if (!ref || !chk) continue;
            fprintf(out, "| %s | %s | %s | %s | %.3g | %.3g | %.4g | %.3g |\n", s->name, b ? "Blender" : "Weft",
                    ref->setting, chk->setting, chk->err_all, chk->err_end, s->diag[b], s->motion[b]);
        }
    fputc('\n', out);
    if (o->blender)
        fprintf(out,
                "Blender %s's cloth (a Cloth modifier with its defaults but the quality, a fresh file, each frame one "
                "timed scene.frame_set; host_glue/blender/peer_cloth_bench.py; settings read back at the first "
                "quality: %s) and Weft (through the public API, the CPU) on the same meshes, the same pinned "
                "vertices (the sheets' held still, the garment's waist turned about y, speeding up evenly to a "
                "turn a second over 0.5 s: Blender's object keyed so, world-space positions compared), %d frames "
                "each, in one run. Threads: Weft %d (OpenMP), Blender %d (-t) with "
                "OMP_NUM_THREADS=%s as Blender saw it (Debian's Blender runs its OpenMP loops on every core "
                "otherwise).\n\n",
                c->version, c->settings, o->frames, c->weft_threads, c->blender_threads, c->blender_omp);
    else
        fprintf(out, "Weft (through the public API, the CPU), %d frames per run. Threads: Weft %d (OpenMP).\n\n",
                o->frames, c->weft_threads);
    fprintf(out,
            "- Error: each simulator against its OWN reference (Blender at quality %d; Weft at TR-BDF2, Newton 3, "
            "every solve to a relative residual of %g, line search the library's, %d substeps): the RMS over all "
            "frames and all particles of the distance to the reference at the same frame, in %% of the diagonal "
            "of the bounding box of the reference's whole trajectory (every frame's positions); `end`: the same "
            "at the last frame alone. The two references differ (the material models do): the errors measure "
            "each solver's time-stepping error, not agreement between the two.\n"
            "- Weft's settings: `defaults` is the scene's def as the library leaves it (weft_default_cloth_def(), "
            "%s, relative tolerance %s, at most %d iterations; sleeping off) at %g frames per second; the "
            "others change the integrator, Newton iterations (line search off for Newton 1), substeps and, where "
            "their names say so, the tolerance and the first Newton solve's forcing only.\n"
            "- ms/frame: the median over the frames of one frame's time (Weft: weft_cloth_step; Blender: one "
            "scene.frame_set): `CPU` the process's CPU time over the call (CLOCK_PROCESS_CPUTIME_ID; Blender: "
            "time.process_time), `wall` its wall time. The verdict uses the CPU times: with one thread each they "
            "are what an idle machine's wall times would be, while the wall times on a shared machine grow with "
            "the other processes' load; its `(wall)` column is the ratio of the wall-time medians. Blender / "
            "Weft: the ratio of the medians (> 1: Weft is faster).\n\n",
            o->ref_quality, REF_TOLERANCE, o->ref_substeps, cli_solver_name(c->solver),
            cli_tolerance_text(c->tolerance, tol, sizeof tol),
            c->max_iterations, o->fps);
}

enum { C_SCENE, C_PARTICLES, C_FRAMES, C_SIM, C_SETTING, C_ROLE, C_STEPS, C_THREADS, C_CPU_MS, C_MS, C_ERR_ALL,
       C_ERR_END, C_ITER, C_NOTES, N_COLS };
static const char* const csv_cols[N_COLS] = {"scene", "particles", "frames", "simulator", "setting", "role",
                                             "steps_per_frame", "threads", "cpu_ms_per_frame", "ms_per_frame",
                                             "error_pct_all_frames",
                                             "error_pct_end", "iterations_per_solve", "notes"};
static const char* const md_cols[N_COLS] = {"scene", "particles", NULL, "simulator", "setting", "role",
                                            "quality / substeps", NULL, "CPU ms/frame", "wall ms/frame",
                                            "error % (all frames)",
                                            "error % (end)", "it./solve", "notes"};

static int add_rows(bench_table* t, const matched_ctx* c, const matched_scene* s) {
    for (int k = 0; k < s->n_rows; ++k) {
        const matched_row* r = &s->rows[k];
        char b[N_COLS][96];
        const char* cell[N_COLS];
        snprintf(b[C_SCENE], 96, "%s", s->name);
        snprintf(b[C_PARTICLES], 96, "%d", s->particles);
        snprintf(b[C_FRAMES], 96, "%d", c->o->frames);
        snprintf(b[C_SIM], 96, "%s", r->blender ? "Blender" : "Weft");
        snprintf(b[C_SETTING], 96, "%s", r->setting);
        snprintf(b[C_ROLE], 96, "%s", k_roles[r->role]);
        snprintf(b[C_STEPS], 96, "%d", r->steps);
        snprintf(b[C_THREADS], 96, "%d", r->blender ? c->blender_threads : c->weft_threads);
        bench_fmt(b[C_MS], 96, "%.4g", r->ms);
        bench_fmt(b[C_CPU_MS], 96, "%.4g", r->cpu_ms);
        bench_fmt(b[C_ERR_ALL], 96, "%.3g", r->err_all);
        bench_fmt(b[C_ERR_END], 96, "%.3g", r->err_end);
        if (r->blender) snprintf(b[C_ITER], 96, "-");
        else bench_fmt(b[C_ITER], 96, "%.1f", r->it_solve);
        snprintf(b[C_NOTES], 96, "%s", r->notes);
        for (int i = 0; i < N_COLS; ++i) cell[i] = b[i];
        if (bench_table_add(t, cell) != 0) return -1;
    }
    return 0;
}

int bench_peers_matched(const bench_matched_opts* o) {
    matched_ctx c;
    memset(&c, 0, sizeof c);
    c.o = o;
    c.weft_threads = o->com->threads;
    c.scenes = calloc((size_t)(o->n_scenes > 0 ? o->n_scenes : 1), sizeof *c.scenes);
    if (!c.scenes) {
        cli_error("out of memory");
        return CLI_EXIT_FAILURE;
    }
    const int cpu = BENCH_CPU;
    int rc = bench_open_backends(&cpu, 1, o->com->threads);
    for (int i = 0; i < o->n_scenes && rc == CLI_EXIT_OK; ++i) {
        rc = run_scene(&c, o->scenes[i], &c.scenes[i]);
        c.n_scenes = i + 1;
    }
    bench_table t;
    bench_table_init(&t, N_COLS, csv_cols, md_cols);
    for (int i = 0; i < c.n_scenes && rc == CLI_EXIT_OK; ++i)
        if (add_rows(&t, &c, &c.scenes[i]) != 0) {
            cli_error("out of memory");
            rc = CLI_EXIT_FAILURE;
        }
    if (rc == CLI_EXIT_OK) rc = bench_write_tables(o->com, &t, print_header, &c);
    bench_table_free(&t);
    for (int i = 0; i < c.n_scenes; ++i) rows_free(&c.scenes[i]);
    free(c.scenes);
    return rc;
}
