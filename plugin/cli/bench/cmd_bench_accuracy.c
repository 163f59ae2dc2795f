/* `weft bench accuracy`: run time against error, through the public API. For every scene, a
 * reference run (direct solver, --ref-substeps substeps per frame) and its check at twice the
 * substeps (is it converged in time?), then every configuration solver x preconditioner (PCG) x
 * integrator x Newton iterations x tolerance x iteration cap x substeps per frame (the direct
 * solver: no tolerance or cap), each simulated for --seconds. Errors: the trajectory error
 * against the reference at the end, the largest strain, the energy drift and the swing of the
 * centre of mass. Timing: median ms per weft_cloth_step call. --backend cpu,gpu runs every
 * configuration on each backend (the reference stays the CPU's direct solver; the GPU has no
 * direct solver). The linear-solve error against CHOLMOD on the step's own system, and the
 * scene's sensitivity to its start, need the solver's internals: tests/bench/bench_linear_error
 * and tests/bench/bench_sensitivity measure them. */
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

#define LARGE_SCENE 20000   /* particles above which --substeps-large applies */
#define MAX_SCENES 16

typedef struct acc_args {
    const char* scenes[MAX_SCENES];
    int n_scenes;
    char scene_buf[512];
    weft_solver solvers[BENCH_MAX_LIST];
    int n_solvers;
    double tolerances[BENCH_MAX_LIST];
    int n_tolerances;
    int caps[BENCH_MAX_LIST];
    int n_caps;
    int substeps[BENCH_MAX_LIST];
    int n_substeps;
    int substeps_large[BENCH_MAX_LIST];
    int n_substeps_large;
    int ref_substeps;
    int ref_check;          /* 1: the reference again at 2 x ref_substeps, their difference shown */
    int ref_halvings;       /* the check's ladder: ref_substeps x 2, 4, ... 2^ref_halvings (>= 1) */
    int ref_only;           /* 1: the reference and its ladder only, no configurations */
    weft_integrator ref_integrator;
    int undamped;           /* 1: no air drag and no spring damping, in every run (reference included) */
    int no_air;             /* 1: no air drag in every run (reference included) */
    int ref_newton;         /* the reference's Newton iterations (> 1: line search, tolerance 1e-10) */
    bench_methods meth;
    double seconds, fps;
    int backends[BENCH_MAX_BACKENDS];
    int n_backends;
    bench_common com;
} acc_args;

