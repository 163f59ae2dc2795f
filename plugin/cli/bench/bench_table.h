/* A table of text cells: every column in the CSV, the columns with a Markdown header in the
 * Markdown table (bench_table.c). */
#ifndef WEFT_CLI_BENCH_TABLE_H
#define WEFT_CLI_BENCH_TABLE_H
#include <stddef.h>
#include <stdio.h>

typedef struct bench_table {
    int n_cols;
    const char* const* cols;     /* column names (CSV header) */
    const char* const* md_cols;  /* Markdown header of each column, NULL: not in the Markdown table */
    int n_rows, cap_rows;
    char** cells;                /* (n_rows x n_cols) owned strings */
} bench_table;

void bench_table_init(bench_table* t, int n_cols, const char* const* cols, const char* const* md_cols);
/* Append a row: n_cols strings, copied. 0, or -1 when out of memory. */
int bench_table_add(bench_table* t, const char* const* cells);
/* v printed with fmt into buf ("nan", "inf", "-inf" for those), returned. */
const char* bench_fmt(char* buf, size_t size, const char* fmt, double v);
int bench_table_write_csv(const bench_table* t, FILE* out);
int bench_table_write_md(const bench_table* t, FILE* out);
void bench_table_free(bench_table* t);

#endif
