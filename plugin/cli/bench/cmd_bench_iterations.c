/* `weft bench iterations`: how many solver iterations a linear solve takes, by resolution and by
 * stiffness. The hanging sheets of --sizes (default stiffness), one sheet (--stiffness-size) with
 * every spring stiffness times each --stiffness factor, and the --scenes (drape, garment), at one
 * substep per frame, through the public API (weft_cloth_step on a CPU context), for each solver x
 * preconditioner (PCG) x integrator x Newton iterations: PCG
 * iterations per solve (mean, largest), the fraction of solves that converged, the
 * preconditioner's setup and the solve stage's time per solve. Then the goals,
 * met or not per method: every row's mean at most --goal-mean iterations with every solve
 * converged, and the mean growing at most --goal-growth x from the smallest sheet to the largest
 * and from the smallest stiffness factor to the largest. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_args.h"
#include "bench_backend.h"
#include "bench_commands.h"
#include "bench_method.h"
#include "bench_run.h"
#include "bench_table.h"
#include "cli.h"
#include "names.h"

#ifndef WEFT_SAMPLE_SCENES
#define WEFT_SAMPLE_SCENES "sample_scenes"   /* for the usage text; the default is set in cmd_bench.c */
#endif

#define MAX_SCENES 16
#define MAX_METHODS (BENCH_MAX_LIST * 4)   /* solver x method combinations kept for the goals */

typedef struct it_args {
    int sizes[BENCH_MAX_LIST];
    int n_sizes;
    double stiffness[BENCH_MAX_LIST];
    int n_stiffness;
    int stiffness_size;
    const char* scenes[MAX_SCENES];
    int n_scenes;
    char scene_buf[512];
    weft_solver solvers[BENCH_MAX_LIST];
    int n_solvers;
    bench_methods meth;
    double tolerance;
    int cap;
    double seconds, fps;
    double goal_mean, goal_growth;
    bench_common com;
} it_args;