void bench_accuracy_usage(FILE* out) {
    fputs("usage: weft bench accuracy [--quick] [--scenes LIST] [--solvers LIST] [--tolerances LIST]\n"
          "                           [--iterations LIST] [--substeps LIST] [--substeps-large LIST]\n"
          "                           [--preconds LIST] [--integrators LIST] [--newton LIST]\n"
          "                           [--line-search MODE] [--newton-forcing LIST] [--ref-substeps N]\n"
          "                           [--ref-integrator NAME]\n"
          "                           [--ref-newton N] [--undamped] [--no-air]\n"
          "                           [--no-ref-check] [--ref-halvings N] [--ref-only]\n"
          "                           [--seconds T] [--fps F] [--probes N]\n"
          "                           [--threads N] [--garment FILE] [--csv FILE] [--md FILE]\n"
          "                           [--plot FILE.png] [--backend LIST] [--quiet]\n"
          "\n"
          "Run time against error, on the CPU and/or the GPU (--backend).\n"
          "For each scene a reference run (direct solver, --ref-integrator, --ref-newton Newton iterations,\n"
          "--ref-substeps substeps per frame) and the same at twice the substeps: their difference at the end (RMS and max,\n"
          "% of the bounding-box diagonal) shows whether the reference is converged in time (goal\n"
          "< 0.1 %, printed as met / not met; a `reference_check` row in the CSV). Then every\n"
          "configuration solver x preconditioner (PCG only) x integrator x Newton iterations x\n"
          "tolerance x iteration cap x substeps per frame (direct: no tolerance or cap), each\n"
          "simulated for --seconds at --fps. Per configuration:\n"
          "  ms/frame     median wall time of one frame's weft_cloth_step call\n"
          "  it./solve    solver iterations per linear solve, mean (iterations / solves: Newton\n"
          "               iterations and friction passes are solves); max it.: the largest\n"
          "  setup ms     the preconditioner's setup time per solve (part of the solve stage)\n"
          "  lin. err     not measured here (-): the solver's answer against CHOLMOD's on the\n"
          "               step's own system needs the solver's internals; tests/bench/\n"
          "               bench_linear_error measures it\n"
          "  traj. err    RMS and largest vertex distance to the reference run at the end,\n"
          "               divided by the cloth's bounding-box diagonal\n"
          "  max strain   largest stretch-spring strain (l - rest) / rest at the end of any frame\n"
          "  energy drift (E_end - E_start) / (M |g| D): E = kinetic + spring + gravity, M the\n"
          "               cloth's mass, D its diagonal (negative: dissipated)\n"
          "  c.o.m. err   largest distance between the run's and the reference's centres of mass\n"
          "               over every frame / the diagonal (the swing's phase and amplitude)\n"
          "  KE ratio     kinetic energy summed over the frames / the reference's (< 1: the swing\n"
          "               lost energy to numerical damping)\n"
          "\n",
          out);
    fputs(          "options (lists are comma-separated):\n"
          "  --quick              seconds-long preset: sheet16,drape16,garment, tolerance 1e-3,\n"
          "                       iterations 20,100, substeps 1,2, 0.3 s, 1 thread (later\n"
          "                       options still apply)\n"
          "  --scenes LIST        sheetN (N x N particles, 1 m, flat at first, hanging from two\n"
          "                       corners), hangN (the same sheet hanging upright from the start),\n"
          "                       drape (a 64 x 64 sheet falling onto a sphere) or drapeN, garment\n"
          "                       (the --garment mesh pinned at its waist, the waist twirling up to\n"
          "                       one turn a second); default sheet32,sheet64,sheet100,sheet256,\n"
          "                       drape,garment\n"
          "  --solvers LIST       pcg, jacobi, chebyshev, direct or all (default all)\n"
          "  --tolerances LIST    relative residual to stop at (default 1e-3,1e-5; 0: run the cap)\n"
          "  --iterations LIST    iteration caps (default 30,300)\n",
          out);
    fputs("  --substeps LIST      substeps per frame (default 1,2,4)\n"
          "  --substeps-large LIST  substeps per frame for scenes over 20000 particles (default 1)\n",
          out);
    fputs(BENCH_METHOD_HELP("block_jacobi,amg")
          "  --ref-substeps N     substeps per frame of the reference run (default 8: sheet32's halving\n"
          "                       figure 0.11 %, docs/bench/README.md \"Accuracy at one step per frame\")\n"
          "  --ref-integrator NAME  be, bdf2 or trbdf2 (default): the reference's integrator (TR-BDF2:\n"
          "                       second order with its stages solved, L-stable)\n"
          "  --ref-newton N       the reference's Newton iterations per substep (default 3; more than 1: with\n"
          "                       line search and a Newton tolerance of 1e-10, the nonlinear system\n"
          "                       solved, so that a second-order integrator converges at its order)\n"
          "  --undamped           no air drag and no spring damping in any run (the reference's too): what\n"
          "                       is left is the integrators' own error on a conservative system\n"
          "  --no-air             no air drag in any run (spring damping kept)\n"
          "  --no-ref-check       skip the reference's run at twice its substeps\n"
          "  --ref-halvings N     the check as a ladder: the reference at 2, 4, ... 2^N times its substeps,\n"
          "                       each against the previous (default 1); the table shows each halving's\n"
          "                       RMS difference and the observed order log2(previous / this)\n"
          "  --ref-only           the reference and its check only (no configurations)\n"
          "  --seconds T          simulated time (default 2)\n"
          "  --fps F              frames per second (default 30)\n"
          "  --probes N           accepted and ignored: the linear-solve error is measured by\n"
          "                       tests/bench/bench_linear_error (and the scene's sensitivity to a\n"
          "                       displaced start by tests/bench/bench_sensitivity)\n"
          "  --threads N          OpenMP threads (default 0: OpenMP's default)\n"
          "  --garment FILE       the garment mesh (default " WEFT_SAMPLE_SCENES "/skirt.obj)\n"
          "  --csv FILE           write every measurement as CSV\n"
          "  --md FILE            write the Markdown table to FILE instead of stdout\n"
          "  --plot FILE.png      plot trajectory RMS error against ms/frame (log-log, a panel per\n"
          "                       scene, a curve per solver: its methods' points share it; the\n"
          "                       Pareto front marked)\n"
          BENCH_BACKEND_HELP
          "                       The reference is the CPU's direct solver for both; the direct\n"
          "                       solver does not exist on the GPU: its configurations have no GPU\n"
          "                       row. With two backends the plot has a panel per scene and backend.\n"
          "  --quiet              no progress lines on stderr\n"
          "  -h, --help           show this help\n",
          out);
}

static void set_scenes(acc_args* a, const char* list) {
    a->n_scenes = bench_split_names(list, a->scene_buf, sizeof a->scene_buf, a->scenes, MAX_SCENES);
}

static void defaults(void* args, int quick) {
    acc_args* a = args;
    memset(a, 0, sizeof *a);
    set_scenes(a, quick ? "sheet16,drape16,garment" : "sheet32,sheet64,sheet100,sheet256,drape,garment");
    a->n_solvers = bench_parse_solvers("all", a->solvers);
    a->n_tolerances = bench_parse_doubles(quick ? "1e-3" : "1e-3,1e-5", 0, 1, a->tolerances);
    a->n_caps = bench_parse_ints(quick ? "20,100" : "30,300", 1, 1000000, a->caps);
    a->n_substeps = bench_parse_ints(quick ? "1,2" : "1,2,4", 1, 1024, a->substeps);
    a->n_substeps_large = bench_parse_ints("1", 1, 1024, a->substeps_large);
    a->ref_substeps = 8;
    a->ref_check = 1;
    a->ref_halvings = 1;
    /* converged in time (docs/bench/README.md, "Accuracy at one step per frame") */
    a->ref_integrator = WEFT_INTEGRATOR_TRBDF2;
    a->ref_newton = 3;
    bench_methods_default(&a->meth, quick ? "block_jacobi,amg" : "block_jacobi,amg");
    a->seconds = quick ? 0.3 : 2.0;
    a->fps = 30;
    a->backends[0] = BENCH_CPU;
    a->n_backends = 1;
}

