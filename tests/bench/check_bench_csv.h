/* What the `weft bench` checks share: weft's CSV (no quoted fields) split into cells, columns by
 * name, the header checked, and a PNG checked for well-formedness. Header-only (static inline) so
 * that CHECK counts in the including test's own counters (check.h). */
#ifndef WEFT_TESTS_CHECK_BENCH_CSV_H
#define WEFT_TESTS_CHECK_BENCH_CSV_H
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
static inline void csv_parse(csv* c, const char* path) {
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

static inline int col(const csv* c, const char* name) {
    for (int k = 0; k < c->n_cols && k < MAX_COLS; ++k)
        if (!strcmp(c->cell[0][k], name)) return k;
    fprintf(stderr, "no column %s\n", name);
    return -1;
}

static inline const char* get(const csv* c, int row, const char* name) {
    int k = col(c, name);
    return k >= 0 ? c->cell[row + 1][k] : "";
}

/* The cell as a number; NAN when it is not one. */
static inline double num(const csv* c, int row, const char* name) {
    const char* s = get(c, row, name);
    char* end = NULL;
    double v = strtod(s, &end);
    return (end != s && *end == '\0') ? v : NAN;
}

static inline void check_header(const csv* c, const char* const* expected, int n) {
    CHECK_EQ_INT(c->n_cols, n);
    for (int k = 0; k < n && k < c->n_cols; ++k) {
        int same = !strcmp(c->cell[0][k], expected[k]);
        CHECK(same);
        if (!same) fprintf(stderr, "  column %d: %s, expected %s\n", k, c->cell[0][k], expected[k]);
    }
    for (int r = 1; r <= c->n_rows; ++r) CHECK_EQ_INT(c->row_cols[r], n);
}

/* ---- PNG ---- */

static inline unsigned long crc32_png(const unsigned char* p, size_t n) {
    unsigned long c = 0xffffffffUL;
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320UL & (0UL - (c & 1UL)));
    }
    return c ^ 0xffffffffUL;
}

static inline unsigned long be32(const unsigned char* p) {
    return ((unsigned long)p[0] << 24) | ((unsigned long)p[1] << 16) | ((unsigned long)p[2] << 8) | p[3];
}

/* 1 when the file is a well-formed PNG of at least min_w x min_h pixels. */
static inline int png_ok(const char* path, unsigned long min_w, unsigned long min_h) {
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

#endif