void bench_iterations_usage(FILE* out) {
    fputs("usage: weft bench iterations [--quick] [--sizes LIST] [--stiffness LIST] [--stiffness-size N]\n"
          "                             [--scenes LIST] [--solvers LIST] [--preconds LIST]\n"
          "                             [--integrators LIST] [--newton LIST] [--line-search MODE]\n"
          "                             [--newton-forcing LIST]\n"
          "                             [--tolerance T] [--iterations N] [--seconds T] [--fps F]\n"
          "                             [--goal-mean N] [--goal-growth G] [--threads N]\n"
          "                             [--garment FILE] [--csv FILE] [--md FILE] [--quiet]\n"
          "\n"
          "Solver iterations per linear solve, by resolution and stiffness (CPU). Rows, each at one\n"
          "substep per frame (1/--fps s) for --seconds, stepped through the public API\n"
          "(weft_cloth_step, its rollbacks on, as a user runs it):\n"
          "  size       sheetN for every N of --sizes (N x N particles, 1 m, hanging from two corners)\n"
          "  stiffness  the sheet of --stiffness-size with every spring stiffness times each factor\n"
          "  scene      each of --scenes (drape: a 64 x 64 sheet falling onto a sphere; garment: the\n"
          "             --garment mesh pinned at its twirling waist)\n"
          "for every solver x preconditioner (PCG only) x integrator x Newton iterations. Columns:\n"
          "  it./solve      iterations / solves (Newton iterations and friction passes are solves)\n"
          "  max it.        the largest in one solve\n"
          "  converged      the fraction of solves that reached the tolerance before the cap\n"
          "  setup ms       the preconditioner's setup time per solve\n"
          "  solve ms       the solve stage's time per solve (setup included)\n"
          "Goals, met or not per method: every row's mean <= --goal-mean with every solve\n"
          "converged; the mean grows <= --goal-growth x from the smallest to the largest sheet, and\n"
          "from the smallest to the largest stiffness factor.\n"
          "\n"
          "options (lists are comma-separated):\n"
          "  --quick              seconds-long preset: sizes 8,16, stiffness 1,100 on sheet12, scenes\n"
          "                       drape16,garment, 0.3 s, 1 thread (later options still apply)\n"
          "  --sizes LIST         sheet sizes N (default 32,64,128,256)\n"
          "  --stiffness LIST     stiffness factors (default 1,10,100,1000,10000)\n"
          "  --stiffness-size N   the sheet of the stiffness sweep (default 64)\n"
          "  --scenes LIST        further scenes (default drape,garment; none: --scenes none)\n"
          "  --solvers LIST       pcg, jacobi, chebyshev, direct or all (default pcg)\n",
          out);
    fputs(BENCH_METHOD_HELP("block_jacobi,amg")
          "  --tolerance T        relative residual to stop at (default 1e-4)\n"
          "  --iterations N       iteration cap (default 300)\n"
          "  --seconds T          simulated time per row (default 1.5)\n"
          "  --fps F              frames (= substeps) per second (default 30)\n"
          "  --goal-mean N        the goal on iterations per solve (default 30)\n"
          "  --goal-growth G      the goal on the growth over sizes and stiffnesses (default 2)\n"
          "  --threads N          OpenMP threads (default 0: OpenMP's default)\n"
          "  --garment FILE       the garment mesh (default " WEFT_SAMPLE_SCENES "/skirt.obj)\n"
          "  --csv FILE           write every row as CSV\n"
          "  --md FILE            write the Markdown tables to FILE instead of stdout\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static void set_scenes(it_args* a, const char* list) {
    a->n_scenes = !strcmp(list, "none") ? 0 : bench_split_names(list, a->scene_buf, sizeof a->scene_buf, a->scenes, MAX_SCENES);
}

static void defaults(void* args, int quick) {
    it_args* a = args;
    memset(a, 0, sizeof *a);
    a->n_sizes = bench_parse_ints(quick ? "8,16" : "32,64,128,256", 2, 2048, a->sizes);
    a->n_stiffness = bench_parse_doubles(quick ? "1,100" : "1,10,100,1000,10000", 1e-6, 1e9, a->stiffness);
    a->stiffness_size = quick ? 12 : 64;
    set_scenes(a, quick ? "drape16,garment" : "drape,garment");
    a->n_solvers = bench_parse_solvers("pcg", a->solvers);
    bench_methods_default(&a->meth, "block_jacobi,amg");
    a->tolerance = 1e-4;
    a->cap = 300;
    a->seconds = quick ? 0.3 : 1.5;
    a->fps = 30;
    a->goal_mean = 30;
    a->goal_growth = 2;
}

static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    it_args* a = args;
    int m = 0;
#define OPT(name) ((m = cli_option_value(argc, argv, i, name, v)) != 0)
#define BAD(cond) (m < 0 ? m : (cond) ? -2 : 1) /* m < 0: the value is missing */
    if (OPT("--sizes")) return BAD((a->n_sizes = bench_parse_ints(*v, 2, 2048, a->sizes)) < 0);
    if (OPT("--stiffness")) return BAD((a->n_stiffness = bench_parse_doubles(*v, 1e-6, 1e9, a->stiffness)) < 0);
    if (OPT("--stiffness-size")) return BAD(cli_parse_int(*v, 2, 2048, &a->stiffness_size) != 0);
    if (OPT("--scenes")) {
        if (m < 0) return m;
        set_scenes(a, *v);
        return BAD(a->n_scenes == 0 && strcmp(*v, "none") != 0);
    }
    if (OPT("--solvers")) return BAD((a->n_solvers = bench_parse_solvers(*v, a->solvers)) < 0);
    if (OPT("--tolerance"))
        return BAD(cli_parse_double(*v, &a->tolerance) != 0 || !(a->tolerance >= 0 && a->tolerance < 1));
    if (OPT("--iterations")) return BAD(cli_parse_int(*v, 1, 1000000, &a->cap) != 0);
    if (OPT("--seconds"))
        return BAD(cli_parse_double(*v, &a->seconds) != 0 || !(a->seconds > 0 && a->seconds <= 3600));
    if (OPT("--fps")) return BAD(cli_parse_double(*v, &a->fps) != 0 || !(a->fps >= 1 && a->fps <= 10000));
    if (OPT("--goal-mean")) return BAD(cli_parse_double(*v, &a->goal_mean) != 0 || !(a->goal_mean > 0));
    if (OPT("--goal-growth")) return BAD(cli_parse_double(*v, &a->goal_growth) != 0 || !(a->goal_growth > 0));
#undef OPT
#undef BAD
    return bench_methods_option(&a->meth, argc, argv, i, v);
}

