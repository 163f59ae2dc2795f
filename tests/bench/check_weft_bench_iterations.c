/* `weft bench iterations --quick`, run as a user would (WEFT_CLI), so that it cannot rot. Nothing
 * about time or about how few iterations a preconditioner needs is asserted. Checked: --help and
 * usage errors; the CSV's header and one row per (sheet size, stiffness factor, scene) x
 * preconditioner in order, each scene's particle count, every row's counts consistent (mean
 * iterations per solve within (0, largest], largest within the cap, converged fraction within
 * [0, 1] and 1 exactly when no solve stopped at the cap, at least one solve per frame); the
 * Markdown's goals table with a met / not met verdict per preconditioner that agrees with the
 * CSV's own numbers, and a table line per row.
 *
 *   check_weft_bench_iterations */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "check_bench_csv.h"
#include "test_support.h"

static void test_iterations_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench iterations --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "--sizes") && strstr(r.out, "--stiffness") &&
          strstr(r.out, "--preconds") && strstr(r.out, "it./solve") && strstr(r.out, "Goals"));
    ts_run_cli("bench iterations --sizes 1", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --sizes: '1'") != NULL);
    ts_run_cli("bench iterations --stiffness 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench iterations --preconds amg,ilu", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench iterations --tolerance 1", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench iterations --quick --plot it.png", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "draws no plot") != NULL);
    ts_run_cli("bench iterations --quick --quiet --scenes blanket9", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "unknown scene 'blanket9'") != NULL);
}

static const char* const it_cols[] = {
    "group", "scene", "particles", "stiffness_x", "solver", "preconditioner", "integrator", "newton_iterations",
    "line_search", "frames", "substeps", "solves", "iterations_per_solve", "max_iterations_used",
    "converged_fraction", "not_converged", "ms_precond_per_solve", "ms_solve_per_solve", "ms_per_frame",
    "rollbacks", "failures"};

/* 1 when text has prefix followed by a ratio within 2 % of r (or the denominator is tiny). */
static int ratio_in(const char* text, const char* prefix, double r, double denominator) {
    if (denominator < 5) return 1;
    size_t n = strlen(prefix);
    for (const char* at = strstr(text, prefix); at; at = strstr(at + 1, prefix)) {
        char* end;
        double v = strtod(at + n, &end);
        if (end != at + n && fabs(v - r) <= 0.02 * r + 0.006) return 1;
    }
    return 0;
}

/* 1 when some number within 2 % of r in text is followed by "| met |" (met) or "| not met |". */
static int verdict_after(const char* text, double r, int met) {
    for (const char* at = strstr(text, "| "); at; at = strstr(at + 1, "| ")) {
        char* end;
        double v = strtod(at + 2, &end);
        if (end == at + 2 || !(fabs(v - r) <= 0.02 * r + 0.006)) continue;
        if (!strncmp(end, met ? " | met |" : " | not met |", met ? 8 : 12)) return 1;
    }
    return 0;
}