/* This command's own options (bench_option_fn). */
static int own_option(void* args, int argc, char** argv, int* i, const char** v) {
    acc_args* a = args;
    int m = 0;
#define OPT(name) ((m = cli_option_value(argc, argv, i, name, v)) != 0)
#define BAD(cond) (m < 0 ? m : (cond) ? -2 : 1) /* m < 0: the value is missing */
    if (OPT("--scenes")) {
        if (m < 0) return m;
        set_scenes(a, *v);
        return BAD(a->n_scenes == 0);
    }
    if (OPT("--solvers")) return BAD((a->n_solvers = bench_parse_solvers(*v, a->solvers)) < 0);
    if (OPT("--tolerances")) return BAD((a->n_tolerances = bench_parse_doubles(*v, 0, 1, a->tolerances)) < 0);
    if (OPT("--iterations")) return BAD((a->n_caps = bench_parse_ints(*v, 1, 1000000, a->caps)) < 0);
    if (OPT("--substeps")) return BAD((a->n_substeps = bench_parse_ints(*v, 1, 1024, a->substeps)) < 0);
    if (OPT("--substeps-large"))
        return BAD((a->n_substeps_large = bench_parse_ints(*v, 1, 1024, a->substeps_large)) < 0);
    if (OPT("--ref-substeps")) return BAD(cli_parse_int(*v, 1, 512, &a->ref_substeps) != 0);
    if (OPT("--ref-integrator")) {
        if (m < 0) return m;
        const int g = cli_integrator_from_name(*v);
        a->ref_integrator = g >= 0 ? (weft_integrator)g : WEFT_INTEGRATOR_BACKWARD_EULER;
        return g < 0 ? -2 : 1;
    }
    if (!strcmp(argv[*i], "--no-air")) {
        a->no_air = 1;
        return 1;
    }
    if (!strcmp(argv[*i], "--undamped")) {
        a->undamped = 1;
        return 1;
    }
    if (OPT("--ref-newton")) return BAD(cli_parse_int(*v, 1, 100, &a->ref_newton) != 0);
    if (OPT("--ref-halvings")) return BAD(cli_parse_int(*v, 1, 6, &a->ref_halvings) != 0);
    if (!strcmp(argv[*i], "--ref-only")) {
        a->ref_only = 1;
        return 1;
    }
    /* measured in tests/bench (docs/design/tool.md): --probes is accepted so that recorded
       command lines still run (nothing is probed here); --ref-displace is refused, naming
       bench_sensitivity */
    if (OPT("--probes")) {
        int n = 0;
        if (m > 0 && cli_parse_int(*v, 0, 1000000, &n) == 0 && n > 0)
            fprintf(stderr, "weft bench accuracy: --probes %d ignored: the linear-solve error is "
                            "tests/bench/bench_linear_error's\n", n);
        return BAD(cli_parse_int(*v, 0, 1000000, &n) != 0);
    }
    if (OPT("--ref-displace")) {
        if (m > 0)
            fprintf(stderr, "weft bench accuracy: --ref-displace moved to tests/bench/bench_sensitivity (it displaces "
                            "particles inside the state)\n");
        return m < 0 ? m : -2;
    }
    if (!strcmp(argv[*i], "--no-ref-check")) {
        a->ref_check = 0;
        return 1;
    }
    if ((m = bench_methods_option(&a->meth, argc, argv, i, v)) != 0) return m;
    if (OPT("--seconds"))
        return BAD(cli_parse_double(*v, &a->seconds) != 0 || !(a->seconds > 0 && a->seconds <= 3600));
    if (OPT("--fps")) return BAD(cli_parse_double(*v, &a->fps) != 0 || !(a->fps >= 1 && a->fps <= 10000));
    if (OPT("--backend")) return BAD((a->n_backends = bench_parse_backends(*v, a->backends)) < 0);
#undef OPT
#undef BAD
    return m;
}

