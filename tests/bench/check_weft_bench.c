/* `weft bench accuracy|stability --quick`, run as a user would (WEFT_CLI), so neither command can
 * rot. Nothing about time is asserted. Checked: --help texts and usage errors; the CSV has the
 * expected header and one row per configuration/cell with finite errors; the direct solver's
 * linear-solve error against CHOLMOD is ~0; the Markdown table has a line per row; the plot is
 * a well-formed PNG (signature, chunk CRCs, IHDR first, IDAT, IEND last). Physics, from outside
 * the benchmark: (accuracy) the direct solver's trajectory error shrinks when its substeps
 * double, as backward Euler converges to the reference; (stability) a flat sheet's linearised
 * first step is a free fall that would stretch a pinned corner's spring to
 * sqrt(1 + (g h^2 / rest)^2) - 1: the long steps must be rolled back and stay well below it.
 *
 * (peers) Weft beside Blender's cloth on sheet12: both ms/frame positive, the ratio theirs,
 * Blender's pinned vertices unmoved (its vertex order is Weft's particle order), and each cloth's
 * lowest point fallen, but no further than a free particle under that solver's time stepping.
 * Without blender on PATH the peers mode checks what needs none and exits 77 (skipped).
 * (torture) every case of the quick run is ok, rejected with a status and a message, or
 * step_failed; every NaN/Inf injection is refused as NONFINITE; --case reruns a case identically.
 * (skip) one row per configuration in order, the asleep row slept through every timed frame
 * with 0 iterations and bit-identical positions, the full-cap row ran every solve to the cap, the
 * contact row has contacts and the far-collider row none.
 * (gpu, second argument: accuracy, stability, skip, peers) the same quick run with --backend
 * cpu,gpu: the CPU rows checked as above, the GPU rows beside them (no direct solver, no
 * linear-solve probe: "-"), and a GPU context that cannot be made is a clear failure (exit 1).
 *
 *   check_weft_bench accuracy | stability | peers | torture | skip [gpu] */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "check_bench_csv.h"
#include "test_support.h"

/* ---- help and usage ---- */

static void test_help(void) {
    static ts_cli_result r;
    ts_run_cli("--help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "bench") != NULL);
    ts_run_cli("bench --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "weft bench accuracy") && strstr(r.out, "weft bench stability") &&
          strstr(r.out, "weft bench skip") && strstr(r.out, "weft bench iterations"));
    CHECK(strstr(r.out, "--backend LIST") != NULL);
    ts_run_cli("help bench", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "weft bench accuracy") != NULL);
    ts_run_cli("bench", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "missing subcommand") != NULL);
    ts_run_cli("bench sideways", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "unknown subcommand 'sideways'") != NULL);
}

static void test_accuracy_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench accuracy --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "--plot") && strstr(r.out, "lin. err"));
    CHECK(strstr(r.out, "--backend LIST") && strstr(r.out, "not measured"));
    ts_run_cli("bench accuracy --backend tpu", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --backend: 'tpu'") != NULL);
    ts_run_cli("bench accuracy --backend cpu,cpu", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --backend cpu,", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --solvers pcg,gauss", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --solvers") != NULL);
    ts_run_cli("bench accuracy --tolerances 1e-3,,1e-4", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --substeps", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--substeps needs a value") != NULL);
    ts_run_cli("bench accuracy --help", &r);
    CHECK(strstr(r.out, "--preconds LIST") && strstr(r.out, "--integrators LIST") && strstr(r.out, "--newton LIST") &&
          strstr(r.out, "--line-search MODE") && strstr(r.out, "--no-ref-check") && strstr(r.out, "it./solve"));
    CHECK(strstr(r.out, "--ref-newton N") && strstr(r.out, "trbdf2") && strstr(r.out, "KE ratio"));
    ts_run_cli("bench accuracy --preconds block_jacobi,ilu", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --preconds") != NULL);
    ts_run_cli("bench accuracy --integrators be,rk4", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --ref-newton 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --newton 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --line-search sometimes", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --quick --scenes blanket9 --quiet", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "unknown scene 'blanket9'") != NULL);
    ts_run_cli("bench accuracy --quick --scenes garment --garment /nonexistent/skirt.obj --quiet", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "/nonexistent/skirt.obj") != NULL);
}

static void test_stability_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench stability --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "survived") && strstr(r.out, "--fail-strain"));
    CHECK(strstr(r.out, "--backend LIST") != NULL);
    ts_run_cli("bench stability --backend gpu --solvers direct", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "direct solver does not exist on the GPU") != NULL);
    ts_run_cli("bench stability --steps 1/0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench stability --stiffness 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench stability --quick --plot /nonexistent/dir/map.png --quiet", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "cannot write /nonexistent/dir/map.png") != NULL);
}

/* ---- the quick runs ---- */

static const char* const acc_cols[] = {
    "backend", "scene", "particles", "role", "solver", "tolerance", "max_iterations", "substeps", "frames",
    "ms_per_frame", "ms_forces", "ms_assemble", "ms_solve", "ms_collide", "ms_integrate",
    "iterations_per_substep", "max_iterations_used", "not_converged", "rollbacks", "direct_fallbacks",
    "failures", "lin_err_mean", "lin_err_max", "traj_err_rms", "traj_err_max", "max_strain", "energy_drift",
    "preconditioner", "integrator", "newton_iterations", "line_search", "solves", "iterations_per_solve",
    "ms_precond_per_solve", "converged_fraction", "com_err_max", "kinetic_ratio", "newton_forcing"};

static const char* const gpu_solvers[] = {"pcg", "jacobi", "chebyshev"};

