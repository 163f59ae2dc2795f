/* `weft bench`: benchmarks of the simulator (accuracy, stability, skip and peers drive core/
 * directly on the CPU and gpu/'s wg_sim on the GPU, by --backend LIST; torture goes through the
 * public API and takes --backend NAME).
 * Shared by the cmd_bench*.c files:
 *   cmd_bench.c            the `weft bench` dispatcher and list-option parsing
 *   cmd_bench_sim.c        benchmark scenes and one measured run of a scene
 *   cmd_bench_table.c      a table of text cells written as CSV and as Markdown
 *   cmd_bench_plot.c       the PNG plots (PLplot, pngcairo device)
 *   cmd_bench_accuracy.c   `weft bench accuracy`: run time against error
 *   cmd_bench_stability.c  `weft bench stability`: the step/stiffness/mass/solver grid
 *   cmd_bench_peers.c      `weft bench peers`: Weft beside Blender's cloth (cmd_bench_blender.c)
 *   cmd_bench_torture.c    `weft bench torture`: random host inputs through the public API
 *   cmd_bench_skip.c       `weft bench skip`: per-stage cost of features a scene does not use, sleeping
 *   cmd_bench_method.c     the method axes: preconditioner x integrator x Newton iterations
 *   cmd_bench_iterations.c `weft bench iterations`: PCG iterations per solve over sizes and stiffnesses
 *   cmd_bench_api.c        a run through the public API at weft_default_cloth_def() (peers' defaults row)
 *   cmd_bench_gpu.c        the process's headless GPU context and device, and a wg_sim on it
 *   cmd_bench_body.c       mesh collision bodies built in code (UV sphere / ellipsoid)
 *   cmd_bench_collide.c    `weft bench collide`: collision detection's cost over cloth and body sizes */
#ifndef WEFT_CLI_CMD_BENCH_H
#define WEFT_CLI_CMD_BENCH_H
#include <stdio.h>

#include "model.h"
#include "scene.h"
#include "source_mesh.h"
#include "step.h"

/* Backends of accuracy, stability, skip and peers (weft_backend's values). */
enum { BENCH_CPU = 1, BENCH_GPU = 2 };
#define BENCH_MAX_BACKENDS 2
/* The usage texts' line on --backend. */
#define BENCH_BACKEND_HELP                                                                              \
    "  --backend LIST       cpu, gpu or cpu,gpu (default cpu): every configuration on each backend,\n" \
    "                       a `backend` column telling the rows apart (cpu: core's wc_step_frame;\n"  \
    "                       gpu: gpu/'s wg_sim_step_frame on a headless EGL context, positions read\n" \
    "                       back outside the timed steps).\n"

/* ---- lists on the command line (cmd_bench.c) ---- */

#define BENCH_MAX_LIST 16

/* "a,b,c" -> up to BENCH_MAX_LIST finite doubles in [lo, hi]; "1/240" (a fraction) is accepted.
 * Returns the count, or -1 (empty item, not a number, out of range, too many). */
int bench_parse_doubles(const char* text, double lo, double hi, double* out);
/* The same for integers in [lo, hi]. */
int bench_parse_ints(const char* text, int lo, int hi, int* out);
/* Comma-separated names: list copied into buf (size bytes), split in place, up to max pointers
 * into it stored in out (empty items skipped). Returns the count. */
int bench_split_names(const char* list, char* buf, size_t size, const char** out, int max);
/* Backend names ("cpu", "gpu", "auto") as weft_backend values (0 AUTO, 1 CPU, 2 GPU); -1 when
 * unknown. */
int bench_parse_backend(const char* name);
/* A --backend list: "cpu", "gpu", "cpu,gpu" (each at most once) -> BENCH_CPU/BENCH_GPU in out
 * (BENCH_MAX_BACKENDS). Returns the count, or -1. */
int bench_parse_backends(const char* text, int* out);
/* "cpu" / "gpu". */
const char* bench_backend_name(int backend);
/* The backends run, for the Markdown notes: "backend: CPU (core's wc_step_frame)" and/or "GPU
 * (gpu/'s wg_sim_step_frame, <context description>)", joined. */
const char* bench_backend_note(const int* backends, int n, char* buf, size_t size);
/* Open the GPU (bench_gpu_open) when the list has it: CLI_EXIT_OK, or CLI_EXIT_FAILURE with the
 * reason on stderr. */
int bench_open_backends(const int* backends, int n);
/* Solver names ("pcg,jacobi,chebyshev,direct", or "all"); -1 on an unknown name. */
int bench_parse_solvers(const char* text, wc_solver_type* out);