enum {
    C_GROUP, C_SCENE, C_PARTICLES, C_STIFFNESS, C_SOLVER, C_PRECOND, C_INTEGRATOR, C_NEWTON, C_LINE_SEARCH,
    C_FRAMES, C_SUBSTEPS, C_SOLVES, C_ITER, C_MAXITER, C_CONVERGED, C_NOTCONV, C_SETUP_MS, C_SOLVE_MS, C_MS,
    C_ROLLBACKS, C_FAILURES, N_COLS
};
static const char* const csv_cols[N_COLS] = {
    "group", "scene", "particles", "stiffness_x", "solver", "preconditioner", "integrator", "newton_iterations",
    "line_search", "frames", "substeps", "solves", "iterations_per_solve", "max_iterations_used",
    "converged_fraction", "not_converged", "ms_precond_per_solve", "ms_solve_per_solve", "ms_per_frame",
    "rollbacks", "failures"};
static const char* const md_cols[N_COLS] = {
    "group", "scene", "particles", "stiffness x", "solver", "precond.", "integrator", "Newton", NULL, NULL, NULL,
    "solves", "it./solve", "max it.", "converged", NULL, "setup ms/solve", "solve ms/solve", "ms/frame",
    "rollbacks", NULL};

/* One row's job: which scene, at which stiffness, in which group. */
typedef struct job {
    const char* group;      /* "size", "stiffness", "scene" */
    char scene[32];
    double k;
} job;

/* One solver x method's goal figures. */
typedef struct method_goals {
    weft_solver solver;
    bench_method method;
    double worst_mean;      /* the largest it./solve over every row */
    char worst_row[48];
    double worst_converged; /* the smallest converged fraction */
    double size_first, size_last, k_first, k_last;   /* it./solve at the ends of the two sweeps */
} method_goals;

typedef struct header_info {
    const it_args* a;
    int threads;
    const method_goals* g;
    int n_g;
} header_info;

static const char* met(int ok) { return ok ? "met" : "not met"; }

static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    const it_args* a = h->a;
    char blas[64];
    fprintf(out, "## weft bench iterations\n\nbackend: CPU (weft_cloth_step). %d OpenMP thread(s), %s. One "
                 "substep per frame at %g fps, %g s per row, tolerance %g, cap %d; rollbacks on (a rolled-back "
                 "substep's halves are solves too).\n\n",
            h->threads, bench_blas_note(&a->com, blas, sizeof blas), a->fps, a->seconds, a->tolerance, a->cap);
    fprintf(out, "Goals: every row's mean <= %g iterations per solve with every solve converged; growth <= %g x "
                 "from sheet%d to sheet%d and from stiffness x%g to x%g (sheet%d).\n\n",
            a->goal_mean, a->goal_growth, a->sizes[0], a->sizes[a->n_sizes - 1], a->stiffness[0],
            a->stiffness[a->n_stiffness - 1], a->stiffness_size);
    fputs("| solver | precond. | integrator | Newton | worst mean it./solve (row) | least converged | mean <= goal "
          "| size growth | met | stiffness growth | met |\n|---|---|---|---|---|---|---|---|---|---|---|\n",
          out);
    for (int k = 0; k < h->n_g; ++k) {
        const method_goals* g = &h->g[k];
        const double gs = g->size_last / g->size_first, gk = g->k_last / g->k_first;
        fprintf(out, "| %s | %s | %s | %d%s | %.1f (%s) | %.3g | %s | %.2f | %s | %.2f | %s |\n",
                cli_solver_name(g->solver), bench_precond_label(g->solver, &g->method),
                cli_integrator_name(g->method.integrator), g->method.newton, g->method.line_search ? " (ls)" : "",
                g->worst_mean, g->worst_row, g->worst_converged,
                met(g->worst_mean <= a->goal_mean && g->worst_converged >= 1.0), gs,
                a->n_sizes > 1 ? met(gs <= a->goal_growth) : "-", gk,
                a->n_stiffness > 1 ? met(gk <= a->goal_growth) : "-");
    }
    fputs("\n- it./solve: iterations / solves over the run (Newton iterations and friction passes are solves); "
          "max it.: the largest in one solve; converged: the fraction of solves that reached the tolerance.\n"
          "- setup ms/solve: the preconditioner's setup per solve; solve ms/solve: the solve stage per solve "
          "(setup included); ms/frame: median wall time of a frame.\n\n",
          out);
}