enum {
    C_BACKEND, C_SCENE, C_PARTICLES, C_ROLE, C_SOLVER, C_TOL, C_CAP, C_SUBSTEPS, C_FRAMES, C_MS, C_FORCES,
    C_ASSEMBLE, C_SOLVE, C_COLLIDE, C_INTEGRATE, C_ITER, C_MAXITER, C_NOTCONV, C_ROLLBACKS, C_FALLBACKS,
    C_FAILURES, C_LIN_MEAN, C_LIN_MAX, C_TRAJ_RMS, C_TRAJ_MAX, C_STRAIN, C_DRIFT, C_PRECOND, C_INTEGRATOR,
    C_NEWTON, C_LINE_SEARCH, C_SOLVES, C_ITER_SOLVE, C_SETUP_MS, C_CONVERGED, C_SWING, C_KE, C_FORCING, N_COLS
};
static const char* const csv_cols[N_COLS] = {
    "backend", "scene", "particles", "role", "solver", "tolerance", "max_iterations", "substeps", "frames",
    "ms_per_frame", "ms_forces", "ms_assemble", "ms_solve", "ms_collide", "ms_integrate",
    "iterations_per_substep", "max_iterations_used", "not_converged", "rollbacks", "direct_fallbacks",
    "failures", "lin_err_mean", "lin_err_max", "traj_err_rms", "traj_err_max", "max_strain", "energy_drift",
    "preconditioner", "integrator", "newton_iterations", "line_search", "solves", "iterations_per_solve",
    "ms_precond_per_solve", "converged_fraction", "com_err_max", "kinetic_ratio", "newton_forcing"};
static const char* const md_cols[N_COLS] = {
    NULL /* "backend" with two backends */, "scene", NULL, NULL, "solver", "tol.", "cap", "substeps", NULL, "ms/frame", NULL, NULL, NULL, NULL, NULL,
    NULL, "max it.", NULL, "rollbacks", NULL, NULL, NULL, NULL /* lin. err: "-" here */, "traj. err RMS",
    "traj. err max", "max strain", "energy drift", "precond.", "integrator", "Newton", NULL, NULL, "it./solve",
    "setup ms/solve", NULL, "c.o.m. err max", "KE ratio", "forcing"};

typedef struct config {
    weft_solver solver;
    bench_method method;
    double tolerance;
    int cap;
    int substeps;
    int reference;          /* 1: the reference, 2: its check at twice the substeps */
} config;

/* The swing against the reference, over every frame: the largest distance between the centres of
 * mass / the bounding-box diagonal, and the kinetic energy summed over the frames / the
 * reference's (< 1: the swing lost energy to numerical damping). */
typedef struct swing_err {
    double com_max;
    double ke_ratio;
} swing_err;

static swing_err swing_against(const bench_run* r, const bench_run* ref, double diag) {
    swing_err e = {0.0, 1.0};
    int frames = r->frames < ref->frames ? r->frames : ref->frames;
    double ke = 0.0, ke_ref = 0.0;
    for (int f = 0; f < frames; ++f) {
        const double *a = r->track + 4 * (size_t)f, *b = ref->track + 4 * (size_t)f;
        double d2 = 0.0;
        for (int c = 0; c < 3; ++c) d2 += (a[c] - b[c]) * (a[c] - b[c]);
        if (!(sqrt(d2) / diag <= e.com_max)) e.com_max = sqrt(d2) / diag;
        ke += a[3];
        ke_ref += b[3];
    }
    e.ke_ratio = ke_ref > 0 ? ke / ke_ref : NAN;
    return e;
}

