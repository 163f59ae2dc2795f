/* `weft bench stability`: a grid over step length x stiffness x mass x solver x method
 * (preconditioner for PCG, integrator, Newton iterations: bench_method.c). Each cell simulates
 * one scene (default: a 32 x 32 sheet hanging from two corners) for a fixed time at one substep
 * per frame and is judged: failed (a non-finite value, strain above --fail-strain, energy growth
 * above --fail-energy, or a substep that failed every retry), recovered (it needed rollbacks) or
 * survived. --backend cpu,gpu runs the grid on each backend (the direct solver on the CPU only).
 * Every cell steps the library through the public API (weft_cloth_step; the energy from
 * weft_cloth_get_energy). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_commands.h"
#include "bench_method.h"
#include "bench_plot.h"
#include "bench_run.h"
#include "bench_table.h"
#include "cli.h"
#include "names.h"

#ifndef WEFT_SAMPLE_SCENES
#define WEFT_SAMPLE_SCENES "sample_scenes"   /* for the usage text; the default is set in cmd_bench.c */
#endif

typedef struct stab_args {
    const char* scene;
    weft_solver solvers[BENCH_MAX_LIST];
    int n_solvers;
    double steps[BENCH_MAX_LIST];
    int n_steps;
    double stiffness[BENCH_MAX_LIST];
    int n_stiffness;
    double mass[BENCH_MAX_LIST];
    int n_mass;
    double seconds;
    double fail_strain, fail_energy;
    int backends[BENCH_MAX_BACKENDS];
    int n_backends;
    bench_methods meth;
    bench_common com;
} stab_args;

