/* Pre-checks before assimp (see import_precheck.h).
 *
 * 1. PLY without "end_header": assimp 5.2.5's PLY reader never returns (it keeps allocating)
 *    on a PLY whose header has no end_header line, e.g. the 21 bytes "ply\nformat ascii 1.0\n",
 *    or has the word only inside another line ("0.5 0 1 1end_header"), or followed by anything
 *    but a blank or a line end ("end_header\x1a...").
 *    assimp takes a buffer as PLY when it starts with "ply" (its signature check), so such a
 *    buffer must hold an end_header line within its first WC_PRECHECK_PLY_HEADER_MAX bytes. */
#include "import_precheck.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int starts_ply(const unsigned char* b, size_t n) {
    if (n < 3) return 0;
    for (int i = 0; i < 3; ++i) {
        unsigned char c = b[i];
        if (c >= 'A' && c <= 'Z') c = (unsigned char)(c - 'A' + 'a');
        if (c != (unsigned char)"ply"[i]) return 0;
    }
    return 1;
}

static int blank_or_eol(unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/* word as a token at the start of a line (after optional blanks), as a PLY header's keywords are:
 * followed by a blank, a line end, or the end of the bytes (whole: n is the whole input) */
static int holds_line(const unsigned char* b, size_t n, const char* word, int whole) {
    size_t m = strlen(word);
    for (size_t i = 0; i + m <= n; ++i) {
        if (b[i] != (unsigned char)word[0] || memcmp(b + i, word, m) != 0) continue;
        size_t j = i;
        while (j > 0 && (b[j - 1] == ' ' || b[j - 1] == '\t')) --j;
        if (j == 0 || (b[j - 1] != '\n' && b[j - 1] != '\r')) continue;
        if (i + m < n ? blank_or_eol(b[i + m]) : whole) return 1;
    }
    return 0;
}

static weft_status no_end_header(const char* name, wc_diag* diag) {
    return wc_fail(diag, WEFT_ERROR_IMPORT,
                   "cannot import '%s': a PLY file whose header has no end_header line within its "
                   "first %u bytes (truncated or damaged header)", name, WC_PRECHECK_PLY_HEADER_MAX);
}

weft_status wc_import_precheck_memory(const unsigned char* data, size_t size, const char* name, wc_diag* diag) {
    if (starts_ply(data, size)) {
        size_t n = size < WC_PRECHECK_PLY_HEADER_MAX ? size : WC_PRECHECK_PLY_HEADER_MAX;
        if (!holds_line(data, n, "end_header", n == size)) return no_end_header(name, diag);
    }
    return WEFT_OK;
}

weft_status wc_import_precheck_file(const char* path, const unsigned char* head, size_t n_head, wc_diag* diag) {
    if (!starts_ply(head, n_head)) return WEFT_OK;
    unsigned char* buf = malloc(WC_PRECHECK_PLY_HEADER_MAX);
    if (!buf) return wc_fail(diag, WEFT_ERROR_OUT_OF_MEMORY, "import '%s': out of memory", path);
    errno = 0;
    FILE* f = fopen(path, "rb");
    if (!f) {
        free(buf);
        return wc_fail(diag, WEFT_ERROR_IO, "cannot open '%s': %s", path, errno ? strerror(errno) : "fopen failed");
    }
    size_t n = fread(buf, 1, WC_PRECHECK_PLY_HEADER_MAX, f);
    int whole = n < WC_PRECHECK_PLY_HEADER_MAX || fgetc(f) == EOF;
    fclose(f);
    int ok = holds_line(buf, n, "end_header", whole);
    free(buf);
    return ok ? WEFT_OK : no_end_header(path, diag);
}