/* ---- methods: preconditioner x integrator x Newton iterations (cmd_bench_method.c) ---- */

/* How each substep is solved, beside the solver and its tolerance. */
typedef struct bench_method {
    wc_precond_type precond;    /* PCG's preconditioner (the other solvers: BLOCK_JACOBI, shown "-") */
    wc_integrator integrator;
    int newton;                 /* Newton iterations per substep (>= 1) */
    int line_search;            /* 0 / 1 */
    double forcing;             /* inexact Newton's forcing term (wc_sim_def.newton_forcing) */
} bench_method;

/* The method axes of a command line: --preconds, --integrators, --newton, --line-search,
 * --newton-forcing. */
typedef struct bench_methods {
    wc_precond_type preconds[BENCH_MAX_LIST];
    int n_preconds;
    wc_integrator integrators[BENCH_MAX_LIST];
    int n_integrators;
    int newton[BENCH_MAX_LIST];
    int n_newton;
    int line_search;            /* -1 auto (on when Newton iterations > 1), 0 off, 1 on */
    double forcing[BENCH_MAX_LIST];
    int n_forcing;
} bench_methods;

/* The usage texts' lines on the five options; `preconds` is the command's default list. */
#define BENCH_METHOD_HELP(preconds)                                                                       \
    "  --preconds LIST      PCG's preconditioners: block_jacobi, amg or all (default " preconds ");\n"  \
    "                       the other solvers have none (shown -)\n"                                     \
    "  --integrators LIST   be (backward Euler), bdf2, trbdf2 or all (default be)\n"                            \
    "  --newton LIST        Newton iterations per substep (default 1: one Baraff-Witkin step)\n"        \
    "  --line-search MODE   auto (on when Newton iterations > 1; default), on or off\n"              \
    "  --newton-forcing LIST  inexact Newton: with more than one Newton iteration, a substep's\n"     \
    "                       first solve stops at this relative residual (default 1e-2; 0: at the\n"  \
    "                       tolerance, like the later ones)\n"

/* Defaults: preconds as given ("block_jacobi", "block_jacobi,amg"), be, 1 Newton iteration, auto,
 * the core's forcing term. */
void bench_methods_default(bench_methods* m, const char* preconds);
/* One of the five options at argv[*i] (bench_option_fn's contract: 1, 0 not one, -1, -2). */
int bench_methods_option(bench_methods* m, int argc, char** argv, int* i, const char** value);
/* The methods a solver runs: every preconditioner (PCG only; one entry for the others) x
 * integrator x Newton count x forcing term, in that order. Returns the count (<= cap). */
int bench_methods_expand(const bench_methods* m, wc_solver_type solver, bench_method* out, int cap);
/* How many methods any solver can have (the size for bench_methods_expand). */
int bench_methods_max(const bench_methods* m);
/* The method into a sim def (solver.preconditioner, integrator, newton_iterations, line_search,
 * newton_forcing). */
void bench_method_apply(const bench_method* b, wc_sim_def* sd);
/* The method of a sim def. */
bench_method bench_method_of(const wc_sim_def* sd);
/* "amg" / "block_jacobi", or "-" when the solver is not PCG. */
const char* bench_precond_label(wc_solver_type solver, const bench_method* b);
/* "amg bdf2 n3 ls" style short label: the preconditioner (PCG only), then the integrator, Newton
 * count and line search when not be, 1, off, and the forcing term ("f0.01") with more than one
 * Newton iteration and an iterative solver; "" for another solver's default method. */
const char* bench_method_short(wc_solver_type solver, const bench_method* b, char* buf, size_t size);
/* Preconditioner and integrator names ("...,all"). -1 on an unknown name. */
int bench_parse_preconds(const char* text, wc_precond_type* out);
int bench_parse_integrators(const char* text, wc_integrator* out);

/* ---- options and outputs shared by the subcommands (cmd_bench.c) ---- */

struct bench_table;

typedef struct bench_common {
    int threads;            /* --threads N: OpenMP threads (0: OpenMP's default; --quick: 1) */
    int quiet;              /* --quiet: no progress lines on stderr */
    const char* garment;    /* --garment FILE: the garment scene's mesh */
    const char* csv;        /* --csv FILE, NULL: none */
    const char* md;         /* --md FILE, NULL: stdout */
    const char* plot;       /* --plot FILE.png, NULL: none */
    int blas_threads;       /* OpenBLAS's threads (set to `threads` when > 0; cli_blas_threads), -1:
                               another BLAS */
} bench_common;

