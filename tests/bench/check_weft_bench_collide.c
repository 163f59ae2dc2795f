/* `weft bench collide --quick`, run as a user would (WEFT_CLI), so that it cannot rot. Nothing
 * about time is asserted. Checked: --help and usage errors; the CSV's header and one row per
 * (cloth size, body size) in order, each row's particle and triangle counts (the UV sphere's
 * 4 m (m - 1)), the sheet touching the body within the warm-up, finite non-negative stage
 * medians with collide + self and solve within the total and the share their ratio, min <= median
 * <= max; the error side (no penetration into the body, no self-intersection at the last frame);
 * the Markdown's table (a line per row) and its goal line (not run by --quick). With the argument
 * `gpu` (a build with the GPU backend) the same on `--backend cpu,gpu`: the CPU's rows, then the
 * GPU's, each checked alike.
 *
 *   check_weft_bench_collide [gpu] */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "check_bench_csv.h"
#include "test_support.h"

static void test_collide_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench collide --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "--cloth LIST") && strstr(r.out, "--body LIST") &&
          strstr(r.out, "30 %"));
    ts_run_cli("bench --help", &r);
    CHECK(strstr(r.out, "weft bench collide") != NULL);
    ts_run_cli("bench collide --cloth 2", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --cloth: '2'") != NULL);
    ts_run_cli("bench collide --body 10", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench collide --frames 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench collide --quick --plot c.png", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench collide --quick --backend tpu", &r);
    CHECK_EQ_INT(r.rc, 2);
}

static int g_gpu; /* also on the GPU backend */

static const char* const collide_cols[] = {
    "backend", "n", "particles", "body_triangles", "warmup_frames", "frames", "iterations_per_substep", "ms_total",
    "ms_collide", "ms_self", "ms_solve", "collision_share", "ms_total_min", "ms_total_max", "contacts",
    "self_proximity", "self_impacts", "self_zones", "self_unresolved", "max_penetration_mm",
    "self_intersections"};

static void test_collide_quick(void) {
    static ts_cli_result r;
    static csv c;
    static char md[1 << 16];
    char args[2048], csv_path[512], md_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_collide.csv"));
    snprintf(md_path, sizeof md_path, "%s", ts_tmp_path("bench_collide.md"));
    remove(csv_path);
    remove(md_path);
    snprintf(args, sizeof args, "bench collide --quick --quiet --backend %s --csv '%s' --md '%s'",
             g_gpu ? "cpu,gpu" : "cpu", csv_path, md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, collide_cols, (int)(sizeof collide_cols / sizeof collide_cols[0]));
    static const int cloth[] = {16, 24}, tris[] = {960, 5040}; /* --quick: bodies 1000, 5000 -> m 16, 36 */
    const int rows = g_gpu ? 8 : 4;
    CHECK_EQ_INT(c.n_rows, rows);
    for (int row = 0; row < c.n_rows && row < rows; ++row) {
        const int n = cloth[row % 4 / 2];
        CHECK(!strcmp(get(&c, row, "backend"), row < 4 ? "cpu" : "gpu"));
        CHECK(num(&c, row, "n") == n && num(&c, row, "particles") == n * n);
        CHECK(num(&c, row, "body_triangles") == tris[row % 2]);
        CHECK(num(&c, row, "warmup_frames") >= 1 && num(&c, row, "warmup_frames") <= 30);
        CHECK(num(&c, row, "frames") == 2 && num(&c, row, "iterations_per_substep") > 0);
        const double total = num(&c, row, "ms_total"), col = num(&c, row, "ms_collide");
        const double self = num(&c, row, "ms_self"), solve = num(&c, row, "ms_solve");
        CHECK(isfinite(total) && total > 0 && col > 0 && self > 0 && solve > 0);
        /* medians of per-frame stages, each frame's stages within its total */
        CHECK(col + self <= total * (1 + 1e-9) + 1e-3 && solve <= total * (1 + 1e-9) + 1e-3);
        CHECK(fabs(num(&c, row, "collision_share") - (col + self) / total) < 1e-3 + 1e-3 * (col + self) / total);
        CHECK(num(&c, row, "ms_total_min") <= total + 1e-3 && total <= num(&c, row, "ms_total_max") + 1e-3);
        CHECK(num(&c, row, "contacts") > 0);
        CHECK(num(&c, row, "self_unresolved") == 0);
        /* the error side: nothing inside the body, no crossing of the cloth */
        CHECK(num(&c, row, "max_penetration_mm") == 0);
        CHECK(num(&c, row, "self_intersections") == 0);
    }
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, "## weft bench collide") != NULL);
    CHECK(strstr(md, "Goal (cpu; a 20k-triangle body at 160 x 160 particles): not run here") != NULL);
    CHECK((strstr(md, "Goal (gpu; a 20k-triangle body at 160 x 160 particles): not run here") != NULL) == g_gpu);
    CHECK(strstr(md, "| backend | particles | body tris |") != NULL);
    int lines = 0;
    for (const char* p = strstr(md, "| backend |"); p && (p = strchr(p, '\n')) != NULL; ++p)
        if (p[1] == '|') ++lines;
    CHECK_EQ_INT(lines, 1 + c.n_rows); /* the separator and a line per row */
}

int main(int argc, char** argv) {
    g_gpu = argc > 1 && !strcmp(argv[1], "gpu");
    RUN_TEST(test_collide_usage);
    RUN_TEST(test_collide_quick);
    return TEST_SUMMARY();
}
