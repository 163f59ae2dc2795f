/* `weft bench peers --quick`: Weft beside Blender's cloth on sheet12, run as a user would
 * (WEFT_CLI): both ms/frame positive, the ratio theirs, Blender's pinned vertices unmoved (its
 * vertices are Weft's particles), and each cloth's lowest point fallen, but no further than a free
 * particle under that solver's time stepping. Without blender on PATH it checks what needs none
 * and exits 77 (skipped). (gpu, second argument) Weft's rows on both backends. And --matched: a
 * small sheet's errors against each simulator's own reference, finite, ordered and 0 for the
 * references themselves (the metric itself: check_bench_traj_error.c).
 *
 *   check_weft_bench_peers [gpu] */
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

static const char* const matched_cols[] = {"scene", "particles", "frames", "simulator", "setting", "role",
                                           "steps_per_frame", "threads", "cpu_ms_per_frame", "ms_per_frame",
                                           "error_pct_all_frames",
                                           "error_pct_end", "iterations_per_solve", "notes"};

/* The row of a simulator's setting, or -1. */
static int matched_row(const csv* c, const char* sim, const char* setting) {
    for (int row = 0; row < c->n_rows; ++row)
        if (!strcmp(get(c, row, "simulator"), sim) && !strcmp(get(c, row, "setting"), setting)) return row;
    fprintf(stderr, "no row %s / %s\n", sim, setting);
    return -1;
}

/* --matched, usage and no Blender: Weft's rows alone, its reference's own error 0. */
static void test_matched_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench peers --help", &r);
    CHECK(strstr(r.out, "--matched") && strstr(r.out, "--ref-quality") && strstr(r.out, "trbdf2_n3_s2") &&
          strstr(r.out, "bdf2_n1,") && strstr(r.out, "trbdf2_n3_tight"));
    ts_run_cli("bench peers --matched --settings defaults,nope", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --settings: 'defaults,nope'") != NULL);
    ts_run_cli("bench peers --matched --ref-quality 1", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench peers --matched --backend gpu", &r);
    CHECK_EQ_INT(r.rc, 2);
    const char* path = getenv("PATH");
    char saved[4096];
    snprintf(saved, sizeof saved, "%s", path ? path : "");
    setenv("PATH", "/nonexistent", 1);
    ts_run_cli("bench peers --matched --quiet --scenes sheet8 --frames 5 --settings defaults --ref-substeps 2", &r);
    setenv("PATH", saved, 1);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "**No Blender here**") && !strstr(r.out, "| Blender |"));
    CHECK(strstr(r.out, "| sheet8 | 64 | Weft | defaults | run | 1 | ") != NULL);
    CHECK(strstr(r.out, "| sheet8 | 64 | Weft | TR-BDF2 Newton 3 tol. 1e-8 at 2 substeps | reference | 2 | ") != NULL);
    CHECK(strstr(r.out, "| sheet8 | Weft | TR-BDF2 Newton 3 tol. 1e-8 at 2 substeps | TR-BDF2 Newton 3 tol. 1e-8 at 1 "
                        "substeps | ") != NULL);
}

/* --matched's screening settings reach the def: without Blender, TR-BDF2 Newton 2's iterations a
 * solve grow from the library's (1e-2 first solves, 1e-4 the later) to forcing 0 (every solve to
 * 1e-4) to every solve to 1e-6 on the 32 x 32 sheet (multigrid; below 800 particles the
 * library already takes forcing 0), and BDF2 Newton 1 runs with a finite error. */
static void test_matched_settings_applied(void) {
    static ts_cli_result r;
    static csv c;
    char args[1024], csv_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_peers_matched_settings.csv"));
    remove(csv_path);
    snprintf(args, sizeof args,
             "bench peers --matched --quiet --scenes sheet32 --frames 5 --settings trbdf2_n2,trbdf2_n2_f0,trbdf2_n2_tight,bdf2_n1 "
             "--ref-substeps 2 --csv '%s'", csv_path);
    const char* path = getenv("PATH");
    char saved[4096];
    snprintf(saved, sizeof saved, "%s", path ? path : "");
    setenv("PATH", "/nonexistent", 1);
    ts_run_cli(args, &r);
    setenv("PATH", saved, 1);
    CHECK_EQ_INT(r.rc, 0);
    csv_parse(&c, csv_path);
    const int n2 = matched_row(&c, "Weft", "TR-BDF2 Newton 2");
    const int f0 = matched_row(&c, "Weft", "TR-BDF2 Newton 2 forcing 0");
    const int tight = matched_row(&c, "Weft", "TR-BDF2 Newton 2 tol. 1e-6 forcing 0");
    const int b1 = matched_row(&c, "Weft", "BDF2 Newton 1 (no line search)");
    if (n2 < 0 || f0 < 0 || tight < 0 || b1 < 0) {
        CHECK(!"a row is missing");
        return;
    }
    CHECK(num(&c, f0, "iterations_per_solve") > num(&c, n2, "iterations_per_solve"));
    CHECK(num(&c, tight, "iterations_per_solve") > num(&c, f0, "iterations_per_solve"));
    const double e = num(&c, b1, "error_pct_all_frames");
    CHECK(isfinite(e) && e > 0 && e < 50);
}