static void test_accuracy_quick(int gpu) {
    static ts_cli_result r;
    static csv c;
    char args[4096];
    char csv_path[512], png_path[512], md_path[512]; /* ts_tmp_path's buffers are reused */
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_accuracy.csv"));
    snprintf(png_path, sizeof png_path, "%s", ts_tmp_path("bench_accuracy.png"));
    snprintf(md_path, sizeof md_path, "%s", ts_tmp_path("bench_accuracy.md"));
    remove(csv_path);
    remove(png_path);
    remove(md_path);
    snprintf(args, sizeof args, "bench accuracy --quick --quiet --csv '%s' --plot '%s' --md '%s'%s", csv_path,
             png_path, md_path, gpu ? " --backend cpu,gpu" : "");
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, acc_cols, (int)(sizeof acc_cols / sizeof acc_cols[0]));
    /* per scene: the reference and its check at twice the substeps, then pcg (block_jacobi, amg),
     * jacobi, chebyshev x 1 tolerance x 2 caps x 2 substeps, direct x 2; with the GPU, then the same
     * on the GPU but the direct solver's and AMG's */
    static const char* const scenes[] = {"sheet16", "drape16", "garment"};
    const int per_scene = 2 + 4 * 2 * 2 + 2, per_gpu = gpu ? 3 * 2 * 2 : 0, block = per_scene + per_gpu;
    CHECK_EQ_INT(c.n_rows, 3 * block);
    for (int s = 0; s < 3; ++s) {
        double direct_err[2] = {NAN, NAN};
        for (int j = 0; j < per_gpu && s * block + per_scene + j < c.n_rows; ++j) {
            /* the GPU's rows: every iterative configuration, no linear-solve probe */
            const int row = s * block + per_scene + j;
            CHECK(!strcmp(get(&c, row, "scene"), scenes[s]) && !strcmp(get(&c, row, "backend"), "gpu"));
            CHECK(!strcmp(get(&c, row, "role"), "config") && !strcmp(get(&c, row, "solver"), gpu_solvers[j / 4]));
            CHECK(num(&c, row, "max_iterations") == (j % 4 < 2 ? 20 : 100) && num(&c, row, "substeps") == j % 2 + 1);
            CHECK(num(&c, row, "frames") == 9 && num(&c, row, "ms_per_frame") > 0);
            CHECK(!strcmp(get(&c, row, "lin_err_max"), "-") && !strcmp(get(&c, row, "lin_err_mean"), "-"));
            CHECK(!isnan(num(&c, row, "traj_err_rms")) || !strcmp(get(&c, row, "traj_err_rms"), "nan"));
            if (j < 4) { /* PCG on the GPU follows the reference as on the CPU */
                const double rms = num(&c, row, "traj_err_rms");
                CHECK(isfinite(rms) && rms >= 0 && rms < 10);
            }
        }
        for (int k = 0; k < per_scene && s * block + k < c.n_rows; ++k) {
            const int row = s * block + k;
            const int ref = k <= 1;
            CHECK(!strcmp(get(&c, row, "scene"), scenes[s]));
            CHECK(!strcmp(get(&c, row, "backend"), "cpu"));
            CHECK(!strcmp(get(&c, row, "role"), k == 0 ? "reference" : k == 1 ? "reference_check" : "config"));
            /* the method columns: PCG's preconditioner (block_jacobi, then amg), backward Euler, one
             * Newton iteration, no line search (the defaults of these axes); the reference and its
             * check: TR-BDF2, Newton 3 + line search (--ref-integrator, --ref-newton defaults) */
            const char* pre = get(&c, row, "preconditioner");
            CHECK(!strcmp(pre, k >= 2 && k < 6 ? "block_jacobi" : k >= 6 && k < 10 ? "amg" : "-"));
            CHECK(!strcmp(get(&c, row, "integrator"), ref ? "trbdf2" : "be") &&
                  num(&c, row, "newton_iterations") == (ref ? 3 : 1) &&
                  !strcmp(get(&c, row, "line_search"), ref ? "on" : "off"));
            const double solves = num(&c, row, "solves"), its = num(&c, row, "iterations_per_solve");
            CHECK(solves >= 9 && its > 0 && its <= num(&c, row, "max_iterations_used"));
            CHECK(num(&c, row, "ms_precond_per_solve") >= 0);
            const double conv = num(&c, row, "converged_fraction");
            CHECK(conv >= 0 && conv <= 1);
            CHECK(num(&c, row, "frames") == 9);
            CHECK(num(&c, row, "ms_per_frame") > 0);
            const double rms = num(&c, row, "traj_err_rms"), max = num(&c, row, "traj_err_max");
            CHECK(isfinite(rms) && isfinite(max) && rms >= 0 && max >= rms);
            /* the reference's check at twice its substeps: close to it (first order: about half its own
             * error), the very figure the Markdown reports */
            CHECK(k == 0 ? rms == 0 && max == 0 : k == 1 ? rms > 0 && rms < 0.05 : rms < 10);
            CHECK(isfinite(num(&c, row, "max_strain")) && num(&c, row, "max_strain") >= 0);
            CHECK(isfinite(num(&c, row, "energy_drift")));
            /* the swing over every frame: the reference against itself is exact */
            const double com = num(&c, row, "com_err_max"), ke = num(&c, row, "kinetic_ratio");
            CHECK(isfinite(com) && com >= 0 && com <= (k == 0 ? 0.0 : 10.0));
            CHECK(k == 0 ? ke == 1.0 : isfinite(ke) && ke > 0.0);
            CHECK(num(&c, row, "substeps") == (k == 0 ? 8 : k == 1 ? 16 : (k - 2) % 2 + 1));
            if (ref) {
                CHECK(!strcmp(get(&c, row, "lin_err_max"), "-"));
                continue;
            }
            const double lin = num(&c, row, "lin_err_max"), lin_mean = num(&c, row, "lin_err_mean");
            CHECK(isfinite(lin) && isfinite(lin_mean) && lin >= lin_mean && lin_mean >= 0);
            if (!strcmp(get(&c, row, "solver"), "direct")) {
                CHECK(lin < 1e-9);
                CHECK(!strcmp(get(&c, row, "tolerance"), "-"));
                direct_err[(int)num(&c, row, "substeps") - 1] = rms;
            } else {
                CHECK(num(&c, row, "max_iterations_used") <= num(&c, row, "max_iterations"));
                CHECK(num(&c, row, "tolerance") == 1e-3);
            }
        }
        /* backward Euler converges to the reference as the step shrinks */
        CHECK(direct_err[1] < direct_err[0]);
        if (!(direct_err[1] < direct_err[0]))
            fprintf(stderr, "  %s: direct error %g (1 substep) vs %g (2 substeps)\n", scenes[s], direct_err[0],
                    direct_err[1]);
    }
    static char md[1 << 16];
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, gpu ? "| backend | scene | solver |" : "| scene | solver |") != NULL);
    CHECK(strstr(md, gpu ? "backends: CPU (core's wc_step_frame) and GPU (gpu/'s wg_sim_step_frame on "
                         : "backend: CPU (core's wc_step_frame)") != NULL);
    CHECK(gpu == (strstr(md, "lin. err is not measured") != NULL));
    CHECK(strstr(md, "Is the reference converged in time?") && strstr(md, "| sheet16 | 8 | 16 | ") &&
          strstr(md, "| garment | 8 | 16 | "));
    int table_lines = 0;
    for (const char* p = md; (p = strstr(p, "\n| ")) != NULL; ++p) ++table_lines;
    /* the reference check's header and 3 scenes, then the table's header + rows ("|---" start "|-") */
    CHECK_EQ_INT(table_lines, 4 + c.n_rows + 1);
    CHECK(png_ok(png_path, 400, 300));
}