/* The jobs: sizes, then the stiffness sweep, then the scenes. */
static int make_jobs(const it_args* a, job* out, int cap) {
    int n = 0;
    for (int k = 0; k < a->n_sizes && n < cap; ++k, ++n) {
        out[n].group = "size";
        snprintf(out[n].scene, sizeof out[n].scene, "sheet%d", a->sizes[k]);
        out[n].k = 1.0;
    }
    for (int k = 0; k < a->n_stiffness && n < cap; ++k, ++n) {
        out[n].group = "stiffness";
        snprintf(out[n].scene, sizeof out[n].scene, "sheet%d", a->stiffness_size);
        out[n].k = a->stiffness[k];
    }
    for (int k = 0; k < a->n_scenes && n < cap; ++k, ++n) {
        out[n].group = "scene";
        snprintf(out[n].scene, sizeof out[n].scene, "%s", a->scenes[k]);
        out[n].k = 1.0;
    }
    return n;
}

static int add_row(bench_table* t, const job* j, const bench_scene* bs, weft_solver solver,
                   const bench_method* m, const bench_run* r) {
    char b[N_COLS][48];
    const char* cell[N_COLS];
    snprintf(b[C_GROUP], 48, "%s", j->group);
    snprintf(b[C_SCENE], 48, "%s", bs->name);
    snprintf(b[C_PARTICLES], 48, "%d", r->particles);
    snprintf(b[C_STIFFNESS], 48, "%g", j->k);
    snprintf(b[C_SOLVER], 48, "%s", cli_solver_name(solver));
    snprintf(b[C_PRECOND], 48, "%s", bench_precond_label(solver, m));
    snprintf(b[C_INTEGRATOR], 48, "%s", cli_integrator_name(m->integrator));
    snprintf(b[C_NEWTON], 48, "%d", m->newton);
    snprintf(b[C_LINE_SEARCH], 48, "%s", m->line_search ? "on" : "off");
    snprintf(b[C_FRAMES], 48, "%d", r->frames);
    snprintf(b[C_SUBSTEPS], 48, "%lld", r->substeps);
    snprintf(b[C_SOLVES], 48, "%lld", r->solves);
    bench_fmt(b[C_ITER], 48, "%.1f", bench_run_iterations_per_solve(r));
    snprintf(b[C_MAXITER], 48, "%d", r->max_iterations);
    bench_fmt(b[C_CONVERGED], 48, "%.3g", bench_run_converged_fraction(r));
    snprintf(b[C_NOTCONV], 48, "%d", r->not_converged);
    bench_fmt(b[C_SETUP_MS], 48, "%.3g", bench_run_precond_ms_per_solve(r));
    bench_fmt(b[C_SOLVE_MS], 48, "%.3g", bench_run_solve_ms_per_solve(r));
    bench_fmt(b[C_MS], 48, "%.2f", r->ms_median);
    snprintf(b[C_ROLLBACKS], 48, "%d", r->rollbacks);
    snprintf(b[C_FAILURES], 48, "%d", r->failures);
    for (int k = 0; k < N_COLS; ++k) cell[k] = b[k];
    return bench_table_add(t, cell);
}

/* A row's figures into its method's goals. */
static void note_goals(method_goals* g, const it_args* a, const job* j, int job_index, int n_sizes, const bench_run* r) {
    const double mean = bench_run_iterations_per_solve(r), conv = bench_run_converged_fraction(r);
    if (!(mean <= g->worst_mean)) {
        g->worst_mean = mean;
        snprintf(g->worst_row, sizeof g->worst_row, "%s k x%g", j->scene, j->k);
    }
    if (!(conv >= g->worst_converged)) g->worst_converged = conv;
    if (!strcmp(j->group, "size")) {
        if (job_index == 0) g->size_first = mean;
        if (job_index == n_sizes - 1) g->size_last = mean;
    } else if (!strcmp(j->group, "stiffness")) {
        if (j->k == a->stiffness[0]) g->k_first = mean;
        if (j->k == a->stiffness[a->n_stiffness - 1]) g->k_last = mean;
    }
}