/* --matched on an 8 x 8 sheet for 30 frames (1 s): every row's error finite, each reference's
 * own 0, the coarser run of each simulator further from its reference than the finer one, the
 * references' checks closer than any run, and the verdict's lines. */
static void test_matched_smoke(void) {
    static ts_cli_result r;
    static csv c;
    char args[1024], csv_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_peers_matched.csv"));
    remove(csv_path);
    snprintf(args, sizeof args,
             "bench peers --matched --quiet --scenes sheet8 --frames 30 --qualities 5,20 --settings defaults,trbdf2_n3 "
             "--ref-substeps 8 --csv '%s'", csv_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, matched_cols, (int)(sizeof matched_cols / sizeof matched_cols[0]));
    CHECK_EQ_INT(c.n_rows, 8);   /* Blender 5, 20, 40 (check), 80 (reference); Weft 2 settings, 4, 8 */
    for (int row = 0; row < c.n_rows; ++row) {
        const double all = num(&c, row, "error_pct_all_frames"), end = num(&c, row, "error_pct_end");
        CHECK(isfinite(all) && all >= 0 && all < 50 && isfinite(end) && end >= 0 && end < 50);
        CHECK(num(&c, row, "ms_per_frame") > 0 && num(&c, row, "cpu_ms_per_frame") > 0);
        CHECK(num(&c, row, "threads") == 1 && num(&c, row, "frames") == 30);
        CHECK(num(&c, row, "particles") == 64);
        if (!strcmp(get(&c, row, "role"), "reference")) CHECK(all == 0 && end == 0);
        else CHECK(all > 0);
    }
    const int q5 = matched_row(&c, "Blender", "quality 5"), q20 = matched_row(&c, "Blender", "quality 20");
    const int q40 = matched_row(&c, "Blender", "quality 40"), q80 = matched_row(&c, "Blender", "quality 80");
    const int wd = matched_row(&c, "Weft", "defaults"), wt = matched_row(&c, "Weft", "TR-BDF2 Newton 3");
    const int w4 = matched_row(&c, "Weft", "TR-BDF2 Newton 3 tol. 1e-8 at 4 substeps");
    const int w8 = matched_row(&c, "Weft", "TR-BDF2 Newton 3 tol. 1e-8 at 8 substeps");
    if (q5 < 0 || q20 < 0 || q40 < 0 || q80 < 0 || wd < 0 || wt < 0 || w4 < 0 || w8 < 0) {
        CHECK(!"a row is missing");
        return;
    }
    CHECK(!strcmp(get(&c, q40, "role"), "reference's check") && !strcmp(get(&c, q80, "role"), "reference"));
    CHECK(!strcmp(get(&c, w4, "role"), "reference's check") && !strcmp(get(&c, w8, "role"), "reference"));
#define ERR(row) num(&c, row, "error_pct_all_frames")
    CHECK(ERR(q5) > ERR(q20) && ERR(q20) > ERR(q40));   /* Blender converges in its quality */
    CHECK(ERR(wd) > ERR(wt) && ERR(wt) > ERR(w4));      /* backward Euler, TR-BDF2, 4 substeps at 1e-8 */
#undef ERR
    CHECK(strstr(r.out, "## weft bench peers --matched") && strstr(r.out, "Blender 3."));
    CHECK(strstr(r.out, "| scene | Blender quality | Blender error % | Blender CPU ms/frame | fastest Weft within it |") !=
          NULL);
    CHECK(strstr(r.out, "| sheet8 | 5 | ") && strstr(r.out, "| sheet8 | 20 | ") && strstr(r.out, ">= 10 x"));
    CHECK(strstr(r.out, "| sheet8 | Blender | quality 80 | quality 40 | ") != NULL);
    CHECK(strstr(r.out, "| reference's diagonal (m) | its motion % |") != NULL);
    CHECK(strstr(r.out, "Blender 1 (-t) with OMP_NUM_THREADS=1 as Blender saw it") != NULL);
    CHECK(strstr(r.out, "| sheet8 | Weft | TR-BDF2 Newton 3 tol. 1e-8 at 8 substeps | TR-BDF2 Newton 3 tol. 1e-8 at 4 "
                        "substeps | ") != NULL);
    int table_lines = 0;
    for (const char* p = r.out; (p = strstr(p, "\n| ")) != NULL; ++p) ++table_lines;
    CHECK_EQ_INT(table_lines, (1 + 2) + (1 + 2) + (1 + 8));   /* verdict, references' checks, the rows */
}

static void test_peers_quick_cpu(void) { test_peers_quick(0); }
static void test_peers_quick_gpu(void) { test_peers_quick(1); }

int main(int argc, char** argv) {
    const int gpu = argc > 1 && !strcmp(argv[1], "gpu");
    if (!gpu) RUN_TEST(test_peers_usage);
    if (!gpu) RUN_TEST(test_matched_usage);
    if (!gpu) RUN_TEST(test_matched_settings_applied);
    if (!blender_on_path()) {
        if (TEST_SUMMARY() != 0) return 1;
        printf("SKIPPED: `blender` is not installed (apt-get install blender; .ci/deps.sh does)\n");
        return 77;
    }
    if (gpu) {
        RUN_TEST(test_peers_quick_gpu);
    } else {
        RUN_TEST(test_peers_blender_errors);
        RUN_TEST(test_peers_quick_cpu);
        RUN_TEST(test_matched_smoke);
    }
    return TEST_SUMMARY();
}
