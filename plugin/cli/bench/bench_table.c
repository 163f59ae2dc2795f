/* A table of text cells: every column in the CSV, the columns with a Markdown header in the
 * Markdown table. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bench_table.h"

void bench_table_init(bench_table* t, int n_cols, const char* const* cols, const char* const* md_cols) {
    memset(t, 0, sizeof *t);
    t->n_cols = n_cols;
    t->cols = cols;
    t->md_cols = md_cols;
}

int bench_table_add(bench_table* t, const char* const* cells) {
    if (t->n_rows == t->cap_rows) {
        int cap = t->cap_rows ? 2 * t->cap_rows : 32;
        char** grown = realloc(t->cells, sizeof(char*) * (size_t)cap * (size_t)t->n_cols);
        if (!grown) return -1;
        t->cells = grown;
        t->cap_rows = cap;
    }
    char** row = t->cells + (size_t)t->n_rows * t->n_cols;
    for (int c = 0; c < t->n_cols; ++c) {
        row[c] = strdup(cells[c] ? cells[c] : "");
        if (!row[c]) {
            while (c-- > 0) free(row[c]);
            return -1;
        }
    }
    ++t->n_rows;
    return 0;
}

const char* bench_fmt(char* buf, size_t size, const char* fmt, double v) {
    if (isnan(v)) snprintf(buf, size, "nan");
    else if (isinf(v)) snprintf(buf, size, v > 0 ? "inf" : "-inf");
    else snprintf(buf, size, fmt, v);
    return buf;
}

/* A CSV field, quoted when it holds a comma, quote or newline. */
static void csv_field(FILE* out, const char* s) {
    if (!strpbrk(s, ",\"\n")) {
        fputs(s, out);
        return;
    }
    fputc('"', out);
    for (const char* c = s; *c; ++c) {
        if (*c == '"') fputc('"', out);
        fputc(*c, out);
    }
    fputc('"', out);
}

int bench_table_write_csv(const bench_table* t, FILE* out) {
    for (int c = 0; c < t->n_cols; ++c) {
        if (c) fputc(',', out);
        csv_field(out, t->cols[c]);
    }
    fputc('\n', out);
    for (int r = 0; r < t->n_rows; ++r) {
        for (int c = 0; c < t->n_cols; ++c) {
            if (c) fputc(',', out);
            csv_field(out, t->cells[(size_t)r * t->n_cols + c]);
        }
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

int bench_table_write_md(const bench_table* t, FILE* out) {
    for (int c = 0; c < t->n_cols; ++c)
        if (t->md_cols[c]) fprintf(out, "| %s ", t->md_cols[c]);
    fputs("|\n", out);
    for (int c = 0; c < t->n_cols; ++c)
        if (t->md_cols[c]) fputs("|---", out);
    fputs("|\n", out);
    for (int r = 0; r < t->n_rows; ++r) {
        for (int c = 0; c < t->n_cols; ++c)
            if (t->md_cols[c]) fprintf(out, "| %s ", t->cells[(size_t)r * t->n_cols + c]);
        fputs("|\n", out);
    }
    return ferror(out) ? -1 : 0;
}

void bench_table_free(bench_table* t) {
    if (!t) return;
    for (size_t k = 0; k < (size_t)t->n_rows * t->n_cols; ++k) free(t->cells[k]);
    free(t->cells);
    memset(t, 0, sizeof *t);
}
