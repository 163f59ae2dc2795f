/* `weft bench skip --quick`, run as a user would (WEFT_CLI): one row per configuration in order,
 * the asleep row slept through every timed frame with 0 iterations and bit-identical positions,
 * the full-cap row ran every solve to the cap, the contact row has contacts and the far-collider
 * row none. (gpu, second argument) the same with --backend cpu,gpu, and a GPU context that cannot
 * be made is a clear failure (exit 1).
 *
 *   check_weft_bench_skip [gpu] */
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
    CHECK(strstr(r.out, gpu ? "backends: CPU (weft_cloth_step) and GPU" : "backend: CPU (weft_cloth_step)"));
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
        /* self-collision on a sheet that never touches itself: the same motion as the baseline */
        CHECK(num(&c, o + 8, "iterations_per_substep") == num(&c, o, "iterations_per_substep"));
        CHECK(b > 0 || num(&c, o + 8, "ms_collide") > num(&c, o, "ms_collide"));
        /* tolerance 0: every solve runs to the cap of 300 and counts as not converged */
        CHECK(num(&c, o + 9, "iterations_per_substep") == 300 && num(&c, o + 9, "not_converged") == 20);
        CHECK(num(&c, o, "not_converged") == 0);
        /* a far collider changes nothing of the motion: the same iterations as the baseline */
        CHECK(num(&c, o + 3, "iterations_per_substep") == num(&c, o, "iterations_per_substep"));
    }
}

static void test_skip_quick_cpu(void) { test_skip_quick(0); }
static void test_skip_quick_gpu(void) { test_skip_quick(1); }
static void test_skip_gpu_unavailable(void) { test_gpu_unavailable("skip"); }

int main(int argc, char** argv) {
    if (argc > 1 && !strcmp(argv[1], "gpu")) {
        RUN_TEST(test_skip_gpu_unavailable);
        RUN_TEST(test_skip_quick_gpu);
    } else {
        RUN_TEST(test_skip_usage);
        RUN_TEST(test_skip_quick_cpu);
    }
    return TEST_SUMMARY();
}
