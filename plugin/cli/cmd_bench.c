/* `weft bench SUBCOMMAND`: dispatch to `accuracy` or `stability`, and the list options they share. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cmd_bench.h"

void cli_bench_usage(FILE* out) {
    fputs("usage: weft bench accuracy [OPTIONS]    run time against error, for every solver\n"
          "       weft bench stability [OPTIONS]   survival over step length x stiffness x mass x solver\n"
          "       weft bench SUBCOMMAND --help     a subcommand's options\n"
          "\n"
          "Benchmarks of the simulator core. " BENCH_BACKEND_NOTE ".\n"
          "Each writes a Markdown table (stdout or --md FILE), a CSV (--csv FILE) and a PNG plot\n"
          "(--plot FILE); --quick runs a seconds-long version (what CI runs).\n",
          out);
}

int cli_bench_run(int argc, char** argv) {
    if (argc < 2) return cli_usage_error("weft bench", cli_bench_usage, "missing subcommand");
    const char* sub = argv[1];
    if (!strcmp(sub, "--help") || !strcmp(sub, "-h") || !strcmp(sub, "help")) {
        cli_bench_usage(stdout);
        return CLI_EXIT_OK;
    }
    if (!strcmp(sub, "accuracy")) return bench_accuracy_run(argc - 1, argv + 1);
    if (!strcmp(sub, "stability")) return bench_stability_run(argc - 1, argv + 1);
    return cli_usage_error("weft bench", cli_bench_usage, "unknown subcommand '%s'", sub);
}

/* Split text at commas into items (each copied into item, at most size - 1 characters); calls
 * fn on each; returns the count or -1. */
static int for_each_item(const char* text, int (*fn)(const char* item, void* ctx, int k), void* ctx) {
    if (!text || !*text) return -1;
    int k = 0;
    const char* p = text;
    for (;;) {
        const char* comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        char item[64];
        if (len == 0 || len >= sizeof item || k >= BENCH_MAX_LIST) return -1;
        memcpy(item, p, len);
        item[len] = '\0';
        if (fn(item, ctx, k) != 0) return -1;
        ++k;
        if (!comma) break;
        p = comma + 1;
    }
    return k;
}

typedef struct range_ctx {
    double lo, hi;
    double* d;
    int* i;
} range_ctx;

static int one_double(const char* item, void* ctx, int k) {
    range_ctx* c = ctx;
    double v;
    const char* slash = strchr(item, '/');
    if (slash) {
        char num[64];
        double a, b;
        size_t len = (size_t)(slash - item);
        memcpy(num, item, len);
        num[len] = '\0';
        if (cli_parse_double(num, &a) != 0 || cli_parse_double(slash + 1, &b) != 0 || b == 0) return -1;
        v = a / b;
    } else if (cli_parse_double(item, &v) != 0) {
        return -1;
    }
    if (!(v >= c->lo && v <= c->hi)) return -1;
    c->d[k] = v;
    return 0;
}

static int one_int(const char* item, void* ctx, int k) {
    range_ctx* c = ctx;
    return cli_parse_int(item, (int)c->lo, (int)c->hi, &c->i[k]);
}

static int one_solver(const char* item, void* ctx, int k) {
    int t = wc_solver_from_name(item);
    if (t < 0) return -1;
    ((wc_solver_type*)ctx)[k] = (wc_solver_type)t;
    return 0;
}

int bench_parse_doubles(const char* text, double lo, double hi, double* out) {
    range_ctx c = {lo, hi, out, NULL};
    return for_each_item(text, one_double, &c);
}

int bench_parse_ints(const char* text, int lo, int hi, int* out) {
    range_ctx c = {lo, hi, NULL, out};
    return for_each_item(text, one_int, &c);
}

int bench_parse_solvers(const char* text, wc_solver_type* out) {
    if (text && !strcmp(text, "all")) text = "pcg,jacobi,chebyshev,direct";
    return for_each_item(text, one_solver, out);
}
