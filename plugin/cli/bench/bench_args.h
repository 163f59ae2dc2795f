/* What the `weft bench` subcommands share on their command lines and in their outputs: lists
 * ("a,b,c"), solver and backend names, the common options (--quick, --threads, --garment, --csv,
 * --md, --plot, --quiet) and writing a table's Markdown and CSV (bench_args.c). */
#ifndef WEFT_CLI_BENCH_ARGS_H
#define WEFT_CLI_BENCH_ARGS_H
#include <stddef.h>
#include <stdio.h>

#include "weft/weft.h"

#define BENCH_MAX_LIST 16

/* "a,b,c" -> up to BENCH_MAX_LIST finite doubles in [lo, hi]; "1/240" (a fraction) is accepted.
 * Returns the count, or -1 (empty item, not a number, out of range, too many). */
int bench_parse_doubles(const char* text, double lo, double hi, double* out);
/* The same for integers in [lo, hi]. */
int bench_parse_ints(const char* text, int lo, int hi, int* out);
/* Comma-separated names: list copied into buf (size bytes), split in place, up to max pointers
 * into it stored in out (empty items skipped). Returns the count. */
int bench_split_names(const char* list, char* buf, size_t size, const char** out, int max);
/* Split text at commas and call fn on each item (copied, at most 63 characters; k its index):
 * the count, or -1 when text is empty or NULL, an item is empty or too long, there are more than
 * BENCH_MAX_LIST, or fn returns non-zero. */
int bench_for_each_item(const char* text, int (*fn)(const char* item, void* ctx, int k), void* ctx);
/* Solver names ("pcg,jacobi,chebyshev,direct", or "all"); -1 on an unknown name. */
int bench_parse_solvers(const char* text, weft_solver* out);

/* Options and outputs shared by the subcommands. */
typedef struct bench_common {
    int threads;            /* --threads N: OpenMP threads (0: OpenMP's default; --quick: 1) */
    int quiet;              /* --quiet: no progress lines on stderr */
    const char* garment;    /* --garment FILE: the garment scene's mesh */
    const char* csv;        /* --csv FILE, NULL: none */
    const char* md;         /* --md FILE, NULL: stdout */
    const char* plot;       /* --plot FILE.png, NULL: none */
    int blas_threads;       /* OpenBLAS's threads (set to `threads` when > 0; cli_blas_threads), -1:
                               another BLAS */
} bench_common;

/* CHOLMOD's BLAS threads, for the Markdown notes: "OpenBLAS: N thread(s)" or "BLAS: not OpenBLAS". */
const char* bench_blas_note(const bench_common* c, char* buf, size_t size);

/* A subcommand's own option at argv[*i]: 1 when it is one and its value is good, 0 when it is not
 * one, -1 when its value is missing, -2 when its value is bad (*value set, as cli_option_value). */
typedef int (*bench_option_fn)(void* args, int argc, char** argv, int* i, const char** value);

/* Parse a subcommand's arguments: -h/--help prints usage to stdout (returns CLI_EXIT_OK);
 * otherwise set_defaults(args, quick) and the common defaults are applied, then every argument
 * must be --quick, a common option or one of own's. Returns -1 to go on, or an exit code (usage
 * errors name the command). */
int bench_parse_args(int argc, char** argv, const char* command, void (*usage)(FILE*),
                     void (*set_defaults)(void* args, int quick), bench_option_fn own, void* args,
                     bench_common* common);

struct bench_table;
/* Write header(out, ctx) and the Markdown table to common->md (or stdout), and the CSV to
 * common->csv when set. CLI_EXIT_OK, or CLI_EXIT_FAILURE (message on stderr). */
int bench_write_tables(const bench_common* common, const struct bench_table* t,
                       void (*header)(FILE* out, const void* ctx), const void* ctx);

#endif