void bench_stability_usage(FILE* out) {
    fputs("usage: weft bench stability [--quick] [--scene NAME] [--solvers LIST] [--steps LIST]\n"
          "                            [--stiffness LIST] [--mass LIST] [--seconds T]\n"
          "                            [--fail-strain S] [--fail-energy E] [--preconds LIST]\n"
          "                            [--integrators LIST] [--newton LIST] [--line-search MODE]\n"
          "                            [--newton-forcing LIST] [--threads N]\n"
          "                            [--garment FILE] [--csv FILE] [--md FILE] [--plot FILE.png]\n"
          "                            [--backend LIST] [--quiet]\n"
          "\n"
          "Numerical stability over a grid of step length x stiffness x mass x solver x method\n"
          "(preconditioner for PCG, integrator, Newton iterations), on the CPU and/or the GPU\n"
          "(--backend; the GPU: block Jacobi, backward Euler, one Newton iteration only).\n"
          "Each cell simulates the scene for --seconds, one substep per frame of the given step\n"
          "length (the step's own rollback and retry on), and is judged:\n"
          "  failed     a non-finite position or energy, a stretch strain above --fail-strain, the\n"
          "             total energy (kinetic + spring + gravity) above its start by more than\n"
          "             --fail-energy x M |g| D (M the cloth's mass, D its bounding-box diagonal), or\n"
          "             a substep that failed every retry; the run stops there\n"
          "  recovered  none of that, but substeps were rolled back and retried\n"
          "  survived   no rollback\n"
          "\n"
          "options (lists are comma-separated; a step may be written as a fraction, 1/240):\n"
          "  --quick              seconds-long preset: sheet12, steps 1/60,1/30,1/12, stiffness\n"
          "                       1,100,10000, mass 0.1,10, 0.25 s, 1 thread (later options still\n"
          "                       apply)\n"
          "  --scene NAME         sheetN, hangN, drape, drapeN or garment as in `weft bench\n"
          "                       accuracy` (default sheet32)\n"
          "  --solvers LIST       pcg, jacobi, chebyshev, direct or all (default all)\n"
          "  --steps LIST         step lengths in seconds (default 1/240,1/120,1/60,1/30,1/12)\n"
          "  --stiffness LIST     factors on every spring stiffness (default 1,10,100,1000,10000)\n"
          "  --mass LIST          factors on the density (default 0.1,1,10)\n"
          "  --seconds T          simulated time per cell (default 1)\n"
          "  --fail-strain S      strain that fails a cell (default 0.5)\n"
          "  --fail-energy E      energy growth that fails a cell, relative to M |g| D (default 0.1)\n"
          BENCH_METHOD_HELP("block_jacobi,amg")
          "  --threads N          OpenMP threads (default 0: OpenMP's default)\n"
          "  --garment FILE       the garment mesh (default " WEFT_SAMPLE_SCENES "/skirt.obj)\n"
          "  --csv FILE           write every cell as CSV\n"
          "  --md FILE            write the Markdown tables to FILE instead of stdout\n"
          "  --plot FILE.png      heat map: a panel per solver and method, step length across, stiffness and\n"
          "                       mass down\n"
          BENCH_BACKEND_HELP
          "                       The direct solver does not exist on the GPU: it has no GPU cells.\n"
          "                       The plot has a panel per backend and solver.\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static void defaults(void* args, int quick) {
    stab_args* a = args;
    memset(a, 0, sizeof *a);
    a->scene = quick ? "sheet12" : "sheet32";
    a->n_solvers = bench_parse_solvers("all", a->solvers);
    a->n_steps = bench_parse_doubles(quick ? "1/60,1/30,1/12" : "1/240,1/120,1/60,1/30,1/12", 1e-6, 1, a->steps);
    a->n_stiffness = bench_parse_doubles(quick ? "1,100,10000" : "1,10,100,1000,10000", 1e-6, 1e9, a->stiffness);
    a->n_mass = bench_parse_doubles(quick ? "0.1,10" : "0.1,1,10", 1e-6, 1e6, a->mass);
    a->seconds = quick ? 0.25 : 1.0;
    a->fail_strain = 0.5;
    a->fail_energy = 0.1;
    a->backends[0] = BENCH_CPU;
    a->n_backends = 1;
    bench_methods_default(&a->meth, "block_jacobi,amg");
}

/* This command's own options (bench_option_fn). */
static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    stab_args* a = args;
    int m = 0;
#define OPT(name) ((m = cli_option_value(argc, argv, i, name, v)) != 0)
#define BAD(cond) (m < 0 ? m : (cond) ? -2 : 1) /* m < 0: the value is missing */
    if (OPT("--scene")) {
        if (m > 0) a->scene = *v;
        return m;
    }
    if (OPT("--solvers")) return BAD((a->n_solvers = bench_parse_solvers(*v, a->solvers)) < 0);
    if (OPT("--steps")) return BAD((a->n_steps = bench_parse_doubles(*v, 1e-6, 1, a->steps)) < 0);
    if (OPT("--stiffness")) return BAD((a->n_stiffness = bench_parse_doubles(*v, 1e-6, 1e9, a->stiffness)) < 0);
    if (OPT("--mass")) return BAD((a->n_mass = bench_parse_doubles(*v, 1e-6, 1e6, a->mass)) < 0);
    if (OPT("--seconds"))
        return BAD(cli_parse_double(*v, &a->seconds) != 0 || !(a->seconds > 0 && a->seconds <= 3600));
    if (OPT("--fail-strain")) return BAD(cli_parse_double(*v, &a->fail_strain) != 0 || !(a->fail_strain > 0));
    if (OPT("--fail-energy")) return BAD(cli_parse_double(*v, &a->fail_energy) != 0 || !(a->fail_energy > 0));
    if (OPT("--backend")) return BAD((a->n_backends = bench_parse_backends(*v, a->backends)) < 0);
#undef OPT
#undef BAD
    return bench_methods_option(&a->meth, argc, argv, i, v);
}