static int add_row(bench_table* t, int backend, const bench_scene* bs, const config* c, const bench_run* r,
                   double rms, double max, swing_err sw) {
    char b[N_COLS][48];
    const char* cell[N_COLS];
    snprintf(b[C_BACKEND], 48, "%s", bench_backend_name(backend));
    snprintf(b[C_SCENE], 48, "%s", bs->name);
    snprintf(b[C_PARTICLES], 48, "%d", r->particles);
    static const char* const roles[3] = {"config", "reference", "reference_check"};
    snprintf(b[C_ROLE], 48, "%s", roles[c->reference]);
    snprintf(b[C_SOLVER], 48, "%s%s", cli_solver_name(c->solver),
             c->reference == 2 ? " (2x reference)" : c->reference ? " (reference)" : "");
    if (c->solver == WEFT_SOLVER_DIRECT) {
        snprintf(b[C_TOL], 48, "-");
        snprintf(b[C_CAP], 48, "-");
    } else {
        snprintf(b[C_TOL], 48, "%g", c->tolerance);
        snprintf(b[C_CAP], 48, "%d", c->cap);
    }
    snprintf(b[C_SUBSTEPS], 48, "%d", c->substeps);
    snprintf(b[C_FRAMES], 48, "%d", r->frames);
    bench_fmt(b[C_MS], 48, "%.2f", r->ms_median);
    for (int k = 0; k < 5; ++k) bench_fmt(b[C_FORCES + k], 48, "%.2f", r->stage_median[k]);
    bench_fmt(b[C_ITER], 48, "%.1f", r->iterations);
    snprintf(b[C_MAXITER], 48, "%d", r->max_iterations);
    snprintf(b[C_NOTCONV], 48, "%d", r->not_converged);
    snprintf(b[C_ROLLBACKS], 48, "%d", r->rollbacks);
    snprintf(b[C_FALLBACKS], 48, "%d", r->direct_fallbacks);
    snprintf(b[C_FAILURES], 48, "%d", r->failures);
    snprintf(b[C_LIN_MEAN], 48, "-");   /* tests/bench/bench_linear_error */
    snprintf(b[C_LIN_MAX], 48, "-");
    bench_fmt(b[C_TRAJ_RMS], 48, "%.3g", rms);
    bench_fmt(b[C_TRAJ_MAX], 48, "%.3g", max);
    bench_fmt(b[C_STRAIN], 48, "%.3g", r->max_strain);
    bench_fmt(b[C_DRIFT], 48, "%.3g", (r->energy_end - r->energy0) / r->energy_scale);
    snprintf(b[C_PRECOND], 48, "%s", bench_precond_label(c->solver, &c->method));
    snprintf(b[C_INTEGRATOR], 48, "%s", cli_integrator_name(c->method.integrator));
    snprintf(b[C_NEWTON], 48, "%d", c->method.newton);
    snprintf(b[C_LINE_SEARCH], 48, "%s", c->method.line_search ? "on" : "off");
    if (c->method.newton > 1 && c->solver != WEFT_SOLVER_DIRECT) bench_forcing_label(c->method.forcing, b[C_FORCING], 48);
    else snprintf(b[C_FORCING], 48, "-");
    snprintf(b[C_SOLVES], 48, "%lld", r->solves);
    bench_fmt(b[C_ITER_SOLVE], 48, "%.1f", bench_run_iterations_per_solve(r));
    bench_fmt(b[C_SETUP_MS], 48, "%.3g", bench_run_precond_ms_per_solve(r));
    bench_fmt(b[C_CONVERGED], 48, "%.3g", bench_run_converged_fraction(r));
    bench_fmt(b[C_SWING], 48, "%.3g", sw.com_max);
    bench_fmt(b[C_KE], 48, "%.4g", sw.ke_ratio);
    for (int k = 0; k < N_COLS; ++k) cell[k] = b[k];
    return bench_table_add(t, cell);
}

/* The configurations of a scene with n particles. */
static int configs_for(const acc_args* a, int n, config* out, int cap) {
    const int* subs = n > LARGE_SCENE ? a->substeps_large : a->substeps;
    const int n_subs = n > LARGE_SCENE ? a->n_substeps_large : a->n_substeps;
    bench_method meth[BENCH_MAX_LIST * BENCH_MAX_LIST * BENCH_MAX_LIST];
    int k = 0;
    for (int s = 0; s < a->n_solvers; ++s) {
        const int direct = a->solvers[s] == WEFT_SOLVER_DIRECT;
        const int n_meth = bench_methods_expand(&a->meth, a->solvers[s], meth, (int)(sizeof meth / sizeof meth[0]));
        for (int q = 0; q < n_meth * (direct ? 1 : a->n_tolerances * a->n_caps); ++q)
            for (int u = 0; u < n_subs && k < cap; ++u) {
                const int mi = direct ? q : q / (a->n_tolerances * a->n_caps);
                const int t = direct ? 0 : q / a->n_caps % a->n_tolerances, c = direct ? 0 : q % a->n_caps;
                config* g = &out[k++];
                g->solver = a->solvers[s];
                g->method = meth[mi];
                g->tolerance = direct ? 0 : a->tolerances[t];
                g->cap = direct ? 1 : a->caps[c];
                g->substeps = subs[u];
                g->reference = 0;
            }
    }
    return k;
}

/* One halving of the reference's check of a scene: the run at `substeps` against the run at half
 * of them (the reference itself for the first halving). */
typedef struct ref_check {
    char scene[32];
    int substeps;           /* the finer run's (2 x the coarser one's) */
    double rms, max;        /* their difference at the end / bounding-box diagonal */
    double order;           /* log2(previous halving's rms / this rms); NAN for the first */
} ref_check;

#define MAX_HALVINGS 6
#define REF_GOAL 1e-3       /* the reference is converged when halving its step moves it by < 0.1 % */

typedef struct header_info {
    const acc_args* a;
    int frames, threads;
    const ref_check* checks;
    int n_checks;
} header_info;

static const char* integrator_words(weft_integrator g) {
    return g == WEFT_INTEGRATOR_BDF2 ? "BDF2" : g == WEFT_INTEGRATOR_TRBDF2 ? "TR-BDF2" : "backward Euler";
}

