/* The lists, names and common options of the `weft bench` subcommands, and writing their tables
 * (bench_args.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench_args.h"

#include <stdlib.h>
#include <string.h>

#include "bench_table.h"
#include "cli.h"
#include "names.h"

#ifndef WEFT_SAMPLE_SCENES
#define WEFT_SAMPLE_SCENES "sample_scenes"
#endif

int bench_split_names(const char* list, char* buf, size_t size, const char** out, int max) {
    snprintf(buf, size, "%s", list);
    int n = 0;
    char* save = NULL;
    for (char* tok = strtok_r(buf, ",", &save); tok && n < max; tok = strtok_r(NULL, ",", &save)) out[n++] = tok;
    return n;
}

int bench_for_each_item(const char* text, int (*fn)(const char* item, void* ctx, int k), void* ctx) {
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
    int t = cli_solver_from_name(item);
    if (t < 0) return -1;
    ((weft_solver*)ctx)[k] = (weft_solver)t;
    return 0;
}

int bench_parse_doubles(const char* text, double lo, double hi, double* out) {
    range_ctx c = {lo, hi, out, NULL};
    return bench_for_each_item(text, one_double, &c);
}

int bench_parse_ints(const char* text, int lo, int hi, int* out) {
    range_ctx c = {lo, hi, NULL, out};
    return bench_for_each_item(text, one_int, &c);
}

const char* bench_blas_note(const bench_common* c, char* buf, size_t size) {
    if (c->blas_threads > 0) snprintf(buf, size, "OpenBLAS: %d thread(s)", c->blas_threads);
    else snprintf(buf, size, "BLAS: not OpenBLAS");
    return buf;
}

int bench_parse_solvers(const char* text, weft_solver* out) {
    if (text && !strcmp(text, "all")) text = "pcg,jacobi,chebyshev,direct";
    return bench_for_each_item(text, one_solver, out);
}

int bench_parse_args(int argc, char** argv, const char* command, void (*usage)(FILE*),
                     void (*set_defaults)(void* args, int quick), bench_option_fn own, void* args, bench_common* c) {
    int quick = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return CLI_EXIT_OK;
        }
        if (!strcmp(argv[i], "--quick")) quick = 1;
    }
    set_defaults(args, quick);
    memset(c, 0, sizeof *c);
    c->threads = quick ? 1 : 0;
    c->garment = WEFT_SAMPLE_SCENES "/skirt.obj";
    for (int i = 1; i < argc; ++i) {
        const char* arg = argv[i];
        const char* v = NULL;
        int m = 0;
        if (!strcmp(arg, "--quick")) continue;
        if (!strcmp(arg, "--quiet")) {
            c->quiet = 1;
            continue;
        }
        if ((m = cli_option_value(argc, argv, &i, "--threads", &v)) != 0) {
            if (m > 0 && cli_parse_int(v, 0, 64, &c->threads) != 0) m = -2;
        } else if ((m = cli_option_value(argc, argv, &i, "--garment", &v)) != 0) {
            c->garment = v;
        } else if ((m = cli_option_value(argc, argv, &i, "--csv", &v)) != 0) {
            c->csv = v;
        } else if ((m = cli_option_value(argc, argv, &i, "--md", &v)) != 0) {
            c->md = v;
        } else if ((m = cli_option_value(argc, argv, &i, "--plot", &v)) != 0) {
            c->plot = v;
        } else if ((m = own(args, argc, argv, &i, &v)) == 0) {
            return cli_usage_error(command, usage, "unknown option '%s'", arg);
        }
        if (m == -1) return cli_usage_error(command, usage, "%s needs a value", arg);
        if (m == -2) return cli_usage_error(command, usage, "bad value for %s: '%s'", arg, v);
    }
    c->blas_threads = cli_blas_threads(c->threads);
    return -1;
}

static FILE* open_out(const char* path) {
    FILE* f = fopen(path, "w");
    if (!f) fprintf(stderr, "weft: cannot write %s\n", path);
    return f;
}

int bench_write_tables(const bench_common* c, const bench_table* t, void (*header)(FILE* out, const void* ctx),
                       const void* ctx) {
    FILE* md = c->md ? open_out(c->md) : stdout;
    if (!md) return CLI_EXIT_FAILURE;
    header(md, ctx);
    int bad = bench_table_write_md(t, md) != 0;
    if (md != stdout) bad |= fclose(md) != 0;
    if (!bad && c->csv) {
        FILE* f = open_out(c->csv);
        if (!f) return CLI_EXIT_FAILURE;
        bad |= bench_table_write_csv(t, f) != 0;
        bad |= fclose(f) != 0;
    }
    if (bad) cli_error("error writing the tables");
    return bad ? CLI_EXIT_FAILURE : CLI_EXIT_OK;
}