enum {
    C_BACKEND, C_SCENE, C_PARTICLES, C_SOLVER, C_STEP, C_STIFFNESS, C_MASS, C_OUTCOME, C_REASON, C_FRAMES,
    C_FRAMES_ASKED, C_ROLLBACKS, C_HALVINGS, C_FALLBACKS, C_FAILURES, C_STRAIN, C_ENERGY, C_ITER, C_MS, C_PRECOND,
    C_INTEGRATOR, C_NEWTON, C_LINE_SEARCH, C_ITER_SOLVE, N_COLS
};
static const char* const csv_cols[N_COLS] = {
    "backend", "scene", "particles", "solver", "step_s", "stiffness_x", "mass_x", "outcome", "reason",
    "frames", "frames_asked", "rollbacks", "halvings", "direct_fallbacks", "failures", "max_strain",
    "energy_growth", "iterations_per_substep", "ms_per_frame", "preconditioner", "integrator", "newton_iterations",
    "line_search", "iterations_per_solve"};
static const char* const md_cols[N_COLS] = {
    NULL, NULL, NULL, "solver", "step (s)", "stiffness x", "mass x", "outcome", "why", "frames", NULL,
    "rollbacks", NULL, "direct fallbacks", NULL, "max strain", "energy growth", NULL, "ms/frame", "precond.",
    "integrator", "Newton", NULL, "it./solve"};
static const char* const outcome_name[3] = {"survived", "recovered", "failed"};

/* "1/240" when 1/step is (nearly) a whole number, else "%.4g". */
static void step_label(double step, char* buf, size_t size) {
    double inv = 1.0 / step;
    if (fabs(inv - round(inv)) < 1e-6 * inv) snprintf(buf, size, "1/%.0f", round(inv));
    else snprintf(buf, size, "%.4g", step);
}

/* Judge a run: outcome and a short reason. */
static int judge(const stab_args* a, const bench_run* r, char* why, size_t size) {
    const double growth = (r->energy_max - r->energy0) / r->energy_scale;
    if (r->nonfinite) snprintf(why, size, "non-finite");
    else if (r->max_strain > a->fail_strain) snprintf(why, size, "strain %.2g", r->max_strain);
    else if (growth > a->fail_energy) snprintf(why, size, "energy +%.2g", growth);
    else if (r->failures > 0) snprintf(why, size, "step failed");
    else {
        snprintf(why, size, "%s", r->rollbacks > 0 ? "rollbacks" : "");
        return r->rollbacks > 0 ? BENCH_RECOVERED : BENCH_SURVIVED;
    }
    return BENCH_FAILED;
}

/* One word for a failed cell of the heat map. */
static const char* short_reason(const bench_run* r, const char* why) {
    if (r->nonfinite) return "NaN";
    if (!strncmp(why, "strain", 6)) return "strain";
    if (!strncmp(why, "energy", 6)) return "energy";
    return "step";
}

#define MAX_PANELS 64

/* The grid's panels: every backend x solver x method but what the GPU lacks (the direct solver,
 * the AMG preconditioner, BDF2, Newton iterations). */
typedef struct panels {
    int n;
    int backend[MAX_PANELS];
    weft_solver solver[MAX_PANELS];
    bench_method method[MAX_PANELS];
    char name[MAX_PANELS][64];
    char method_name[MAX_PANELS][48];  /* bench_method_short, "-" when empty */
    int skipped_direct;     /* 1: the GPU's direct solver was left out */
} panels;