static const char* const stab_cols[] = {
    "backend", "scene", "particles", "solver", "step_s", "stiffness_x", "mass_x", "outcome", "reason",
    "frames", "frames_asked", "rollbacks", "halvings", "direct_fallbacks", "failures", "max_strain",
    "energy_growth", "iterations_per_substep", "ms_per_frame", "preconditioner", "integrator", "newton_iterations",
    "line_search", "iterations_per_solve"};

static void test_stability_quick(int gpu) {
    static ts_cli_result r;
    static csv c;
    char args[4096];
    char csv_path[512], png_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_stability.csv"));
    snprintf(png_path, sizeof png_path, "%s", ts_tmp_path("bench_stability.png"));
    remove(csv_path);
    remove(png_path);
    /* on both backends, two stiffnesses of the three (llvmpipe's GPU frames are slow: ~60 s -> ~40 s) */
    snprintf(args, sizeof args, "bench stability --quick --quiet --csv '%s' --plot '%s'%s", csv_path, png_path,
             gpu ? " --backend cpu,gpu --stiffness 1,10000" : "");
    const int n_k = gpu ? 2 : 3;
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    CHECK(strstr(r.out, gpu ? "| backend | solver | method | survived | recovered | failed |"
                            : "| solver | method | survived | recovered | failed |") != NULL);
    CHECK(strstr(r.out, "| pcg | block_jacobi |") && strstr(r.out, "| pcg | amg |") && strstr(r.out, "| direct | - |"));
    CHECK(!gpu || (strstr(r.out, "| gpu | chebyshev |") && strstr(r.out, "it has no GPU cells") &&
                   !strstr(r.out, "| gpu | direct |")));
    csv_parse(&c, csv_path);
    check_header(&c, stab_cols, (int)(sizeof stab_cols / sizeof stab_cols[0]));
    /* solvers (PCG twice: block_jacobi, amg) x steps x stiffness x mass; the GPU: no direct solver, no AMG */
    CHECK_EQ_INT(c.n_rows, (5 + (gpu ? 3 : 0)) * 3 * n_k * 2);
    int free_fall_cells = 0, gpu_rows = 0;
    for (int row = 0; row < c.n_rows; ++row) {
        const int on_gpu = !strcmp(get(&c, row, "backend"), "gpu");
        CHECK(on_gpu || !strcmp(get(&c, row, "backend"), "cpu"));
        gpu_rows += on_gpu;
        if (on_gpu) CHECK(strcmp(get(&c, row, "solver"), "direct") != 0 && strcmp(get(&c, row, "preconditioner"), "amg") != 0);
        CHECK(!strcmp(get(&c, row, "preconditioner"), strcmp(get(&c, row, "solver"), "pcg") ? "-" : get(&c, row, "preconditioner")));
        CHECK(!strcmp(get(&c, row, "integrator"), "be") && num(&c, row, "newton_iterations") == 1);
        /* the physics below holds for every solver on both backends */
        const int physics = 1;
        const char* out = get(&c, row, "outcome");
        const int failed = !strcmp(out, "failed"), recovered = !strcmp(out, "recovered");
        CHECK(failed || recovered || !strcmp(out, "survived"));
        CHECK(failed == (get(&c, row, "reason")[0] != '\0' && strcmp(get(&c, row, "reason"), "rollbacks") != 0));
        CHECK(recovered == (!failed && num(&c, row, "rollbacks") > 0));
        const double frames = num(&c, row, "frames"), asked = num(&c, row, "frames_asked");
        CHECK(frames >= 1 && frames <= asked);
        CHECK(failed || frames == asked);
        CHECK(!strcmp(get(&c, row, "scene"), "sheet12") && num(&c, row, "particles") == 144);
        const double strain = num(&c, row, "max_strain");
        CHECK(failed || (isfinite(strain) && strain <= 0.5));
        /* A flat sheet at rest: no spring resists vertical motion in the linearised step, so every
         * free particle falls g h^2 in the first step and a pinned corner's edge spring (rest
         * 1/11 m) would stretch to sqrt(rest^2 + (g h^2)^2): with 1/12 s a strain of 25%, energy
         * the step did not have. The step's energy check rolls that back and retries in smaller
         * pieces: every 1/12 s cell recovers, and stays well below the free-fall strain. */
        if (physics && !strcmp(get(&c, row, "step_s"), "1/12")) {
            const double h = 1.0 / 12, drop = 9.81 * h * h, rest = 1.0 / 11;
            CHECK(recovered && num(&c, row, "rollbacks") >= 1);
            CHECK(strain < 0.5 * (sqrt(1 + drop * drop / (rest * rest)) - 1));
            ++free_fall_cells;
        }
        /* small steps of the default cloth survive with every solver */
        if (physics && !strcmp(get(&c, row, "step_s"), "1/60") && num(&c, row, "stiffness_x") == 1) CHECK(!failed);
    }
    CHECK_EQ_INT(gpu_rows, gpu ? 3 * 3 * n_k * 2 : 0);
    CHECK_EQ_INT(free_fall_cells, (5 + (gpu ? 3 : 0)) * n_k * 2);
    CHECK(png_ok(png_path, 400, 300));
}

