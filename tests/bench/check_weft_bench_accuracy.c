/* `weft bench accuracy --quick`, run as a user would (WEFT_CLI), so the command cannot rot. Nothing
 * about time is asserted. Checked: --help texts and usage errors; the CSV has the expected header
 * and one row per configuration with finite errors (the linear-solve error columns "-": that
 * measurement is tests/bench/bench_linear_error's); the Markdown table has a line per row; the
 * plot is a well-formed PNG (signature, chunk CRCs, IHDR first, IDAT, IEND last). Physics, from
 * outside the benchmark: the direct solver's trajectory error shrinks when its substeps double,
 * as backward Euler converges to the reference. (gpu, second argument) the same quick run with
 * --backend cpu,gpu: the CPU rows checked as above, the GPU rows beside them (no direct solver),
 * and a GPU context that cannot be made is a clear failure (exit 1).
 *
 *   check_weft_bench_accuracy [gpu] */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "check_bench_csv.h"
#include "check_weft_bench.h"
#include "test_support.h"

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
            /* the linear-solve error is bench_linear_error's (it needs the step's own system) */
            CHECK(!strcmp(get(&c, row, "lin_err_max"), "-") && !strcmp(get(&c, row, "lin_err_mean"), "-"));
            if (ref) continue;
            if (!strcmp(get(&c, row, "solver"), "direct")) {
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
    CHECK(strstr(md, gpu ? "backends: CPU (weft_cloth_step) and GPU (weft_cloth_step on "
                         : "backend: CPU (weft_cloth_step)") != NULL);
    CHECK(gpu == (strstr(md, "lin. err is not measured") != NULL));
    CHECK(strstr(md, "Is the reference converged in time?") && strstr(md, "| sheet16 | 8 | 16 | ") &&
          strstr(md, "| garment | 8 | 16 | "));
    int table_lines = 0;
    for (const char* p = md; (p = strstr(p, "\n| ")) != NULL; ++p) ++table_lines;
    /* the reference check's header and 3 scenes, then the table's header + rows ("|---" start "|-") */
    CHECK_EQ_INT(table_lines, 4 + c.n_rows + 1);
    CHECK(png_ok(png_path, 400, 300));
}

/* RUN_TEST takes functions of no argument. */
static void test_accuracy_quick_cpu(void) { test_accuracy_quick(0); }
static void test_accuracy_quick_gpu(void) { test_accuracy_quick(1); }
static void test_accuracy_gpu_unavailable(void) { test_gpu_unavailable("accuracy"); }

int main(int argc, char** argv) {
    if (argc > 1 && !strcmp(argv[1], "gpu")) {
        RUN_TEST(test_accuracy_gpu_unavailable);
        RUN_TEST(test_accuracy_quick_gpu);
    } else {
        RUN_TEST(test_help);
        RUN_TEST(test_accuracy_usage);
        RUN_TEST(test_accuracy_quick_cpu);
    }
    return TEST_SUMMARY();
}
