/* `weft bench torture --quick`, run as a user would (WEFT_CLI): every case of the quick run is
 * ok, rejected with a status and a message, or step_failed; every NaN/Inf injection is refused as
 * NONFINITE; --case reruns a case identically.
 *
 *   check_weft_bench_torture */
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

int main(void) {
    RUN_TEST(test_torture_usage);
    RUN_TEST(test_torture_quick);
    return TEST_SUMMARY();
}
