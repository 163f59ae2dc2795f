/* `weft bench accuracy|stability|skip --quick`, run as a user would (WEFT_CLI), so none can
 * rot. Nothing about time is asserted. Checked: --help texts and usage errors; the CSV has the
 * expected header and one row per configuration/cell with finite errors; the direct solver's
 * linear-solve error against CHOLMOD is ~0; the Markdown table has a line per row; the plot is
 * a well-formed PNG (signature, chunk CRCs, IHDR first, IDAT, IEND last). Physics, from outside
 * the benchmark: (accuracy) the direct solver's trajectory error shrinks when its substeps
 * double, as backward Euler converges to the reference; (stability) a flat sheet's first step
 * is a free fall, so the strain of a pinned corner's spring after one step of h is
 * sqrt(1 + (g h^2 / rest)^2) - 1; (skip) one row per configuration in order, the asleep row slept
 * through every timed frame with 0 iterations and bit-identical positions, the full-cap row ran
 * every solve to the cap, the contact row has contacts and the far-collider row none.
 *
 *   check_weft_bench accuracy | stability | skip */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "test_support.h"

/* ---- CSV ---- */

#define MAX_ROWS 512
#define MAX_COLS 40

typedef struct csv {
    int n_rows, n_cols;              /* data rows (header excluded), header columns */
    char* cell[MAX_ROWS + 1][MAX_COLS];  /* [0] is the header */
    int row_cols[MAX_ROWS + 1];
    char text[1 << 17];
} csv;

/* Split text (no quoted fields in weft's CSV) into rows and cells. */
static void csv_parse(csv* c, const char* path) {
    memset(c, 0, sizeof *c);
    ts_read_text(path, c->text, sizeof c->text);
    int r = 0;
    for (char* line = strtok(c->text, "\n"); line && r <= MAX_ROWS; line = strtok(NULL, "\n"), ++r) {
        int k = 0;
        char* p = line;
        for (;;) {
            char* comma = strchr(p, ',');
            if (k < MAX_COLS) c->cell[r][k] = p;
            ++k;
            if (!comma) break;
            *comma = '\0';
            p = comma + 1;
        }
        c->row_cols[r] = k;
    }
    c->n_rows = r > 0 ? r - 1 : 0;
    c->n_cols = c->row_cols[0];
}

static int col(const csv* c, const char* name) {
    for (int k = 0; k < c->n_cols && k < MAX_COLS; ++k)
        if (!strcmp(c->cell[0][k], name)) return k;
    fprintf(stderr, "no column %s\n", name);
    return -1;
}

static const char* get(const csv* c, int row, const char* name) {
    int k = col(c, name);
    return k >= 0 ? c->cell[row + 1][k] : "";
}

/* The cell as a number; NAN when it is not one. */
static double num(const csv* c, int row, const char* name) {
    const char* s = get(c, row, name);
    char* end = NULL;
    double v = strtod(s, &end);
    return (end != s && *end == '\0') ? v : NAN;
}

static void check_header(const csv* c, const char* const* expected, int n) {
    CHECK_EQ_INT(c->n_cols, n);
    for (int k = 0; k < n && k < c->n_cols; ++k) {
        int same = !strcmp(c->cell[0][k], expected[k]);
        CHECK(same);
        if (!same) fprintf(stderr, "  column %d: %s, expected %s\n", k, c->cell[0][k], expected[k]);
    }
    for (int r = 1; r <= c->n_rows; ++r) CHECK_EQ_INT(c->row_cols[r], n);
}

/* ---- PNG ---- */

static unsigned long crc32_png(const unsigned char* p, size_t n) {
    unsigned long c = 0xffffffffUL;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320UL & (0UL - (c & 1UL)));
    }
    return c ^ 0xffffffffUL;
}

static unsigned long be32(const unsigned char* p) {
    return ((unsigned long)p[0] << 24) | ((unsigned long)p[1] << 16) | ((unsigned long)p[2] << 8) | p[3];
}

/* 1 when the file is a well-formed PNG of at least min_w x min_h pixels. */
static int png_ok(const char* path, unsigned long min_w, unsigned long min_h) {
    FILE* f = fopen(path, "rb");
    if (!f) return 0;
    static unsigned char buf[1 << 21];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (n < 8 + 25 + 12 || n == sizeof buf || memcmp(buf, sig, 8) != 0) return 0;
    size_t at = 8;
    int chunks = 0, idat = 0, iend = 0;
    while (at + 12 <= n && !iend) {
        unsigned long len = be32(buf + at);
        if (len > n || at + 12 + len > n) return 0;
        const unsigned char* type = buf + at + 4;
        if (crc32_png(type, 4 + len) != be32(buf + at + 8 + len)) return 0;
        if (chunks == 0) {
            if (memcmp(type, "IHDR", 4) != 0 || len != 13) return 0;
            if (be32(type + 4) < min_w || be32(type + 8) < min_h) return 0;
        }
        idat += !memcmp(type, "IDAT", 4);
        iend = !memcmp(type, "IEND", 4);
        at += 12 + len;
        ++chunks;
    }
    return iend && idat > 0 && at == n;
}