/* CHOLMOD's BLAS threads, for the Markdown notes: "OpenBLAS: N thread(s)" or "BLAS: not OpenBLAS". */
const char* bench_blas_note(const bench_common* c, char* buf, size_t size);

/* A subcommand's own option at argv[*i]: 1 when it is one and its value is good, 0 when it is not
 * one, -1 when its value is missing, -2 when its value is bad (*value set, as cli_option_value). */
typedef int (*bench_option_fn)(void* args, int argc, char** argv, int* i, const char** value);

/* Parse a subcommand's arguments: -h/--help prints usage to stdout (returns CLI_EXIT_OK);
 * otherwise defaults(args, quick) and the common defaults are applied, then every argument must
 * be --quick, a common option or one of own's. Returns -1 to go on, or an exit code (usage
 * errors name the command). */
int bench_parse_args(int argc, char** argv, const char* command, void (*usage)(FILE*),
                     void (*defaults)(void* args, int quick), bench_option_fn own, void* args, bench_common* common);

/* Write header(out, ctx) and the Markdown table to common->md (or stdout), and the CSV to
 * common->csv when set. CLI_EXIT_OK, or CLI_EXIT_FAILURE (message on stderr). */
int bench_write_tables(const bench_common* common, const struct bench_table* t,
                       void (*header)(FILE* out, const void* ctx), const void* ctx);

/* ---- the GPU backend (cmd_bench_gpu.c) ---- */

/* One headless GL context and solver device per process, made on first use and released by
 * bench_gpu_close (cli_bench_run calls it when the subcommand returns). 0, or -1 with msg (no GL
 * context or device here, or a weft built without gpu/: WEFT_GPU=OFF). */
int bench_gpu_open(char* msg, size_t size);
/* The context's description (device, renderer, GL version); "" when not open. */
const char* bench_gpu_description(void);
void bench_gpu_close(void);

/* A wg_sim of one state on the process's device (bench_gpu_open first); every call wraps its GL
 * work in wg_gl_begin/wg_gl_end. The direct solver is refused (WC_ERROR_UNSUPPORTED). */
typedef struct bench_gpu_sim bench_gpu_sim;
wc_status bench_gpu_sim_create(const wc_state* s, bench_gpu_sim** out, wc_diag* diag);
/* wg_sim_step_frame (pins and colliders taken from s, as wc_step_frame). */
wc_status bench_gpu_sim_step(bench_gpu_sim* g, wc_state* s, double dt, wc_step_stats* st, wc_diag* diag);
/* wg_sim_download: s->x, v, dv and contacts filled from the GPU. */
wc_status bench_gpu_sim_download(bench_gpu_sim* g, wc_state* s, wc_diag* diag);
void bench_gpu_sim_destroy(bench_gpu_sim* g);

/* ---- scenes (cmd_bench_sim.c) ---- */

#define BENCH_GARMENT_SPIN 6.283185307179586   /* rad/s: one turn a second */
#define BENCH_GARMENT_RAMP 0.5                 /* s */

/* The scene's pins resolved to particles (static targets at their rest positions). */
typedef struct bench_pins {
    int n;
    wc_pin* pins;           /* (n) */
    double* start;          /* (n x 3) rest positions (m) */
} bench_pins;

typedef struct bench_scene {
    char name[32];
    scene sc;               /* the scene as parsed: mesh, material, pins, colliders */
    /* the scene in core's forms, for the runs that step a wc_state */
    wc_source_mesh src;
    wc_model_def model_def;
    wc_sim_def sim;
    int n_colliders;
    wc_collider* colliders;
    wc_model model;
    bench_pins pins;
    double diag;            /* bounding-box diagonal of the cloth at rest (m) */
    double spin;            /* rad/s: the pins' targets turn about the y axis at this rate (0: still) */
} bench_scene;

/* Build a named scene:
 *   "sheetN"   N x N particles (2 <= N <= 2048), 1 m x 1 m, horizontal at first, hanging from the
 *              two corners of one edge;
 *   "drapeN"   an N x N sheet, 1 m x 1 m, 5 cm above a sphere of radius 0.25 m, falling onto it
 *              (no pins); "drape" is drape64;
 *   "hangN"    the sheetN grid hanging upright from its two top corners (at rest at first);
 *   "garment"  the mesh file `garment` (sample_scenes/skirt.obj, Y up), pinned at the waist
 *              (every vertex within 1 mm of its largest y), the waist turning about the y axis,
 *              speeding up evenly to BENCH_GARMENT_SPIN over BENCH_GARMENT_RAMP (a twirl).
 * Default material with every spring stiffness times k_scale and the density times mass_scale.
 * On failure *out is zeroed and diag says why. */
