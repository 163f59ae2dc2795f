/* Small argument helpers shared by the subcommands. */
#include "cli.h"

#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int cli_parse_double(const char* text, double* out) {
    if (!text || !*text) return -1;
    char* end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno == ERANGE || end == text || *end != '\0' || !isfinite(v)) return -1;
    *out = v;
    return 0;
}

int cli_parse_int(const char* text, int lo, int hi, int* out) {
    if (!text || !*text) return -1;
    char* end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno == ERANGE || end == text || *end != '\0' || v < lo || v > hi) return -1;
    *out = (int)v;
    return 0;
}

int cli_option_value(int argc, char** argv, int* i, const char* name, const char** value) {
    const char* arg = argv[*i];
    size_t n = strlen(name);
    if (strncmp(arg, name, n) != 0) return 0;
    if (arg[n] == '=') {
        *value = arg + n + 1;
        return 1;
    }
    if (arg[n] != '\0') return 0;
    if (*i + 1 >= argc) return -1;
    *value = argv[++*i];
    return 1;
}

void cli_error(const char* message) {
    fputs("weft: ", stderr);
    for (const char* c = message; *c; ++c) fputc(*c == '\n' || *c == '\r' ? ' ' : *c, stderr);
    fputc('\n', stderr);
}

int cli_usage_error(const char* command, void (*usage)(FILE*), const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "%s: ", command);
    vfprintf(stderr, fmt, ap);
    fputs("\n", stderr);
    va_end(ap);
    usage(stderr);
    return CLI_EXIT_USAGE;
}