static void print_header(FILE* out, const void* ctx) {
    const header_info* h = ctx;
    const acc_args* a = h->a;
    const int frames = h->frames, threads = h->threads;
    char note[1024], blas[64];
    int gpu = 0;
    for (int k = 0; k < a->n_backends; ++k) gpu |= a->backends[k] == BENCH_GPU;
    fprintf(out, "## weft bench accuracy\n\n");
    fprintf(out, "%s. %d OpenMP thread(s), %s. %g s simulated at %g fps (%d frames). Reference: the direct "
                 "solver (CHOLMOD), %s, %d Newton iteration(s)%s, at %d substeps per frame, on the CPU.\n\n",
            bench_backend_note(a->backends, a->n_backends, note, sizeof note), threads,
            bench_blas_note(&a->com, blas, sizeof blas), a->seconds, a->fps, frames, integrator_words(a->ref_integrator),
            a->ref_newton, a->ref_newton > 1 ? " with line search, tolerance 1e-10" : "", a->ref_substeps);
    if (a->undamped) fprintf(out, "Undamped (--undamped): no air drag and no spring damping in any run.\n\n");
    else if (a->no_air) fprintf(out, "No air (--no-air): no air drag in any run (spring damping kept).\n\n");
    if (h->n_checks > 0) {
        fprintf(out, "Is the reference converged in time? The same run at %d substeps per frame against it at the "
                     "end, as %% of the bounding-box diagonal (goal < %g %%; the ref. halving figure). With "
                     "--ref-halvings, every further halving against the previous one and the observed order "
                     "log2(previous RMS diff / this one). A scene's own sensitivity to its start, below which no "
                     "reference converges, is tests/bench/bench_sensitivity's:\n\n"
                     "| scene | substeps | check substeps | ref. halving RMS diff (%%) | max diff (%%) | order | "
                     "goal < %g %% |\n"
                     "|---|---|---|---|---|---|---|\n",
                2 * a->ref_substeps, 100 * REF_GOAL, 100 * REF_GOAL);
        for (int k = 0; k < h->n_checks; ++k) {
            const ref_check* c = &h->checks[k];
            char order[32];
            if (isnan(c->order)) snprintf(order, sizeof order, "-");
            else bench_fmt(order, sizeof order, "%.2f", c->order);
            fprintf(out, "| %s | %d | %d | %.3g | %.3g | %s | %s |\n", c->scene, c->substeps / 2, c->substeps,
                    100 * c->rms, 100 * c->max, order,
                    c->max < REF_GOAL ? "met" : c->rms < REF_GOAL ? "met (RMS only)" : "not met");
        }
        fputc('\n', out);
    }
    if (gpu)
        fputs("GPU rows: the trajectory error is against the same CPU reference; lin. err is not measured "
              "on either backend here; the direct solver does not exist on the GPU, so its configurations "
              "have no GPU row.\n\n",
              out);
    fputs("- ms/frame: median wall time of one frame's weft_cloth_step call (its stats' ms_total: the step and "
          "the library's bookkeeping around it).\n"
          "- precond.: PCG's preconditioner (- for the other solvers); integrator: be (backward Euler), bdf2 or trbdf2; "
          "Newton: linearised solves per substep (line search on when the CSV's line_search says so); forcing: "
          "inexact Newton's first solve of a substep stops at this relative residual (0: at the tolerance; "
          "default: the library's; - with one Newton iteration or the direct solver).\n"
          "- it./solve: solver iterations per linear solve, mean over the run (Newton iterations and friction "
          "passes are solves); max it.: the largest in one solve; setup ms/solve: the preconditioner's setup "
          "time per solve.\n"
          "- lin. err (CSV: -): the linear-solve error against CHOLMOD on the step's own system needs the "
          "solver's internals, not the public API: tests/bench/bench_linear_error.\n"
          "- traj. err: RMS / largest host-vertex distance to the reference run at the end (float positions, "
          "as weft_cloth_get_vertices gives them), divided by the cloth's bounding-box diagonal.\n"
          "- max strain: largest stretch-spring strain (l - rest) / rest at the end of any frame.\n"
          "- energy drift: (E_end - E_start) / (M |g| D), E = kinetic + spring + gravitational energy "
          "(weft_cloth_get_energy; negative: dissipated; compare with the reference row).\n"
          "- c.o.m. err max: largest distance between the centres of mass of the run and the reference over "
          "every frame, divided by the diagonal (the swing's phase and amplitude); KE ratio: kinetic energy "
          "summed over the frames / the reference's (< 1: the swing lost energy to numerical damping).\n\n",
          out);
}

/* The run options of the scene with the command's damping and air, sleeping off. */
static bench_run_opts run_opts(const acc_args* a, const bench_scene* bs, int frames) {
    bench_run_opts o;
    memset(&o, 0, sizeof o);
    o.backend = BENCH_CPU;
    o.fps = a->fps;
    o.frames = frames;
    o.def = bench_run_def(bs);
    if (a->undamped || a->no_air) o.def.air_drag_normal = o.def.air_drag_tangent = 0.0;
    if (a->undamped)
        for (int k = 0; k < 3; ++k) o.def.material.damping[k] = 0.0;
    return o;
}

/* The reference's method: the direct solver, --ref-integrator, --ref-newton Newton iterations
 * (more than one: line search on, tolerance 1e-10). */
static bench_method reference_method(const acc_args* a) {
    const bench_method m = {WEFT_PRECOND_BLOCK_JACOBI, a->ref_integrator, a->ref_newton, a->ref_newton > 1, -1.0};
    return m;
}