/* ---- peers: Weft beside Blender's cloth ---- */

/* 1 when an executable `blender` is on PATH (as `weft bench peers` looks for it). */
static int blender_on_path(void) {
    const char* path = getenv("PATH");
    char buf[1024];
    for (const char* p = path ? path : ""; *p;) {
        const char* colon = strchr(p, ':');
        int len = colon ? (int)(colon - p) : (int)strlen(p);
        snprintf(buf, sizeof buf, "%.*s/blender", len, p);
        if (len > 0 && access(buf, X_OK) == 0) return 1;
        if (!colon) break;
        p = colon + 1;
    }
    return 0;
}

/* What needs no Blender: help, usage errors, and the message when Blender is missing. */
static void test_peers_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "weft bench peers") != NULL);
    ts_run_cli("bench peers --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "--blender") && strstr(r.out, "--timeout") &&
          strstr(r.out, "Blender / Weft") && strstr(r.out, "5 quality steps"));
    ts_run_cli("bench peers --frames 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --frames: '0'") != NULL);
    ts_run_cli("bench peers --substeps 1,,2", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench peers --timeout -1", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench peers --blender", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--blender needs a value") != NULL);
    ts_run_cli("bench peers --quick --plot peers.png", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "draws no plot") != NULL);
    ts_run_cli("bench peers --quick --quiet --blender /nonexistent/blender", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "'/nonexistent/blender' is not an executable file") != NULL);
    /* no blender on PATH: said on stderr and in the Markdown; Weft's rows alone (its scene rows and
     * the defaults row), Blender's columns "-" */
    const char* path = getenv("PATH");
    char saved[4096];
    snprintf(saved, sizeof saved, "%s", path ? path : "");
    setenv("PATH", "/nonexistent", 1);
    ts_run_cli("bench peers --quick --quiet --preconds block_jacobi", &r);
    setenv("PATH", saved, 1);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.err, "blender is not installed") && strstr(r.err, "Weft's rows only"));
    CHECK(strstr(r.out, "**No Blender here**") != NULL);
    CHECK(strstr(r.out, "| sheet12 | 144 | 1 | ") && strstr(r.out, "| sheet12 | 144 | default | "));
    CHECK(strstr(r.out, "| sheet12 | - | ") != NULL); /* the per-scene summary: no Blender ms */
}

/* What needs Blender: its failures reported, and the quick run. */
static void test_peers_blender_errors(void) {
    static ts_cli_result r;
    ts_run_cli("bench peers --quick --quiet --script /nonexistent/driver.py", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "cannot read the Blender driver script /nonexistent/driver.py") != NULL);
    ts_run_cli("bench peers --quick --quiet --timeout 0.01", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "did not finish within 0.01 s") != NULL);
    /* a script that fails: Blender's exit status and its last words */
    const char* bad = ts_write_tmp("peers_bad_driver.py", "raise RuntimeError('driver broke on purpose')\n");
    char args[1024];
    snprintf(args, sizeof args, "bench peers --quick --quiet --script '%s'", bad);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "blender exited with status 1") && strstr(r.err, "driver broke on purpose"));
    ts_run_cli("bench peers --quick --quiet --scenes blanket9", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "unknown scene 'blanket9'") != NULL);
}

static const char* const peers_cols[] = {
    "backend", "scene", "particles", "frames", "weft_threads", "blender_threads", "weft_solver", "weft_substeps",
    "weft_ms_per_frame", "blender_ms_per_frame", "ratio_blender_over_weft", "weft_drop_m", "blender_drop_m",
    "blender_pin_drift_m", "blender_version", "notes", "weft_config", "weft_preconditioner", "weft_integrator",
    "weft_newton_iterations", "weft_line_search", "weft_iterations_per_solve", "weft_ms_precond_per_solve"};