static void panels_make(const stab_args* a, panels* p) {
    memset(p, 0, sizeof *p);
    bench_method meth[MAX_PANELS];
    for (int b = 0; b < a->n_backends; ++b)
        for (int s = 0; s < a->n_solvers; ++s) {
            if (a->backends[b] == BENCH_GPU && a->solvers[s] == WEFT_SOLVER_DIRECT) {
                p->skipped_direct = 1;
                continue;
            }
            const int n_meth = bench_methods_expand(&a->meth, a->solvers[s], meth, MAX_PANELS);
            for (int k = 0; k < n_meth && p->n < MAX_PANELS; ++k) {
                const bench_method* m = &meth[k];
                if (a->backends[b] == BENCH_GPU && !bench_method_on_gpu(m)) continue;
                p->backend[p->n] = a->backends[b];
                p->solver[p->n] = a->solvers[s];
                p->method[p->n] = *m;
                char* mn = p->method_name[p->n];
                bench_method_short(a->solvers[s], m, mn, sizeof p->method_name[p->n]);
                if (!mn[0]) snprintf(mn, sizeof p->method_name[p->n], "-");
                const char* sep = strcmp(mn, "-") ? " " : "";
                const char* shown = strcmp(mn, "-") ? mn : "";
                if (a->n_backends > 1)
                    snprintf(p->name[p->n], sizeof p->name[p->n], "%s%s%s (%s)", cli_solver_name(a->solvers[s]), sep,
                             shown, bench_backend_name(a->backends[b]));
                else
                    snprintf(p->name[p->n], sizeof p->name[p->n], "%s%s%s", cli_solver_name(a->solvers[s]), sep, shown);
                ++p->n;
            }
        }
}

typedef struct header_info {
    const stab_args* a;
    const panels* pn;
    const int* outcome;
    int per_solver, particles, threads;
} header_info;

/* What was run and how it is judged, then the counts per solver and outcome. */
static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    const stab_args* a = h->a;
    const int* outcome = h->outcome;
    const int per_solver = h->per_solver;
    const panels* pn = h->pn;
    char note[1024], blas[64];
    fprintf(out, "## weft bench stability\n\n%s. %d OpenMP thread(s), %s. Scene %s (%d particles), %g s "
                 "simulated per cell at one substep per frame; failed: non-finite, strain > %g, energy "
                 "growth > %g x M |g| D, or a substep that failed every retry; recovered: rollbacks.%s\n\n",
            bench_backend_note(a->backends, a->n_backends, note, sizeof note), h->threads,
            bench_blas_note(&a->com, blas, sizeof blas), a->scene, h->particles,
            a->seconds, a->fail_strain, a->fail_energy,
            pn->skipped_direct ? " The direct solver does not exist on the GPU: it has no GPU cells." : "");
    const int two = a->n_backends > 1;
    fputs(two ? "| backend | solver | method | survived | recovered | failed |\n|---|---|---|---|---|---|\n"
              : "| solver | method | survived | recovered | failed |\n|---|---|---|---|---|\n",
          out);
    for (int s = 0; s < pn->n; ++s) {
        int count[3] = {0, 0, 0};
        for (int k = 0; k < per_solver; ++k) ++count[outcome[s * per_solver + k]];
        if (two) fprintf(out, "| %s ", bench_backend_name(pn->backend[s]));
        fprintf(out, "| %s | %s | %d | %d | %d |\n", cli_solver_name(pn->solver[s]), pn->method_name[s], count[0],
                count[1], count[2]);
    }
    fputc('\n', out);
}