wc_status bench_scene_build(bench_scene* out, const char* name, const char* garment, double k_scale,
                              double mass_scale, wc_diag* diag);
void bench_scene_free(bench_scene* s);

/* One run of a scene. */
typedef struct bench_run_opts {
    int backend;            /* BENCH_CPU (0 too) or BENCH_GPU (bench_gpu_open first; no direct solver) */
    wc_sim_def sim;         /* solver, substeps, threads...; max_pins/max_colliders are set by the run */
    double fps;             /* frames per simulated second */
    int frames;             /* frames to simulate */
    int probe_frames;       /* frames (evenly spread, the first included) at which the linear-solve
                               error is measured; 0: not measured (never on the GPU: CPU only) */
    double fail_strain;     /* > 0: stop at the first frame whose strain exceeds this */
    double fail_energy;     /* > 0: stop at the first frame whose energy growth exceeds this */
    double displace;        /* m; > 0: every unpinned particle starts displaced by this much along
                               its own pseudo-random direction (a fixed hash of its index) */
} bench_run_opts;

typedef struct bench_run {
    int frames;             /* frames stepped (fewer than asked when stopped early) */
    double ms_median;       /* wall time of one frame (the step's own stats: wc_step_frame or
                               wg_sim_step_frame), median over frames */
    double stage_median[5]; /* forces, assemble, solve, collide, integrate: medians (ms) */
    double iterations;      /* solver iterations per substep, mean */
    int max_iterations;     /* largest in one solve */
    long long substeps;     /* substeps completed */
    int not_converged;      /* solves stopped at the iteration cap */
    int rollbacks, halvings, direct_fallbacks;
    int failures;           /* substeps that failed every retry */
    int nonfinite;          /* 1 when any position or energy became non-finite */
    double max_strain;      /* largest stretch strain at the end of any frame */
    double energy0;         /* total energy (kinetic + spring + gravity) at the start (J) */
    double energy_end;      /* ... at the end */
    double energy_max;      /* ... largest at the end of any frame */
    double energy_scale;    /* total mass x |g| x bounding-box diagonal (J): energies are reported
                               relative to this */
    int probes;             /* linear-solve errors measured */
    double lin_err_mean;    /* ||dv - dv_direct|| / ||dv_direct|| on the same system, mean */
    double lin_err_max;     /* ... largest */
    long long solves;       /* linear solves (Newton iterations and friction passes included) */
    long long iterations_total; /* solver iterations, summed */
    double precond_ms;      /* preconditioner setup time, summed over the run (ms) */
    double solve_ms;        /* the solve stage's time (setup included), summed over the run (ms) */
    double* x;              /* (n_particles x 3) positions at the end (owned; bench_run_free) */
    double* track;          /* (frames x 4) at the end of each frame: the centre of mass (3, m, mass-
                               weighted) and the kinetic energy (J); owned, NULL where not recorded */
} bench_run;

/* Simulate; 0 on success, -1 when the state (or the GPU sim) cannot be created or a GPU call
 * fails (diag says why). A frame whose step fails (WC_ERROR_STEP_FAILED) is counted, not fatal.
 * On the GPU, positions are downloaded after each frame (outside its timing) so that the energy,
 * strain and finiteness checks and the final positions are the CPU's. */
int bench_run_scene(const bench_scene* bs, const bench_run_opts* o, bench_run* out, wc_diag* diag);
void bench_run_free(bench_run* r);

/* The scene through the public API at weft_default_cloth_def() (cmd_bench_api.c): the library's
 * own defaults for everything but the mesh, the pins (held still) and sleeping (off); CPU
 * backend, `threads` threads, no colliders. ms_median from weft_frame_stats.ms_total; x per
 * particle of bs->model. 0, or -1 with msg. */
int bench_api_run_defaults(const bench_scene* bs, double fps, int frames, int threads, bench_run* out, char* msg,
                           size_t size);

/* Distances between two position sets (n x 3): RMS and largest. */
void bench_distance(const double* a, const double* b, int n, double* rms, double* max);

/* ---- tables (cmd_bench_table.c) ---- */

typedef struct bench_table {
    int n_cols;
    const char* const* cols;     /* column names (CSV header) */
    const char* const* md_cols;  /* Markdown header of each column, NULL: not in the Markdown table */
    int n_rows, cap_rows;
    char** cells;                /* (n_rows x n_cols) owned strings */
} bench_table;