static void test_peers_quick(int gpu) {
    static ts_cli_result r;
    static csv c;
    char args[2048], csv_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_peers.csv"));
    remove(csv_path);
    snprintf(args, sizeof args, "bench peers --quick --quiet --substeps 1,2 --preconds block_jacobi --csv '%s'%s", csv_path,
             gpu ? " --backend cpu,gpu" : "");
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, peers_cols, (int)(sizeof peers_cols / sizeof peers_cols[0]));
    /* the GPU's rows after the CPU's, beside the same Blender run, then the library's defaults (CPU) */
    CHECK_EQ_INT(c.n_rows, gpu ? 5 : 3);
    for (int row = 0; row < c.n_rows; ++row) {
        const int defaults = row == c.n_rows - 1;
        const int substeps = defaults ? 1 : row % 2 + 1; /* defaults: at most the fall of 1 substep, below */
        CHECK(!strcmp(get(&c, row, "backend"), row < 2 || defaults ? "cpu" : "gpu"));
        CHECK(!strcmp(get(&c, row, "weft_config"), defaults ? "defaults" : "scene"));
        CHECK(!strcmp(get(&c, row, "weft_preconditioner"), defaults ? "default" : "block_jacobi"));
        CHECK(num(&c, row, "weft_iterations_per_solve") > 0);
        CHECK(!strcmp(get(&c, row, "blender_ms_per_frame"), get(&c, row % 2, "blender_ms_per_frame")));
        CHECK(!strcmp(get(&c, row, "scene"), "sheet12") && num(&c, row, "particles") == 144);
        CHECK(num(&c, row, "frames") == 10 &&
              (defaults ? !strcmp(get(&c, row, "weft_substeps"), "default") : num(&c, row, "weft_substeps") == substeps));
        CHECK(num(&c, row, "weft_threads") == 1 && num(&c, row, "blender_threads") == 1);
        CHECK(!strncmp(get(&c, row, "blender_version"), "3.", 2) || !strncmp(get(&c, row, "blender_version"), "4.", 2));
        const double w = num(&c, row, "weft_ms_per_frame"), b = num(&c, row, "blender_ms_per_frame");
        const double ratio = num(&c, row, "ratio_blender_over_weft");
        CHECK(isfinite(w) && w > 0 && isfinite(b) && b > 0);
        /* ms printed with 4 significant digits, the ratio with 3 */
        CHECK(fabs(ratio - b / w) <= 6e-3 * ratio);
        /* Blender's pinned vertices are the pinned particles (same vertex order): they stay put */
        CHECK(num(&c, row, "blender_pin_drift_m") < 1e-4);
        /* Both cloths fall, and no faster than a free particle under each one's own time stepping:
         * Weft, backward Euler with h = 1 / (30 substeps): g h^2 n (n + 1) / 2 after n substeps;
         * Blender, 5 steps of 1/5 frame per frame with gravity x 0.001 (frame units). */
        const int n = 10 * substeps;
        const double h = 1.0 / (30.0 * substeps);
        const double weft_fall = 9.81 * h * h * n * (n + 1) / 2;
        const double blender_fall = 9.81e-3 * 0.04 * 50 * 51 / 2;
        const double wd = num(&c, row, "weft_drop_m"), bd = num(&c, row, "blender_drop_m");
        CHECK(wd > 0.1 && wd <= weft_fall);
        CHECK(bd > 0.1 && bd <= blender_fall);
        if (!(wd > 0.1 && wd <= weft_fall && bd > 0.1 && bd <= blender_fall))
            fprintf(stderr, "  drops: weft %g (free fall %g), blender %g (free fall %g)\n", wd, weft_fall, bd,
                    blender_fall);
    }
    CHECK(strstr(r.out, "## weft bench peers") && strstr(r.out, "quality=5") && strstr(r.out, "Blender 3."));
    CHECK(strstr(r.out, "| scene | particles | Weft substeps | Weft ms/frame | Blender ms/frame | Blender / Weft |") !=
          NULL);
    CHECK(gpu == (strstr(r.out, "| backend | scene |") != NULL));
    CHECK(strstr(r.out, "| scene | Blender ms/frame | Weft defaults ms/frame | Blender / Weft | >= 10 x |") != NULL);
    int table_lines = 0;
    for (const char* p = r.out; (p = strstr(p, "\n| ")) != NULL; ++p) ++table_lines;
    CHECK_EQ_INT(table_lines, 2 + c.n_rows + 1); /* the per-scene summary (header, sheet12), the table */
}

/* ---- torture ---- */

