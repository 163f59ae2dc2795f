/* `weft bench stability --quick`, run as a user would (WEFT_CLI), so the command cannot rot.
 * Nothing about time is asserted. Checked: --help and usage errors; the CSV has the expected
 * header and one row per cell; the heat map is a well-formed PNG. Physics, from outside the
 * benchmark: a flat sheet's linearised first step is a free fall that would stretch a pinned
 * corner's spring to sqrt(1 + (g h^2 / rest)^2) - 1: the long steps must be rolled back and stay
 * well below it. (gpu, second argument) the same with --backend cpu,gpu, and a GPU context that
 * cannot be made is a clear failure (exit 1).
 *
 *   check_weft_bench_stability [gpu] */
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

static void test_stability_quick_cpu(void) { test_stability_quick(0); }
static void test_stability_quick_gpu(void) { test_stability_quick(1); }
static void test_stability_gpu_unavailable(void) { test_gpu_unavailable("stability"); }

int main(int argc, char** argv) {
    if (argc > 1 && !strcmp(argv[1], "gpu")) {
        RUN_TEST(test_stability_gpu_unavailable);
        RUN_TEST(test_stability_quick_gpu);
    } else {
        RUN_TEST(test_stability_usage);
        RUN_TEST(test_stability_quick_cpu);
    }
    return TEST_SUMMARY();
}