int bench_stability_run(int argc, char** argv) {
    stab_args a;
    int rc = bench_parse_args(argc, argv, "weft bench stability", bench_stability_usage, defaults, own_option, &a,
                              &a.com);
    if (rc >= 0) return rc;
    static panels pn;
    panels_make(&a, &pn);
    const int n_rows = a.n_stiffness * a.n_mass, per_solver = n_rows * a.n_steps;
    const int n_cells = pn.n * per_solver;
    int* outcome = calloc((size_t)n_cells + 1, sizeof(int));
    char(*text)[16] = calloc((size_t)n_cells + 1, sizeof *text);
    const char** text_ptr = calloc((size_t)n_cells + 1, sizeof(char*));
    bench_table t;
    const char* md[N_COLS];
    memcpy(md, md_cols, sizeof md);
    if (a.n_backends > 1) md[C_BACKEND] = "backend";
    bench_table_init(&t, N_COLS, csv_cols, md);
    rc = CLI_EXIT_OK;
    if (!outcome || !text || !text_ptr) {
        cli_error("out of memory");
        rc = CLI_EXIT_FAILURE;
    }
    if (rc == CLI_EXIT_OK && n_cells == 0)
        rc = cli_usage_error("weft bench stability", bench_stability_usage,
                             "--backend gpu --solvers direct: the direct solver does not exist on the GPU");
    if (rc == CLI_EXIT_OK) rc = bench_open_backends(a.backends, a.n_backends, a.com.threads);
    int particles = 0, threads = 1, done = 0;
    char msg[1024];
    for (int ki = 0; ki < a.n_stiffness && rc == CLI_EXIT_OK; ++ki)
        for (int mi = 0; mi < a.n_mass && rc == CLI_EXIT_OK; ++mi) {
            bench_scene bs;
            if (bench_scene_build(&bs, a.scene, a.com.garment, a.stiffness[ki], a.mass[mi], msg, sizeof msg) != 0) {
                cli_error(msg);
                rc = CLI_EXIT_FAILURE;
                break;
            }
            const int row = ki * a.n_mass + mi;
            for (int s = 0; s < pn.n && rc == CLI_EXIT_OK; ++s)
                for (int c = 0; c < a.n_steps; ++c) {
                    bench_run_opts o;
                    memset(&o, 0, sizeof o);
                    o.backend = pn.backend[s];
                    o.def = bench_run_def(&bs);
                    o.def.solver = pn.solver[s];
                    o.def.substeps = 1;
                    bench_method_apply(&pn.method[s], &o.def);
                    o.fps = 1.0 / a.steps[c];
                    o.frames = (int)ceil(a.seconds / a.steps[c] - 1e-9);
                    o.fail_strain = a.fail_strain;
                    o.fail_energy = a.fail_energy;
                    bench_run r;
                    if (bench_run_scene(&bs, &o, &r, msg, sizeof msg) != 0) {
                        cli_error(msg);
                        rc = CLI_EXIT_FAILURE;
                        break;
                    }
                    threads = r.threads;
                    particles = r.particles;
                    char why[48], step[24], b[N_COLS][48];
                    const int out = judge(&a, &r, why, sizeof why);
                    const int idx = (s * n_rows + row) * a.n_steps + c;
                    outcome[idx] = out;
                    if (out == BENCH_RECOVERED) snprintf(text[idx], sizeof text[idx], "%d", r.rollbacks);
                    else if (out == BENCH_FAILED) snprintf(text[idx], sizeof text[idx], "%s", short_reason(&r, why));
                    step_label(a.steps[c], step, sizeof step);
                    snprintf(b[C_BACKEND], 48, "%s", bench_backend_name(pn.backend[s]));
                    snprintf(b[C_SCENE], 48, "%s", bs.name);
                    snprintf(b[C_PARTICLES], 48, "%d", particles);
                    snprintf(b[C_SOLVER], 48, "%s", cli_solver_name(pn.solver[s]));
                    snprintf(b[C_STEP], 48, "%s", step);
                    snprintf(b[C_STIFFNESS], 48, "%g", a.stiffness[ki]);
                    snprintf(b[C_MASS], 48, "%g", a.mass[mi]);
                    snprintf(b[C_OUTCOME], 48, "%s", outcome_name[out]);
                    snprintf(b[C_REASON], 48, "%s", why);
                    snprintf(b[C_FRAMES], 48, "%d", r.frames);
                    snprintf(b[C_FRAMES_ASKED], 48, "%d", o.frames);
                    snprintf(b[C_ROLLBACKS], 48, "%d", r.rollbacks);
                    snprintf(b[C_HALVINGS], 48, "%d", r.halvings);
                    snprintf(b[C_FALLBACKS], 48, "%d", r.direct_fallbacks);
                    snprintf(b[C_FAILURES], 48, "%d", r.failures);
                    bench_fmt(b[C_STRAIN], 48, "%.3g", r.max_strain);
                    bench_fmt(b[C_ENERGY], 48, "%.3g", (r.energy_max - r.energy0) / r.energy_scale);
                    bench_fmt(b[C_ITER], 48, "%.1f", r.iterations);
                    bench_fmt(b[C_MS], 48, "%.2f", r.ms_median);
                    snprintf(b[C_PRECOND], 48, "%s", bench_precond_label(pn.solver[s], &pn.method[s]));
                    snprintf(b[C_INTEGRATOR], 48, "%s", cli_integrator_name(pn.method[s].integrator));
                    snprintf(b[C_NEWTON], 48, "%d", pn.method[s].newton);
                    snprintf(b[C_LINE_SEARCH], 48, "%s", pn.method[s].line_search ? "on" : "off");
                    bench_fmt(b[C_ITER_SOLVE], 48, "%.1f", bench_run_iterations_per_solve(&r));
                    const char* cell[N_COLS];
                    for (int k = 0; k < N_COLS; ++k) cell[k] = b[k];
                    if (bench_table_add(&t, cell) != 0) rc = CLI_EXIT_FAILURE;
                    ++done;
                    if (!a.com.quiet)
                        fprintf(stderr, "[%d/%d] %s step %s k x%g m x%g: %s %s\n", done, n_cells, pn.name[s], step, a.stiffness[ki], a.mass[mi], outcome_name[out], why);
                    bench_run_free(&r);
                }
            bench_scene_free(&bs);
        }
    if (rc == CLI_EXIT_OK) {
        const header_info h = {&a, &pn, outcome, per_solver, particles, threads};
        rc = bench_write_tables(&a.com, &t, print_header, &h);
    }
    if (rc == CLI_EXIT_OK && a.com.plot) {
        /* rows top to bottom in the order of the table: row r is drawn at n_rows - 1 - r */
        const char** names = calloc((size_t)pn.n, sizeof(char*));
        char(*cols)[24] = calloc((size_t)a.n_steps, sizeof *cols);
        char(*rows)[40] = calloc((size_t)n_rows, sizeof *rows);
        const char** col_ptr = calloc((size_t)a.n_steps, sizeof(char*));
        const char** row_ptr = calloc((size_t)n_rows, sizeof(char*));
        int* flipped = calloc((size_t)n_cells, sizeof(int));
        char msg[256] = "out of memory";
        if (!names || !cols || !rows || !col_ptr || !row_ptr || !flipped) rc = CLI_EXIT_FAILURE;
        if (rc == CLI_EXIT_OK) {
            for (int s = 0; s < pn.n; ++s) names[s] = pn.name[s];
            for (int c = 0; c < a.n_steps; ++c) {
                step_label(a.steps[c], cols[c], sizeof cols[c]);
                col_ptr[c] = cols[c];
            }
            for (int r = 0; r < n_rows; ++r) {
                const int pr = n_rows - 1 - r;
                snprintf(rows[pr], sizeof rows[pr], "k x%g, mass x%g", a.stiffness[r / a.n_mass], a.mass[r % a.n_mass]);
                row_ptr[pr] = rows[pr];
                for (int s = 0; s < pn.n; ++s)
                    for (int c = 0; c < a.n_steps; ++c) {
                        const int from = (s * n_rows + r) * a.n_steps + c, to = (s * n_rows + pr) * a.n_steps + c;
                        flipped[to] = outcome[from];
                        text_ptr[to] = text[from];
                    }
            }
            char title[160];
            snprintf(title, sizeof title, "%s, %g s per cell, one substep per frame", a.scene,
                     a.seconds);
            if (bench_plot_heatmap(a.com.plot, names, pn.n, col_ptr, a.n_steps, row_ptr, n_rows, flipped,
                                   text_ptr, title, msg, sizeof msg) != 0)
                rc = CLI_EXIT_FAILURE;
        }
        if (rc != CLI_EXIT_OK) cli_error(msg);
        free(names);
        free(cols);
        free(rows);
        free(col_ptr);
        free(row_ptr);
        free(flipped);
    }
    free(outcome);
    free(text);
    free(text_ptr);
    bench_table_free(&t);
    return rc;
}