static void test_torture_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench --help", &r);
    CHECK(strstr(r.out, "weft bench torture") != NULL);
    ts_run_cli("bench torture --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--case-timeout") && strstr(r.out, "--kinds") && strstr(r.out, "accepted_nonfinite") &&
          strstr(r.out, "state_changed") && strstr(r.out, "--no-fork"));
    ts_run_cli("bench torture --kinds spin,wobble", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --kinds") != NULL);
    ts_run_cli("bench torture --kinds spin,", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench torture --cases 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench torture --seed -1", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench torture --case", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--case needs a value") != NULL);
    ts_run_cli("bench torture --quick --plot x.png", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench torture --quick --quiet --cases 7 --md /nonexistent/dir/t.md", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "cannot write /nonexistent/dir/t.md") != NULL);
}

static const char* const torture_cols[] = {"kind",  "case",   "seed",     "outcome", "defect", "status",
                                           "where", "calls", "frames", "vertices", "detail"};
static const char* const torture_kinds[] = {"random_mesh", "teleport", "spin", "nan_inject", "zero_area",
                                            "one_particle", "extreme"};
static const char* const torture_outcomes[] = {"ok", "rejected", "step_failed", "nonfinite", "state_changed",
                                               "empty_message", "accepted_nonfinite", "crash", "hang"};

static int index_of(const char* s, const char* const* list, int n) {
    for (int k = 0; k < n; ++k)
        if (!strcmp(s, list[k])) return k;
    return -1;
}

static void test_torture_quick(void) {
    static ts_cli_result r;
    static csv c, one;
    char args[4096], csv_path[512], md_path[512], one_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_torture.csv"));
    snprintf(md_path, sizeof md_path, "%s", ts_tmp_path("bench_torture.md"));
    snprintf(one_path, sizeof one_path, "%s", ts_tmp_path("bench_torture_one.csv"));
    remove(csv_path);
    remove(md_path);
    snprintf(args, sizeof args, "bench torture --quick --quiet --csv '%s' --md '%s'", csv_path, md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, torture_cols, (int)(sizeof torture_cols / sizeof torture_cols[0]));
    CHECK_EQ_INT(c.n_rows, 140);
    int per_kind[7] = {0}, per_outcome[9] = {0};
    for (int row = 0; row < c.n_rows; ++row) {
        const int kind = index_of(get(&c, row, "kind"), torture_kinds, 7);
        const int out = index_of(get(&c, row, "outcome"), torture_outcomes, 9);
        CHECK(kind >= 0 && out >= 0);
        if (kind < 0 || out < 0) continue;
        ++per_kind[kind];
        ++per_outcome[out];
        CHECK(num(&c, row, "case") == row && kind == row % 7); /* cases cycle through the kinds */
        CHECK(num(&c, row, "defect") == 0 && out <= 2);
        CHECK(num(&c, row, "calls") >= 1);
        const int has_status = get(&c, row, "status")[0] != '\0';
        /* every refused input has a status and a message; an ok case has neither */
        CHECK(out == 0 ? !has_status : has_status && get(&c, row, "detail")[0] != '\0');
        if (out == 2) CHECK(!strcmp(get(&c, row, "status"), "WEFT_ERROR_STEP_FAILED"));
        if (kind == 3) { /* nan_inject: the NaN or Inf is always refused, as NONFINITE */
            CHECK(out == 1);
            CHECK(!strcmp(get(&c, row, "status"), "WEFT_ERROR_NONFINITE"));
        }
    }
    for (int k = 0; k < 7; ++k) CHECK_EQ_INT(per_kind[k], 20);
    CHECK_EQ_INT(per_outcome[0] + per_outcome[1] + per_outcome[2], 140);
    CHECK(per_outcome[0] > 0 && per_outcome[1] > 0);
    static char md[1 << 16];
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, "140 cases, 0 defects") != NULL);
    CHECK(strstr(md, "| kind | cases | ok | rejected | step_failed | nonfinite |") != NULL);
    for (int k = 0; k < 7; ++k) {
        char line[96];
        snprintf(line, sizeof line, "\n| %s | 20 |", torture_kinds[k]);
        CHECK(strstr(md, line) != NULL);
    }
    CHECK(strstr(md, "| all | 140 |") != NULL);
    /* --case reruns one case exactly as the full run ran it (its own process, or this one) */
    for (int mode = 0; mode < 2; ++mode) {
        const int which = mode ? 10 : 7; /* nan_inject, random_mesh */
        snprintf(args, sizeof args, "bench torture --quick --quiet --kinds %s --case %d --csv '%s'%s",
                 torture_kinds[which % 7], which, one_path, mode ? " --no-fork" : "");
        ts_run_cli(args, &r);
        CHECK_EQ_INT(r.rc, 0);
        csv_parse(&one, one_path);
        CHECK_EQ_INT(one.n_rows, 1);
        static const char* const same[] = {"kind", "case", "outcome", "status", "where", "calls", "frames",
                                           "vertices", "detail"};
        for (int k = 0; k < 9; ++k) CHECK(!strcmp(get(&one, 0, same[k]), get(&c, which, same[k])));
    }
    /* in this process (LeakSanitizer sees these cases) */
    ts_run_cli("bench torture --quick --quiet --no-fork --cases 21 --seed 5", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "21 cases, 0 defects") != NULL);
}

static const char* const skip_cols[] = {
    "backend", "scene", "particles", "config", "frames", "warmup_frames", "iterations_per_substep",
    "not_converged", "contacts", "asleep_frames", "positions_unchanged", "ms_forces", "ms_assemble", "ms_solve",
    "ms_collide", "ms_integrate", "ms_total", "ratio_to_baseline", "ms_saved", "skipped"};

static void test_skip_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench skip --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "asleep") && strstr(r.out, "--backend LIST"));
    ts_run_cli("bench skip --backend gpu,tpu", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --backend") != NULL);
    ts_run_cli("bench skip --frames 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --frames") != NULL);
    ts_run_cli("bench skip --quick --plot x.png", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench skip --quick --quiet --scene blanket9", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "unknown scene 'blanket9'") != NULL);
}