/* ---- help and usage ---- */

static void test_help(void) {
    static ts_cli_result r;
    ts_run_cli("--help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "bench") != NULL);
    ts_run_cli("bench --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "weft bench accuracy") && strstr(r.out, "weft bench stability") &&
          strstr(r.out, "weft bench skip"));
    CHECK(strstr(r.out, "no GPU backend") != NULL);
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
    ts_run_cli("bench accuracy --solvers pcg,gauss", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --solvers") != NULL);
    ts_run_cli("bench accuracy --tolerances 1e-3,,1e-4", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench accuracy --substeps", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "--substeps needs a value") != NULL);
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
    "failures", "lin_err_mean", "lin_err_max", "traj_err_rms", "traj_err_max", "max_strain", "energy_drift"};

static void test_accuracy_quick(void) {
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
    snprintf(args, sizeof args, "bench accuracy --quick --quiet --csv '%s' --plot '%s' --md '%s'", csv_path,
             png_path, md_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    csv_parse(&c, csv_path);
    check_header(&c, acc_cols, (int)(sizeof acc_cols / sizeof acc_cols[0]));
    /* per scene: the reference, then pcg/jacobi/chebyshev x 1 tolerance x 2 caps x 2 substeps, direct x 2 */
    static const char* const scenes[] = {"sheet16", "drape16", "garment"};
    const int per_scene = 1 + 3 * 2 * 2 + 2;
    CHECK_EQ_INT(c.n_rows, 3 * per_scene);
    for (int s = 0; s < 3; ++s) {
        double direct_err[2] = {NAN, NAN};
        for (int k = 0; k < per_scene && s * per_scene + k < c.n_rows; ++k) {
            const int row = s * per_scene + k;
            const int ref = k == 0;
            CHECK(!strcmp(get(&c, row, "scene"), scenes[s]));
            CHECK(!strcmp(get(&c, row, "backend"), "cpu"));
            CHECK(!strcmp(get(&c, row, "role"), ref ? "reference" : "config"));
            CHECK(num(&c, row, "frames") == 9);
            CHECK(num(&c, row, "ms_per_frame") > 0);
            const double rms = num(&c, row, "traj_err_rms"), max = num(&c, row, "traj_err_max");
            CHECK(isfinite(rms) && isfinite(max) && rms >= 0 && max >= rms);
            CHECK(ref ? rms == 0 && max == 0 : rms < 10);
            CHECK(isfinite(num(&c, row, "max_strain")) && num(&c, row, "max_strain") >= 0);
            CHECK(isfinite(num(&c, row, "energy_drift")));
            CHECK(num(&c, row, "substeps") == (ref ? 8 : (k - 1) % 2 + 1));
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
    CHECK(strstr(md, "| scene | solver |") != NULL);
    CHECK(strstr(md, "no GPU backend") != NULL);
    int table_lines = 0;
    for (const char* p = md; (p = strstr(p, "\n| ")) != NULL; ++p) ++table_lines;
    CHECK_EQ_INT(table_lines, c.n_rows + 1); /* header + rows ("|---" lines start with "|-") */
    CHECK(png_ok(png_path, 400, 300));
}

static const char* const stab_cols[] = {
    "backend", "scene", "particles", "solver", "step_s", "stiffness_x", "mass_x", "outcome", "reason",
    "frames", "frames_asked", "rollbacks", "halvings", "direct_fallbacks", "failures", "max_strain",
    "energy_growth", "iterations_per_substep", "ms_per_frame"};

static void test_stability_quick(void) {
    static ts_cli_result r;
    static csv c;
    char args[4096];
    char csv_path[512], png_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_stability.csv"));
    snprintf(png_path, sizeof png_path, "%s", ts_tmp_path("bench_stability.png"));
    remove(csv_path);
    remove(png_path);
    snprintf(args, sizeof args, "bench stability --quick --quiet --csv '%s' --plot '%s'", csv_path, png_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    CHECK(strstr(r.out, "| solver | survived | recovered | failed |") != NULL);
    csv_parse(&c, csv_path);
    check_header(&c, stab_cols, (int)(sizeof stab_cols / sizeof stab_cols[0]));
    CHECK_EQ_INT(c.n_rows, 4 * 3 * 3 * 2); /* solvers x steps x stiffness x mass */
    int free_fall_cells = 0;
    for (int row = 0; row < c.n_rows; ++row) {
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
         * 1/11 m) stretches to sqrt(rest^2 + (g h^2)^2). With 1/12 s that is a strain of 25%,
         * and with 10^4 x stiffness the energy check fails the cell right there. */
        if (!strcmp(get(&c, row, "step_s"), "1/12") && num(&c, row, "stiffness_x") == 10000) {
            const double h = 1.0 / 12, drop = 9.81 * h * h, rest = 1.0 / 11;
            CHECK(failed && frames == 1);
            CHECK_NEAR(strain, sqrt(1 + drop * drop / (rest * rest)) - 1, 1e-3);
            ++free_fall_cells;
        }
        /* small steps of the default cloth survive with every solver */
        if (!strcmp(get(&c, row, "step_s"), "1/60") && num(&c, row, "stiffness_x") == 1) CHECK(!failed);
    }
    CHECK_EQ_INT(free_fall_cells, 4 * 2);
    CHECK(png_ok(png_path, 400, 300));
}

static const char* const skip_cols[] = {
    "backend", "scene", "particles", "config", "frames", "warmup_frames", "iterations_per_substep",
    "not_converged", "contacts", "asleep_frames", "positions_unchanged", "ms_forces", "ms_assemble", "ms_solve",
    "ms_collide", "ms_integrate", "ms_total", "ratio_to_baseline", "ms_saved", "skipped"};

static void test_skip_usage(void) {
    static ts_cli_result r;
    ts_run_cli("bench skip --help", &r);
    CHECK_EQ_INT(r.rc, 0);
    CHECK(strstr(r.out, "--quick") && strstr(r.out, "asleep") && strstr(r.out, "no GPU backend"));
    ts_run_cli("bench skip --frames 0", &r);
    CHECK_EQ_INT(r.rc, 2);
    CHECK(strstr(r.err, "bad value for --frames") != NULL);
    ts_run_cli("bench skip --quick --plot x.png", &r);
    CHECK_EQ_INT(r.rc, 2);
    ts_run_cli("bench skip --quick --quiet --scene blanket9", &r);
    CHECK_EQ_INT(r.rc, 1);
    CHECK(strstr(r.err, "unknown scene 'blanket9'") != NULL);
}

static void test_skip_quick(void) {
    static ts_cli_result r;
    static csv c;
    char args[4096], csv_path[512];
    snprintf(csv_path, sizeof csv_path, "%s", ts_tmp_path("bench_skip.csv"));
    remove(csv_path);
    snprintf(args, sizeof args, "bench skip --quick --quiet --csv '%s'", csv_path);
    ts_run_cli(args, &r);
    CHECK_EQ_INT(r.rc, 0);
    if (r.rc != 0) fprintf(stderr, "stderr: %s\n", r.err);
    CHECK(strstr(r.out, "| configuration |") != NULL && strstr(r.out, "no GPU backend") != NULL);
    CHECK(strstr(r.out, "positions bit-identical") != NULL);
    csv_parse(&c, csv_path);
    check_header(&c, skip_cols, (int)(sizeof skip_cols / sizeof skip_cols[0]));
    static const char* const configs[] = {"baseline", "+ air drag", "+ wind", "+ far collider", "+ contact",
                                          "+ moving pins", "full cap", "asleep"};
    CHECK_EQ_INT(c.n_rows, 8);
    for (int row = 0; row < c.n_rows && row < 8; ++row) {
        CHECK(!strcmp(get(&c, row, "config"), configs[row]));
        CHECK(!strcmp(get(&c, row, "backend"), "cpu") && !strcmp(get(&c, row, "scene"), "sheet16"));
        CHECK(num(&c, row, "particles") == 256 && num(&c, row, "frames") == 20);
        for (int k = 11; k <= 16; ++k) CHECK(num(&c, row, skip_cols[k]) >= 0);
        CHECK(isfinite(num(&c, row, "ratio_to_baseline")));
        const int asleep = row == 7;
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
    CHECK(num(&c, 0, "ratio_to_baseline") == 1 && !strcmp(get(&c, 0, "ms_saved"), "-"));
    CHECK(num(&c, 3, "contacts") == 0 && num(&c, 4, "contacts") > 0);
    /* tolerance 0: every solve runs to the cap of 300 and counts as not converged */
    CHECK(num(&c, 6, "iterations_per_substep") == 300 && num(&c, 6, "not_converged") == 20);
    CHECK(num(&c, 0, "not_converged") == 0);
    /* a far collider changes nothing of the motion: the same iterations as the baseline */
    CHECK(num(&c, 3, "iterations_per_substep") == num(&c, 0, "iterations_per_substep"));
}

int main(int argc, char** argv) {
    const char* which = argc > 1 ? argv[1] : "";
    if (!strcmp(which, "accuracy")) {
        RUN_TEST(test_help);
        RUN_TEST(test_accuracy_usage);
        RUN_TEST(test_accuracy_quick);
    } else if (!strcmp(which, "stability")) {
        RUN_TEST(test_help);
        RUN_TEST(test_stability_usage);
        RUN_TEST(test_stability_quick);
    } else if (!strcmp(which, "skip")) {
        RUN_TEST(test_skip_usage);
        RUN_TEST(test_skip_quick);
    } else {
        fprintf(stderr, "usage: %s accuracy|stability|skip\n", argv[0]);
        return 2;
    }
    return TEST_SUMMARY();
}