int bench_iterations_run(int argc, char** argv) {
    it_args a;
    int rc = bench_parse_args(argc, argv, "weft bench iterations", bench_iterations_usage, defaults, own_option, &a,
                              &a.com);
    if (rc >= 0) return rc;
    if (a.com.plot)
        return cli_usage_error("weft bench iterations", bench_iterations_usage, "--plot: this command draws no plot");
    job jobs[3 * BENCH_MAX_LIST];
    const int n_jobs = make_jobs(&a, jobs, (int)(sizeof jobs / sizeof jobs[0]));
    static method_goals goals[MAX_METHODS];
    int n_g = 0;
    for (int s = 0; s < a.n_solvers; ++s) {
        bench_method m[MAX_METHODS];
        const int n = bench_methods_expand(&a.meth, a.solvers[s], m, MAX_METHODS);
        for (int k = 0; k < n && n_g < MAX_METHODS; ++k, ++n_g) {
            memset(&goals[n_g], 0, sizeof goals[n_g]);
            goals[n_g].solver = a.solvers[s];
            goals[n_g].method = m[k];
            goals[n_g].worst_converged = 1.0;
        }
    }
    const int frames = (int)lround(a.seconds * a.fps) > 0 ? (int)lround(a.seconds * a.fps) : 1;
    bench_table t;
    bench_table_init(&t, N_COLS, csv_cols, md_cols);
    const int cpu = BENCH_CPU;
    rc = bench_open_backends(&cpu, 1, a.com.threads);
    int threads = 1;
    char msg[1024];
    for (int j = 0; j < n_jobs && rc == CLI_EXIT_OK; ++j) {
        bench_scene bs;
        if (bench_scene_build(&bs, jobs[j].scene, a.com.garment, jobs[j].k, 1.0, msg, sizeof msg) != 0) {
            cli_error(msg);
            rc = CLI_EXIT_FAILURE;
            break;
        }
        for (int g = 0; g < n_g && rc == CLI_EXIT_OK; ++g) {
            bench_run_opts o;
            memset(&o, 0, sizeof o);
            o.backend = BENCH_CPU;
            o.def = bench_run_def(&bs);
            o.def.solver = goals[g].solver;
            o.def.tolerance = a.tolerance;
            o.def.max_iterations = a.cap;
            o.def.substeps = 1;
            bench_method_apply(&goals[g].method, &o.def);
            o.fps = a.fps;
            o.frames = frames;
            bench_run r;
            if (bench_run_scene(&bs, &o, &r, msg, sizeof msg) != 0) {
                cli_error(msg);
                rc = CLI_EXIT_FAILURE;
                break;
            }
            if (!a.com.quiet) {
                char label[64];
                fprintf(stderr, "%s k x%g (%d particles) %s %s: %.1f it./solve (max %d), %.3g converged, "
                        "%.2f ms/frame\n", bs.name, jobs[j].k, r.particles, cli_solver_name(goals[g].solver),
                        bench_method_short(goals[g].solver, &goals[g].method, label, sizeof label),
                        bench_run_iterations_per_solve(&r), r.max_iterations, bench_run_converged_fraction(&r),
                        r.ms_median);
            }
            threads = r.threads;
            note_goals(&goals[g], &a, &jobs[j], j, a.n_sizes, &r);
            if (add_row(&t, &jobs[j], &bs, goals[g].solver, &goals[g].method, &r) != 0) {
                cli_error("out of memory");
                rc = CLI_EXIT_FAILURE;
            }
            bench_run_free(&r);
        }
        bench_scene_free(&bs);
    }
    if (rc == CLI_EXIT_OK) {
        const header_info h = {&a, threads, goals, n_g};
        rc = bench_write_tables(&a.com, &t, print_header, &h);
    }
    bench_table_free(&t);
    return rc;
}