static void test_skip_quick(int gpu) {
    static ts_cli_result r;
    static csv c;
    char args[4096], csv_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_skip.csv"));
    remove(csv_path);
    snprintf(args, sizeof args, "bench skip --quick --quiet --csv '%s'%s", csv_path, gpu ? " --backend cpu,gpu" : "");
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    CHECK(strstr(r.out, gpu ? "| backend | configuration |" : "| configuration |") != NULL);
    CHECK(strstr(r.out, gpu ? "backends: CPU (core's wc_step_frame) and GPU" : "backend: CPU (core's wc_step_frame)"));
    CHECK(strstr(r.out, "positions bit-identical") != NULL);
    CHECK(!gpu || strstr(r.out, "GPU: Asleep: the cloth fell asleep after"));
    csv_parse(&c, csv_path);
    check_header(&c, skip_cols, (int)(sizeof skip_cols / sizeof skip_cols[0]));
    static const char* const configs[] = {"baseline", "+ air drag", "+ wind", "+ far collider", "+ contact",
                                          "+ far mesh", "+ mesh contact", "+ moving pins", "+ self-collision",
                                          "full cap", "asleep"};
    enum { NC = 11 };
    const int nb = gpu ? 2 : 1;
    CHECK_EQ_INT(c.n_rows, NC * nb); /* the CPU's rows, then the GPU's */
    for (int row = 0; row < c.n_rows && row < NC * nb; ++row) {
        CHECK(!strcmp(get(&c, row, "config"), configs[row % NC]));
        CHECK(!strcmp(get(&c, row, "backend"), row < NC ? "cpu" : "gpu") && !strcmp(get(&c, row, "scene"), "sheet16"));
        CHECK(num(&c, row, "particles") == 256 && num(&c, row, "frames") == 20);
        for (int k = 11; k <= 16; ++k) CHECK(num(&c, row, skip_cols[k]) >= 0);
        CHECK(isfinite(num(&c, row, "ratio_to_baseline")));
        const int asleep = row % NC == NC - 1;
        CHECK(num(&c, row, "asleep_frames") == (asleep ? 20 : 0));
        CHECK(asleep ? num(&c, row, "iterations_per_substep") == 0 : num(&c, row, "iterations_per_substep") > 0);
        if (asleep) {
            CHECK(num(&c, row, "positions_unchanged") == 1);
            CHECK(num(&c, row, "warmup_frames") > 0);
            CHECK(num(&c, row, "ms_solve") == 0 && num(&c, row, "ms_forces") == 0);
        } else {
            CHECK(num(&c, row, "positions_unchanged") == 0);   /* awake, the sheet swings */
        }
    }
    for (int b = 0; b < nb; ++b) { /* each backend against its own baseline */
        const int o = NC * b;
        CHECK(num(&c, o, "ratio_to_baseline") == 1 && !strcmp(get(&c, o, "ms_saved"), "-"));
        CHECK(num(&c, o + 3, "contacts") == 0 && num(&c, o + 4, "contacts") > 0);
        /* the far mesh finds nothing: the baseline's motion, its refit and queries in collide;
           the mesh sphere under the cloth holds it as the analytic one does (the GPU's mesh rows
           are the baseline again: it has no mesh colliders) */
        CHECK(num(&c, o + 5, "contacts") == 0);
        CHECK(num(&c, o + 5, "iterations_per_substep") == num(&c, o, "iterations_per_substep"));
        CHECK(b > 0 || num(&c, o + 5, "ms_collide") > num(&c, o, "ms_collide"));
        CHECK(b > 0 ? num(&c, o + 6, "contacts") == 0 : num(&c, o + 6, "contacts") > 0);
        /* self-collision on a sheet that never touches itself: the same motion as the baseline
           (the GPU's row is the baseline again: it has no self-collision) */
        CHECK(num(&c, o + 8, "iterations_per_substep") == num(&c, o, "iterations_per_substep"));
        CHECK(b > 0 || num(&c, o + 8, "ms_collide") > num(&c, o, "ms_collide"));
        /* tolerance 0: every solve runs to the cap of 300 and counts as not converged */
        CHECK(num(&c, o + 9, "iterations_per_substep") == 300 && num(&c, o + 9, "not_converged") == 20);
        CHECK(num(&c, o, "not_converged") == 0);
        /* a far collider changes nothing of the motion: the same iterations as the baseline */
        CHECK(num(&c, o + 3, "iterations_per_substep") == num(&c, o, "iterations_per_substep"));
    }
}

/* A GPU context that cannot be made: a clear message and exit 1, nothing on stdout. */
static void test_gpu_unavailable(const char* sub) {
    static ts_cli_result r;
    char args[256];
    snprintf(args, sizeof args, "bench %s --quick --quiet --backend cpu,gpu", sub);
    setenv("WEFT_EGL_DEVICE", "no-such-device", 1);
    ts_run_cli(args, &r);
    unsetenv("WEFT_EGL_DEVICE");
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "--backend gpu: cannot create a headless GL context") != NULL);
    if (!strstr(r.err, "--backend gpu")) fprintf(stderr, "stderr: %s\n", r.err);
    CHECK(r.out[0] == '\0');
}

/* RUN_TEST takes functions of no argument. */
static void test_accuracy_quick_cpu(void) { test_accuracy_quick(0); }

/* --ref-displace: the reference from a displaced start, a `reference_displaced` row per distance
 * and the Markdown's sensitivity table. Over 0.3 s the 8 x 8 sheet is still linear in so small a
 * change of its start: the difference at the end is proportional to the displacement (1e-6 m
 * against 1e-9 m: ~1000x), non-zero (the displacement was applied) and of the displacement's
 * size (not amplified or lost). */
