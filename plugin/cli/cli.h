/* The `weft` command-line tool: shared declarations. main.c dispatches argv[1] through a table of
 * subcommands; each subcommand parses its own arguments and returns one of the exit codes below. */
#ifndef WEFT_CLI_H
#define WEFT_CLI_H
#include <stdio.h>

#include "weft/weft_status.h"

enum {
    CLI_EXIT_OK = 0,
    CLI_EXIT_FAILURE = 1,   /* the command ran and failed (e.g. a file that cannot be imported) */
    CLI_EXIT_USAGE = 2      /* bad command line; usage went to stderr */
};

typedef struct cli_command {
    const char* name;
    const char* summary;                 /* one line for `weft --help` */
    int (*run)(int argc, char** argv);   /* argv[0] is the subcommand's name */
    void (*usage)(FILE* out);
} cli_command;

/* Subcommands (one file each). */
int cli_inspect_run(int argc, char** argv);
void cli_inspect_usage(FILE* out);
int cli_run_run(int argc, char** argv);
void cli_run_usage(FILE* out);
int cli_bench_run(int argc, char** argv);
void cli_bench_usage(FILE* out);

/* Parse a whole string as a finite double. 0 on success, -1 otherwise (*out untouched). */
int cli_parse_double(const char* text, double* out);

/* Parse a whole string as a decimal integer in [lo, hi]. 0 on success, -1 otherwise. */
int cli_parse_int(const char* text, int lo, int hi, int* out);

/* Match an option that takes a value, as "--name VALUE" or "--name=VALUE". Returns 1 when argv[*i]
 * is this option and sets *value (advancing *i past a separate value), -1 when it is this option
 * but the value is missing, 0 when it is another argument. */
int cli_option_value(int argc, char** argv, int* i, const char* name, const char** value);
/* Print "COMMAND: message" and the command's usage to stderr; returns CLI_EXIT_USAGE. */
int cli_usage_error(const char* command, void (*usage)(FILE*), const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Sort v[0..n) ascending in place and return its median (the mean of the two middle values for
 * even n; 0 for n <= 0): timings and statistics (median.c). */
double cli_sort_median(double* v, int n);

/* With threads > 0, OpenBLAS's thread count (CHOLMOD's BLAS) set to threads (blas_threads.c).
 * Returns OpenBLAS's thread count after it, or -1 when the BLAS is not OpenBLAS (nothing set). */
int cli_blas_threads(int threads);

/* A failure of the tool's own code (scene files, arguments): the public status and a message
 * naming the file and field. */
typedef struct cli_diag {
    weft_status status;
    char message[512];      /* "" when ok */
} cli_diag;

/* Record a failure (printf-style) and return status. */
weft_status cli_fail(cli_diag* d, weft_status status, const char* fmt, ...) __attribute__((format(printf, 3, 4)));

/* Print "weft: <message>" to stderr as exactly one line (newlines in message become spaces). */
void cli_error(const char* message);

#endif