/* The reference's run options at `substeps`. */
static bench_run_opts reference_opts(const acc_args* a, const bench_scene* bs, int frames, int substeps) {
    bench_run_opts o = run_opts(a, bs, frames);
    o.def.solver = WEFT_SOLVER_DIRECT;
    o.def.substeps = substeps;
    const bench_method m = reference_method(a);
    bench_method_apply(&m, &o.def);
    if (a->ref_newton > 1) o.def.tolerance = 1e-10;
    return o;
}

/* The reference run of a scene (row added) and, when asked, its check at twice the substeps and
 * the further halvings (rows added, check[0 .. ref_halvings - 1] filled). 0, or -1 with msg. */
static int run_reference(const acc_args* a, const bench_scene* bs, int frames, bench_table* t, bench_run* rr,
                         ref_check* check, char* msg, size_t size) {
    bench_run_opts o = reference_opts(a, bs, frames, a->ref_substeps);
    if (!a->com.quiet) fprintf(stderr, "%s: reference run...\n", bs->name);
    if (bench_run_scene(bs, &o, rr, msg, size) != 0) return -1;
    config ref = {WEFT_SOLVER_DIRECT, reference_method(a), 0, 1, a->ref_substeps, 1};
    add_row(t, BENCH_CPU, bs, &ref, rr, 0.0, 0.0, (swing_err){0.0, 1.0});
    if (!a->ref_check) return 0;
    bench_run prev = *rr, r2;   /* prev: the coarser run of the halving (rr for the first: not freed here) */
    for (int k = 0; k < a->ref_halvings; ++k) {
        const int subs = a->ref_substeps << (k + 1);
        if (!a->com.quiet) fprintf(stderr, "  the reference at %d substeps (its check)...\n", subs);
        o = reference_opts(a, bs, frames, subs);
        if (bench_run_scene(bs, &o, &r2, msg, size) != 0) {
            if (k > 0) bench_run_free(&prev);
            bench_run_free(rr);
            return -1;
        }
        double rms, max;
        ref_check* c = &check[k];
        bench_distance(r2.x, prev.x, r2.vertices, &rms, &max);
        snprintf(c->scene, sizeof c->scene, "%s", bs->name);
        c->substeps = subs;
        c->rms = rms / rr->diag;
        c->max = max / rr->diag;
        c->order = k > 0 && c->rms > 0 ? log2(check[k - 1].rms / c->rms) : NAN;
        if (!a->com.quiet)
            fprintf(stderr, "  %d vs %d substeps: RMS %.3g %%, max %.3g %% of the diagonal, order %.2f\n", subs,
                    subs / 2, 100 * c->rms, 100 * c->max, c->order);
        ref.substeps = subs;
        ref.reference = 2;
        add_row(t, BENCH_CPU, bs, &ref, &r2, c->rms, c->max, swing_against(&r2, &prev, rr->diag));
        if (k > 0) bench_run_free(&prev);
        prev = r2;
    }
    if (a->ref_halvings > 0) bench_run_free(&prev);
    return 0;
}

/* One configuration on one backend against the reference rr (row and plot point added). 0, or -1
 * with msg. */
static int run_config(const acc_args* a, const bench_scene* bs, const config* c, int backend, int frames,
                      const bench_run* rr, bench_table* t, bench_point* pt, char* msg, size_t size) {
    bench_run_opts o = run_opts(a, bs, frames);
    o.backend = backend;
    o.def.solver = c->solver;
    o.def.tolerance = c->tolerance;
    if (c->solver != WEFT_SOLVER_DIRECT) o.def.max_iterations = c->cap;
    o.def.substeps = c->substeps;
    bench_method_apply(&c->method, &o.def);
    bench_run r;
    if (bench_run_scene(bs, &o, &r, msg, size) != 0) return -1;
    double rms, max;
    bench_distance(r.x, rr->x, r.vertices, &rms, &max);
    rms /= rr->diag;
    max /= rr->diag;
    if (!a->com.quiet) {
        char label[64];
        fprintf(stderr, "  %s %s %s tol %g cap %d substeps %d: %.2f ms/frame, %.1f it./solve, traj. err %.3g\n",
                bench_backend_name(backend), cli_solver_name(c->solver),
                bench_method_short(c->solver, &c->method, label, sizeof label), c->tolerance, c->cap, c->substeps,
                r.ms_median, bench_run_iterations_per_solve(&r), rms);
    }
    add_row(t, backend, bs, c, &r, rms, max, swing_against(&r, rr, rr->diag));
    pt->solver = (int)c->solver;
    pt->ms = r.ms_median;
    pt->error = rms;
    bench_run_free(&r);
    return 0;
}

