/* Pre-checks before assimp (see import_precheck.h).
 *
 * 1. PLY without "end_header": assimp 5.2.5's PLY reader never returns (it keeps allocating)
 *    on a PLY whose header has no end_header line, e.g. the 21 bytes "ply\nformat ascii 1.0\n",
 *    or has the word only inside another line ("0.5 0 1 1end_header"), or followed by anything
 *    but a blank or a line end ("end_header\x1a...").
 *    assimp takes a buffer as PLY when it starts with "ply" (its signature check), so such a
 *    buffer must hold an end_header line within its first WC_PRECHECK_PLY_HEADER_MAX bytes.
 * 2. PLY declaring one element twice: with two "element vertex" lines in the header, assimp
 *    5.2.5's PLY reader corrupts its heap (ASan: a bad free when the scene is released; found by
 *    fuzz_import). The header's element names must be distinct. */
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

/* The first element name declared twice in the header (the bytes before end_header) into dup;
 * 0 when every name is distinct. Names are compared on their first 31 characters; a header
 * with more than 64 elements is judged on the first 64 (real files have 2-4). */
static int duplicate_element(const unsigned char* b, size_t n, char dup[32]) {
    char names[64][32];
    int count = 0;
    size_t i = 0;
    while (i < n) {
        size_t end = i;
        while (end < n && b[end] != '\n' && b[end] != '\r') ++end;
        size_t k = i;
        while (k < end && (b[k] == ' ' || b[k] == '\t')) ++k;
        if (end - k >= 10 && memcmp(b + k, "end_header", 10) == 0) break;
        if (end - k > 8 && memcmp(b + k, "element", 7) == 0 && (b[k + 7] == ' ' || b[k + 7] == '\t')) {
            k += 8;
            while (k < end && (b[k] == ' ' || b[k] == '\t')) ++k;
            char name[32];
            size_t m = 0;
            while (k < end && b[k] != ' ' && b[k] != '\t' && m < sizeof name - 1) name[m++] = (char)b[k++];
            name[m] = '\0';
            for (int e = 0; e < count; ++e)
                if (strcmp(names[e], name) == 0) {
                    memcpy(dup, name, m + 1);
                    return 1;
                }
            if (count < 64) memcpy(names[count++], name, m + 1);
        }
        i = end + 1;
    }
    return 0;
}

static wc_status ply_header(const unsigned char* b, size_t n, int whole, const char* name, wc_diag* diag);

static wc_status no_end_header(const char* name, wc_diag* diag) {
    return wc_fail(diag, WC_ERROR_IMPORT,
                   "cannot import '%s': a PLY file whose header has no end_header line within its "
                   "first %u bytes (truncated or damaged header)", name, WC_PRECHECK_PLY_HEADER_MAX);
}

wc_status wc_import_precheck_memory(const unsigned char* data, size_t size, const char* name, wc_diag* diag) {
    if (starts_ply(data, size)) {
        size_t n = size < WC_PRECHECK_PLY_HEADER_MAX ? size : WC_PRECHECK_PLY_HEADER_MAX;
        return ply_header(data, n, n == size, name, diag);
    }
    return WC_OK;
}

wc_status wc_import_precheck_file(const char* path, const unsigned char* head, size_t n_head, wc_diag* diag) {
    if (!starts_ply(head, n_head)) return WC_OK;
    unsigned char* buf = malloc(WC_PRECHECK_PLY_HEADER_MAX);
    if (!buf) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "import '%s': out of memory", path);
    errno = 0;
    FILE* f = fopen(path, "rb");
    if (!f) {
        free(buf);
        return wc_fail(diag, WC_ERROR_IO, "cannot open '%s': %s", path, errno ? strerror(errno) : "fopen failed");
    }
    size_t n = fread(buf, 1, WC_PRECHECK_PLY_HEADER_MAX, f);
    int whole = n < WC_PRECHECK_PLY_HEADER_MAX || fgetc(f) == EOF;
    fclose(f);
    wc_status st = ply_header(buf, n, whole, path, diag);
    free(buf);
    return st;
}

static wc_status ply_header(const unsigned char* b, size_t n, int whole, const char* name, wc_diag* diag) {
    if (!holds_line(b, n, "end_header", whole)) return no_end_header(name, diag);
    char dup[32];
    if (duplicate_element(b, n, dup))
        return wc_fail(diag, WC_ERROR_IMPORT,
                       "cannot import '%s': the PLY header declares the element '%s' twice (damaged header)", name, dup);
    return WC_OK;
}