static void test_iterations_quick(void) {
    static ts_cli_result r;
    static csv c;
    static char md[1 << 16];
    char args[2048], csv_path[512], md_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_iterations.csv"));
    snprintf(md_path, sizeof md_path, "%s", ts_tmp_path("bench_iterations.md"));
    remove(csv_path);
    remove(md_path);
    snprintf(args, sizeof args, "bench iterations --quick --quiet --csv '%s' --md '%s'", csv_path, md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, it_cols, (int)(sizeof it_cols / sizeof it_cols[0]));
    /* the quick preset: sheets 8 and 16, sheet12 at stiffness x1 and x100, drape16 and the garment,
     * each with block_jacobi then amg */
    static const char* const group[] = {"size", "size", "stiffness", "stiffness", "scene", "scene"};
    static const char* const scene[] = {"sheet8", "sheet16", "sheet12", "sheet12", "drape16", "garment"};
    static const double particles[] = {64, 256, 144, 144, 256, 544}, k[] = {1, 1, 1, 100, 1, 1};
    static const char* const pre[] = {"block_jacobi", "amg"};
    CHECK_EQ_INT(c.n_rows, 12);
    double worst[2] = {0, 0}, least[2] = {1, 1}, first[2][2], last[2][2]; /* [precond][size, stiffness] */
    for (int row = 0; row < c.n_rows && row < 12; ++row) {
        const int j = row / 2, p = row % 2;
        CHECK(!strcmp(get(&c, row, "group"), group[j]) && !strcmp(get(&c, row, "scene"), scene[j]));
        CHECK(num(&c, row, "particles") == particles[j] && num(&c, row, "stiffness_x") == k[j]);
        CHECK(!strcmp(get(&c, row, "solver"), "pcg") && !strcmp(get(&c, row, "preconditioner"), pre[p]));
        CHECK(!strcmp(get(&c, row, "integrator"), "be") && num(&c, row, "newton_iterations") == 1 &&
              !strcmp(get(&c, row, "line_search"), "off"));
        const double frames = num(&c, row, "frames"), solves = num(&c, row, "solves");
        const double mean = num(&c, row, "iterations_per_solve"), max = num(&c, row, "max_iterations_used");
        const double conv = num(&c, row, "converged_fraction"), notconv = num(&c, row, "not_converged");
        CHECK(frames == 9 && solves >= frames && num(&c, row, "substeps") >= frames);
        CHECK(mean > 0 && mean <= max + 0.05 && max <= 300);
        CHECK(conv >= 0 && conv <= 1);
        CHECK(fabs(conv - (1 - notconv / solves)) < 2e-3);
        CHECK(num(&c, row, "ms_precond_per_solve") >= 0 && num(&c, row, "ms_solve_per_solve") > 0);
        CHECK(num(&c, row, "ms_per_frame") > 0 && num(&c, row, "failures") == 0);
        if (!(mean <= worst[p])) worst[p] = mean;
        if (!(conv >= least[p])) least[p] = conv;
        if (j == 0) first[p][0] = mean;
        if (j == 1) last[p][0] = mean;
        if (j == 2) first[p][1] = mean;
        if (j == 3) last[p][1] = mean;
    }
    ts_read_text(md_path, md, sizeof md);
    CHECK(strstr(md, "## weft bench iterations") != NULL);
    CHECK(strstr(md, "from sheet8 to sheet16 and from stiffness x1 to x100 (sheet12)") != NULL);
    /* the goals: the verdicts follow from the CSV's numbers (printed with 1 decimal; the growth
     * with 2: a verdict within rounding of its threshold is not checked) */
    for (int p = 0; p < 2 && c.n_rows == 12; ++p) {
        char line[256];
        snprintf(line, sizeof line, "| pcg | %s | be | 1 | %.1f (", pre[p], worst[p]);
        const char* at = strstr(md, line);
        CHECK(at != NULL);
        if (!at) {
            fprintf(stderr, "  no goals line starting %s\n", line);
            continue;
        }
        const double gs = last[p][0] / first[p][0], gk = last[p][1] / first[p][1];
        const char* end = strchr(at, '\n');
        char text[512];
        snprintf(text, sizeof text, "%.*s", (int)(end ? end - at : 0), at);
        const int mean_met = worst[p] <= 30 && least[p] >= 1;
        /* the ratios come from CSV means rounded to 1 decimal: allow 2 % either way, and skip a
           ratio whose denominator is tiny (the multigrid solves sheet8, one level, in 1 iteration) */
        CHECK(ratio_in(text, mean_met ? "| met | " : "| not met | ", gs, first[p][0]) ||
              fabs(worst[p] - 30) <= 0.1);
        if (fabs(gs - 2) > 0.05) CHECK(ratio_in(text, "| ", gs, first[p][0]) && verdict_after(text, gs, gs <= 2));
        if (fabs(gk - 2) > 0.05) CHECK(ratio_in(text, "| ", gk, first[p][1]) && verdict_after(text, gk, gk <= 2));
    }
    int table_lines = 0;
    for (const char* q = md; (q = strstr(q, "\n| ")) != NULL; ++q) ++table_lines;
    CHECK_EQ_INT(table_lines, (1 + 2) + (1 + c.n_rows)); /* goals header + 2, the table's header + rows */
}

int main(void) {
    RUN_TEST(test_iterations_usage);
    RUN_TEST(test_iterations_quick);
    return TEST_SUMMARY();
}