int bench_accuracy_run(int argc, char** argv) {
    acc_args a;
    int rc = bench_parse_args(argc, argv, "weft bench accuracy", bench_accuracy_usage, defaults, own_option, &a,
                              &a.com);
    if (rc >= 0) return rc;
    const int frames = (int)lround(a.seconds * a.fps) > 0 ? (int)lround(a.seconds * a.fps) : 1;
    bench_table t;
    const char* md[N_COLS];
    memcpy(md, md_cols, sizeof md);
    if (a.n_backends > 1) md[C_BACKEND] = "backend";
    bench_table_init(&t, N_COLS, csv_cols, md);
    const int max_subs = a.n_substeps > a.n_substeps_large ? a.n_substeps : a.n_substeps_large;
    const int max_cfg = a.n_solvers * bench_methods_max(&a.meth) * a.n_tolerances * a.n_caps * max_subs;
    const int max_points = a.n_scenes * max_cfg * a.n_backends;
    /* the plot's panels: a scene, or (two backends) a scene on a backend */
    char(*panel_buf)[48] = calloc((size_t)(a.n_scenes * a.n_backends), sizeof *panel_buf);
    const char** panels = calloc((size_t)(a.n_scenes * a.n_backends), sizeof(char*));
    bench_point* pts = malloc(sizeof *pts * (size_t)(max_points > 0 ? max_points : 1));
    config* cfg = malloc(sizeof *cfg * (size_t)(max_cfg > 0 ? max_cfg : 1));
    ref_check checks[MAX_SCENES * MAX_HALVINGS];
    int n_pts = 0, n_checks = 0, threads = 1;
    rc = CLI_EXIT_OK;
    if (!pts || !cfg || !panel_buf || !panels) {
        cli_error("out of memory");
        rc = CLI_EXIT_FAILURE;
    }
    /* the reference is the CPU's: its context is open whatever --backend says */
    int open[BENCH_MAX_BACKENDS + 1] = {BENCH_CPU};
    memcpy(open + 1, a.backends, sizeof(int) * (size_t)a.n_backends);
    if (rc == CLI_EXIT_OK) rc = bench_open_backends(open, 1 + a.n_backends, a.com.threads);
    for (int si = 0; si < a.n_scenes && rc == CLI_EXIT_OK; ++si)
        for (int bi = 0; bi < a.n_backends; ++bi) {
            const int pi = si * a.n_backends + bi;
            if (a.n_backends > 1)
                snprintf(panel_buf[pi], sizeof panel_buf[pi], "%s (%s)", a.scenes[si], bench_backend_name(a.backends[bi]));
            else
                snprintf(panel_buf[pi], sizeof panel_buf[pi], "%s", a.scenes[si]);
            panels[pi] = panel_buf[pi];
        }
    char msg[1024];
    for (int si = 0; si < a.n_scenes && rc == CLI_EXIT_OK; ++si) {
        bench_scene bs;
        if (bench_scene_build(&bs, a.scenes[si], a.com.garment, 1.0, 1.0, msg, sizeof msg) != 0) {
            cli_error(msg);
            rc = CLI_EXIT_FAILURE;
            break;
        }
        bench_run rr;
        if (run_reference(&a, &bs, frames, &t, &rr, &checks[n_checks], msg, sizeof msg) != 0) {
            cli_error(msg);
            bench_scene_free(&bs);
            rc = CLI_EXIT_FAILURE;
            break;
        }
        n_checks += a.ref_check ? a.ref_halvings : 0;
        threads = rr.threads;
        const int n_cfg = a.ref_only ? 0 : configs_for(&a, rr.particles, cfg, max_cfg);
        for (int q = 0; q < n_cfg * a.n_backends && rc == CLI_EXIT_OK; ++q) {
            const int bi = q / n_cfg, backend = a.backends[bi];
            const config* c = &cfg[q % n_cfg];
            /* the GPU has no direct solver and runs PCG with block Jacobi, backward Euler, one Newton
             * iteration only: the other configurations have no GPU row */
            if (backend == BENCH_GPU && (c->solver == WEFT_SOLVER_DIRECT || !bench_method_on_gpu(&c->method)))
                continue;
            bench_point pt = {si * a.n_backends + bi, 0, 0.0, 0.0};
            if (run_config(&a, &bs, c, backend, frames, &rr, &t, &pt, msg, sizeof msg) != 0) {
                cli_error(msg);
                rc = CLI_EXIT_FAILURE;
                break;
            }
            if (n_pts < max_points) pts[n_pts++] = pt;
        }
        bench_run_free(&rr);
        bench_scene_free(&bs);
    }
    if (rc == CLI_EXIT_OK) {
        const header_info h = {&a, frames, threads, checks, n_checks};
        rc = bench_write_tables(&a.com, &t, print_header, &h);
    }
    if (rc == CLI_EXIT_OK && a.com.plot) {
        if (bench_plot_accuracy(a.com.plot, panels, a.n_scenes * a.n_backends, pts, n_pts,
                                "trajectory RMS error / bbox diagonal", msg, sizeof msg) != 0) {
            cli_error(msg);
            rc = CLI_EXIT_FAILURE;
        }
    }
    free(pts);
    free(cfg);
    free(panel_buf);
    free(panels);
    bench_table_free(&t);
    return rc;
}