static void test_accuracy_displaced(void) {
    static ts_cli_result r;
    static csv c;
    static char md[1 << 16];
    char args[2048], csv_path[512], md_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_accuracy_displaced.csv"));
    snprintf(md_path, sizeof md_path, "%s", ts_tmp_path("bench_accuracy_displaced.md"));
    remove(csv_path);
    remove(md_path);
    snprintf(args, sizeof args,
             "bench accuracy --scenes sheet8 --ref-only --no-ref-check --ref-displace 1e-9,1e-6 --seconds 0.3 "
             "--threads 1 --quiet --csv '%s' --md '%s'",
             csv_path, md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    csv_parse(&c, csv_path);
    check_header(&c, acc_cols, (int)(sizeof acc_cols / sizeof acc_cols[0]));
    CHECK_EQ_INT(c.n_rows, 3);
    if (c.n_rows != 3) return;
    CHECK(!strcmp(get(&c, 0, "role"), "reference") && num(&c, 0, "traj_err_rms") == 0);
    const double diag = sqrt(2.0), small = num(&c, 1, "traj_err_rms"), large = num(&c, 2, "traj_err_rms");
    for (int k = 1; k <= 2; ++k) {
        CHECK(!strcmp(get(&c, k, "role"), "reference_displaced"));
        CHECK(strstr(get(&c, k, "solver"), k == 1 ? "displaced 1e-09 m" : "displaced 1e-06 m") != NULL);
        CHECK(num(&c, k, "substeps") == 8 && !strcmp(get(&c, k, "integrator"), "trbdf2"));
        CHECK(num(&c, k, "traj_err_max") >= num(&c, k, "traj_err_rms"));
    }
    CHECK(small > 0 && large > 0);
    CHECK(large / small > 500 && large / small < 2000);
    CHECK(large > 0.01 * 1e-6 / diag && large < 10 * 1e-6 / diag);
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, "How sensitive is the scene?") && strstr(md, "| sheet8 | 1e-06 |"));
    /* --threads 1 holds CHOLMOD's OpenBLAS to one thread too (cli_blas_threads) */
    CHECK(strstr(md, "1 OpenMP thread(s), OpenBLAS: 1 thread(s).") || strstr(md, "1 OpenMP thread(s), BLAS: not OpenBLAS."));
    /* the check's verdict: a halving figure within 2x of a displaced start's difference is marked as
     * at the scene's floor (here a 1 mm displacement, far above 0.3 s's halving figure) */
    snprintf(args, sizeof args,
             "bench accuracy --scenes sheet8 --ref-only --ref-displace 1e-3 --seconds 0.3 --threads 1 --quiet "
             "--md '%s'",
             md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, "| sheet8 | 8 | 16 |") && strstr(md, "; at the scene's floor, "));
    /* none: no displaced run, no floor; the full runs' default is one at 1e-8 m (usage) */
    snprintf(args, sizeof args,
             "bench accuracy --scenes sheet8 --ref-only --ref-displace none --seconds 0.3 --threads 1 --quiet "
             "--csv '%s' --md '%s'",
             csv_path, md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    csv_parse(&c, csv_path);
    CHECK_EQ_INT(c.n_rows, 2); /* the reference and its check */
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, "| sheet8 | 8 | 16 |") && !strstr(md, "floor") && !strstr(md, "How sensitive"));
    ts_run_cli("bench accuracy --help", &r);
    CHECK(strstr(r.out, "(default 1e-8; --quick: none; none:") != NULL);
    ts_run_cli("bench accuracy --ref-displace 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --ref-displace 1e-8,0.5", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --ref-displace -1e-8", &r);
    CHECK_EQ_INT(r.rc, 2);
}
static void test_accuracy_quick_gpu(void) { test_accuracy_quick(1); }
static void test_stability_quick_cpu(void) { test_stability_quick(0); }
static void test_stability_quick_gpu(void) { test_stability_quick(1); }
static void test_skip_quick_cpu(void) { test_skip_quick(0); }
static void test_skip_quick_gpu(void) { test_skip_quick(1); }
static void test_peers_quick_cpu(void) { test_peers_quick(0); }
static void test_peers_quick_gpu(void) { test_peers_quick(1); }
static void test_accuracy_gpu_unavailable(void) { test_gpu_unavailable("accuracy"); }
static void test_stability_gpu_unavailable(void) { test_gpu_unavailable("stability"); }
static void test_skip_gpu_unavailable(void) { test_gpu_unavailable("skip"); }

int main(int argc, char** argv) {
    const char* which = argc > 1 ? argv[1] : "";
    if (argc > 2 && !strcmp(argv[2], "gpu")) { /* the quick run on both backends */
        if (!strcmp(which, "accuracy")) {
            RUN_TEST(test_accuracy_gpu_unavailable);
            RUN_TEST(test_accuracy_quick_gpu);
        } else if (!strcmp(which, "stability")) {
            RUN_TEST(test_stability_gpu_unavailable);
            RUN_TEST(test_stability_quick_gpu);
        } else if (!strcmp(which, "skip")) {
            RUN_TEST(test_skip_gpu_unavailable);
            RUN_TEST(test_skip_quick_gpu);
        } else if (!strcmp(which, "peers")) {
            if (!blender_on_path()) {
                printf("SKIPPED: `blender` is not installed (apt-get install blender; .ci/deps.sh does)\n");
                return 77;
            }
            RUN_TEST(test_peers_quick_gpu);
        } else {
            fprintf(stderr, "usage: %s accuracy|stability|peers|skip gpu\n", argv[0]);
            return 2;
        }
        return TEST_SUMMARY();
    }
    if (!strcmp(which, "accuracy")) {
        RUN_TEST(test_help);
        RUN_TEST(test_accuracy_usage);
        RUN_TEST(test_accuracy_quick_cpu);
        RUN_TEST(test_accuracy_displaced);
    } else if (!strcmp(which, "stability")) {
        RUN_TEST(test_help);
        RUN_TEST(test_stability_usage);
        RUN_TEST(test_stability_quick_cpu);
    } else if (!strcmp(which, "peers")) {
        RUN_TEST(test_peers_usage);
        if (!blender_on_path()) {
            if (TEST_SUMMARY() != 0) return 1;
            printf("SKIPPED: `blender` is not installed (apt-get install blender; .ci/deps.sh does)\n");
            return 77;
        }
        RUN_TEST(test_peers_blender_errors);
        RUN_TEST(test_peers_quick_cpu);
    } else if (!strcmp(which, "torture")) {
        RUN_TEST(test_torture_usage);
        RUN_TEST(test_torture_quick);
    } else if (!strcmp(which, "skip")) {
        RUN_TEST(test_skip_usage);
        RUN_TEST(test_skip_quick_cpu);
    } else {
        fprintf(stderr, "usage: %s accuracy|stability|peers|torture|skip [gpu]\n", argv[0]);
        return 2;
    }
    return TEST_SUMMARY();
}