void bench_table_init(bench_table* t, int n_cols, const char* const* cols, const char* const* md_cols);
/* Append a row: n_cols strings, copied. 0, or -1 when out of memory. */
int bench_table_add(bench_table* t, const char* const* cells);
/* v printed with fmt into buf ("nan", "inf", "-inf" for those), returned. */
const char* bench_fmt(char* buf, size_t size, const char* fmt, double v);
int bench_table_write_csv(const bench_table* t, FILE* out);
int bench_table_write_md(const bench_table* t, FILE* out);
void bench_table_free(bench_table* t);

/* ---- plots (cmd_bench_plot.c) ---- */

/* One point of the accuracy plot. */
typedef struct bench_point {
    int panel;              /* panel index (scene, or scene x backend) */
    int solver;             /* wc_solver_type */
    double ms;              /* ms per frame */
    double error;           /* trajectory error (relative); <= 0 points are not drawn */
} bench_point;

/* Error against ms/frame, log-log, one panel per scene, one curve per solver (its own Pareto
 * front through its points), the Pareto front over all solvers marked. 0, or -1 with msg. */
int bench_plot_accuracy(const char* path, const char* const* panel_names, int n_panels, const bench_point* pts,
                        int n_pts, const char* y_label, char* msg, size_t msg_size);

/* Outcome of one stability cell. */
enum { BENCH_SURVIVED = 0, BENCH_RECOVERED = 1, BENCH_FAILED = 2 };

/* Heat map: one panel per solver; columns are the step lengths, rows the (stiffness, mass) pairs;
 * cells coloured by outcome (index = ((solver * n_rows) + row) * n_cols + col), the text
 * cell_text[same index] drawn in the cell (may be NULL). */
int bench_plot_heatmap(const char* path, const char* const* panel_names, int n_panels, const char* const* col_labels,
                       int n_cols, const char* const* row_labels, int n_rows, const int* outcome,
                       const char* const* cell_text, const char* title, char* msg, size_t msg_size);

/* ---- subcommands ---- */
int bench_accuracy_run(int argc, char** argv);
void bench_accuracy_usage(FILE* out);
int bench_stability_run(int argc, char** argv);
void bench_stability_usage(FILE* out);
int bench_peers_run(int argc, char** argv);     /* cmd_bench_peers.c (Blender: cmd_bench_blender.h) */
void bench_peers_usage(FILE* out);
int bench_torture_run(int argc, char** argv);   /* cmd_bench_torture.c */
void bench_torture_usage(FILE* out);
int bench_skip_run(int argc, char** argv);      /* cmd_bench_skip.c */
void bench_skip_usage(FILE* out);
int bench_iterations_run(int argc, char** argv);   /* cmd_bench_iterations.c */
void bench_iterations_usage(FILE* out);
int bench_collide_run(int argc, char** argv);      /* cmd_bench_collide.c */
void bench_collide_usage(FILE* out);

/* ---- mesh bodies (cmd_bench_body.c) ---- */

/* A closed UV sphere of `rings` latitude bands (3 .. 4096) and 2 rings longitudes: 2 + (rings - 1)
 * 2 rings vertices and 4 rings (rings - 1) triangles, wound counter-clockwise seen from outside,
 * scaled by radii (3, m; equal: a sphere, else an ellipsoid) about center (3, m), and its mesh
 * collider (thickness, friction as mesh_collider.h). */
typedef struct bench_body {
    int n_verts, n_tris;
    double* x;              /* (n_verts x 3) m */
    int* tris;              /* (n_tris x 3) */
    wc_mesh_collider* mesh; /* owned */
} bench_body;
/* The band count whose triangle count 4 m (m - 1) is nearest target_tris (m >= 3). */
int bench_body_rings(int target_tris);
wc_status bench_body_create(bench_body* out, int rings, const double* center, const double* radii, double thickness,
                              double friction, wc_diag* diag);
void bench_body_free(bench_body* b);

/* Per-solve figures of a run: iterations (mean), preconditioner setup and solve-stage ms, the
 * fraction of solves that converged. Solves 0: the substeps stand in (a run with no stats). */
double bench_run_iterations_per_solve(const bench_run* r);
double bench_run_precond_ms_per_solve(const bench_run* r);
double bench_run_solve_ms_per_solve(const bench_run* r);
double bench_run_converged_fraction(const bench_run* r);

#endif
