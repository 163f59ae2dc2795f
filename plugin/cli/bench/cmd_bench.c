/* `weft bench SUBCOMMAND`: dispatch to `accuracy`, `iterations`, `stability`, `peers`, `torture`, `skip` or `collide`,
 * and the list options they share. */
#define _POSIX_C_SOURCE 200809L
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cmd_bench.h"

#ifndef WEFT_SAMPLE_SCENES
#define WEFT_SAMPLE_SCENES "sample_scenes"
#endif

void cli_bench_usage(FILE* out) {
    fputs("usage: weft bench accuracy [OPTIONS]    run time against error, for every solver\n"
          "       weft bench iterations [OPTIONS]  solver iterations per solve over sizes and stiffnesses\n"
          "       weft bench stability [OPTIONS]   survival over step length x stiffness x mass x solver\n"
          "       weft bench peers [OPTIONS]       Weft beside Blender's cloth solver (needs blender)\n"
          "       weft bench torture [OPTIONS]     random host inputs: crashes, hangs, NaN outputs\n"
          "       weft bench skip [OPTIONS]        per-stage cost of unused features, and of a sleeping cloth\n"
          "       weft bench collide [OPTIONS]     collision detection's cost over cloth and body sizes\n"
          "       weft bench SUBCOMMAND --help     a subcommand's options\n"
          "\n"
          "Benchmarks of the simulator. accuracy, stability, skip and peers take --backend LIST\n"
          "(cpu, gpu or cpu,gpu; default cpu): each configuration runs on every backend listed, core's\n"
          "wc_step_frame on the CPU, gpu/'s wg_sim_step_frame on a headless GL context (llvmpipe where\n"
          "there is no GPU), side by side in one table with a `backend` column; torture takes\n"
          "--backend cpu|gpu|auto and goes through the public API.\n"
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
    int rc = -1;
    if (!strcmp(sub, "accuracy")) rc = bench_accuracy_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "iterations")) rc = bench_iterations_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "stability")) rc = bench_stability_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "peers")) rc = bench_peers_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "torture")) rc = bench_torture_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "skip")) rc = bench_skip_run(argc - 1, argv + 1);
    else if (!strcmp(sub, "collide")) rc = bench_collide_run(argc - 1, argv + 1);
    else return cli_usage_error("weft bench", cli_bench_usage, "unknown subcommand '%s'", sub);
    bench_gpu_close(); /* the process's GPU context, when a --backend gpu run made one */
    return rc;
}

int bench_split_names(const char* list, char* buf, size_t size, const char** out, int max) {
    snprintf(buf, size, "%s", list);
    int n = 0;
    char* save = NULL;
    for (char* tok = strtok_r(buf, ",", &save); tok && n < max; tok = strtok_r(NULL, ",", &save)) out[n++] = tok;
    return n;
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

int bench_parse_backend(const char* name) {
    static const char* const names[] = {"auto", "cpu", "gpu"};   /* weft_backend's order */
    for (int k = 0; k < 3; ++k)
        if (name && !strcmp(name, names[k])) return k;
    return -1;
}

static int one_backend(const char* item, void* ctx, int k) {
    int* out = ctx;
    const int b = !strcmp(item, "cpu") ? BENCH_CPU : !strcmp(item, "gpu") ? BENCH_GPU : -1;
    if (b < 0 || k >= BENCH_MAX_BACKENDS) return -1;
    for (int j = 0; j < k; ++j)
        if (out[j] == b) return -1; /* each at most once */
    out[k] = b;
    return 0;
}

int bench_parse_backends(const char* text, int* out) {
    int tmp[BENCH_MAX_LIST];
    int n = for_each_item(text, one_backend, tmp);
    for (int k = 0; k < n; ++k) out[k] = tmp[k];
    return n;
}

const char* bench_backend_name(int backend) { return backend == BENCH_GPU ? "gpu" : "cpu"; }

const char* bench_blas_note(const bench_common* c, char* buf, size_t size) {
    if (c->blas_threads > 0) snprintf(buf, size, "OpenBLAS: %d thread(s)", c->blas_threads);
    else snprintf(buf, size, "BLAS: not OpenBLAS");
    return buf;
}

const char* bench_backend_note(const int* backends, int n, char* buf, size_t size) {
    size_t at = 0;
    buf[0] = '\0';
    for (int k = 0; k < n && at < size; ++k) {
        int w;
        if (backends[k] == BENCH_GPU)
            w = snprintf(buf + at, size - at, "%sGPU (gpu/'s wg_sim_step_frame on %s; positions read back outside "
                         "the timed steps)", k ? " and " : "", bench_gpu_description());
        else
            w = snprintf(buf + at, size - at, "%sCPU (core's wc_step_frame)", k ? " and " : "");
        if (w < 0) break;
        at += (size_t)w;
    }
    if (at >= size && size > 0) buf[size - 1] = '\0';
    /* "backend(s): " first */
    char head[16];
    snprintf(head, sizeof head, "%s: ", n > 1 ? "backends" : "backend");
    const size_t hl = strlen(head), bl = strlen(buf);
    if (hl + bl + 1 <= size) {
        memmove(buf + hl, buf, bl + 1);
        memcpy(buf, head, hl);
    }
    return buf;
}

int bench_open_backends(const int* backends, int n) {
    for (int k = 0; k < n; ++k) {
        char msg[768];
        if (backends[k] == BENCH_GPU && bench_gpu_open(msg, sizeof msg) != 0) {
            cli_error(msg);
            return CLI_EXIT_FAILURE;
        }
    }
    return CLI_EXIT_OK;
}

int bench_parse_solvers(const char* text, wc_solver_type* out) {
    if (text && !strcmp(text, "all")) text = "pcg,jacobi,chebyshev,direct";
    return for_each_item(text, one_solver, out);
}

int bench_parse_args(int argc, char** argv, const char* command, void (*usage)(FILE*),
                     void (*defaults)(void* args, int quick), bench_option_fn own, void* args, bench_common* c) {
    int quick = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return CLI_EXIT_OK;
        }
        if (!strcmp(argv[i], "--quick")) quick = 1;
    }
    defaults(args, quick);
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
