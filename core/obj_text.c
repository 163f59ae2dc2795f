/* wc_obj_text_read: the `v` and `f` lines of an OBJ file, in two passes over a NUL-terminated
 * copy of the text (count, then fill). */
#include "obj_text.h"
#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

void wc_obj_text_free(wc_obj_text* t) {
    if (!t) return;
    wc_allocator a = t->alloc;
    wc_free(&a, t->v);
    wc_free(&a, t->face_start);
    wc_free(&a, t->face_v);
    memset(t, 0, sizeof *t);
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

static const char* skip_space(const char* s) {
    while (is_space(*s)) ++s;
    return s;
}

/* Line keyword: "v" or "f" followed by white space. */
static int keyword(const char* s, char k) { return s[0] == k && is_space(s[1]); }

typedef struct scan {
    wc_obj_text* t;
    int fill;         /* 0: count into n_v, n_faces, n_corners; 1: write the arrays too */
    long long n_corners;
    long long cap;    /* face_v's length when filling: the polygons' corners (a point's or a
                         line's corners are read before they are known not to be a polygon's) */
    const char* name;
    wc_diag* diag;
} scan;

static wc_status read_v(scan* s, const char* p) {
    if (s->fill) {
        float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        int n = 0;
        for (; n < 4; ++n) {
            char* end;
            float x = strtof(p, &end);
            if (end == p) break;
            c[n] = x;
            p = end;
        }
        float* o = s->t->v + 3 * (size_t)s->t->n_v;
        const float w = n == 4 && c[3] != 0.0f ? c[3] : 1.0f;   /* homogeneous, as assimp */
        for (int k = 0; k < 3; ++k) o[k] = c[k] / w;
    }
    if (s->t->n_v == INT_MAX / 3)
        return wc_fail(s->diag, WC_ERROR_OUT_OF_RANGE, "'%s': too many v lines", s->name);
    ++s->t->n_v;
    return WC_OK;
}

static wc_status read_f(scan* s, const char* p, int line) {
    wc_obj_text* t = s->t;
    long long first = s->n_corners;
    int k = 0;
    for (p = skip_space(p); *p && *p != '\n' && *p != '#'; p = skip_space(p)) {
        char* end;
        errno = 0;
        long i = strtol(p, &end, 10);
        if (end == p || errno || i == 0 || i > t->n_v || i < -(long)t->n_v)
            return wc_fail(s->diag, WC_ERROR_IMPORT,
                           "'%s' line %d: face corner %d does not name one of the %d v lines "
                           "before it", s->name, line, k + 1, t->n_v);
        if (s->fill && s->n_corners < s->cap) t->face_v[s->n_corners] = i > 0 ? (int)i - 1 : t->n_v + (int)i;
        ++s->n_corners;
        ++k;
        while (*end && !is_space(*end) && *end != '\n') ++end;   /* "/vt/vn" */
        p = end;
    }
    if (k < 3) {   /* points and lines: not polygons */
        s->n_corners = first;
        return WC_OK;
    }
    if (s->n_corners > INT_MAX || t->n_faces == INT_MAX - 1)
        return wc_fail(s->diag, WC_ERROR_OUT_OF_RANGE, "'%s': too many faces", s->name);
    if (s->fill) t->face_start[t->n_faces + 1] = (int)s->n_corners;
    ++t->n_faces;
    return WC_OK;
}

static wc_status scan_text(scan* s, const char* text) {
    s->t->n_v = 0;
    s->t->n_faces = 0;
    s->n_corners = 0;
    int line = 1;
    for (const char* p = text; *p; ++line) {
        const char* q = skip_space(p);
        wc_status st = WC_OK;
        if (keyword(q, 'v')) st = read_v(s, q + 1);
        else if (keyword(q, 'f')) st = read_f(s, q + 1, line);
        if (st != WC_OK) return st;
        p = strchr(p, '\n');
        if (!p) break;
        ++p;
    }
    return WC_OK;
}

wc_status wc_obj_text_read(wc_obj_text* out, const wc_allocator* alloc, const char* text,
                             size_t size, const char* name, wc_diag* diag) {
    memset(out, 0, sizeof *out);
    if (alloc) out->alloc = *alloc;
    const wc_allocator* A = &out->alloc;
    char* buf = WC_NEW(A, char, size + 1);
    if (!buf) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", name);
    /* NUL-terminated copy; a backslash before the end of a line joins the next line to it */
    size_t n = 0;
    for (size_t i = 0; i < size; ++i) {
        char c = text[i];
        if (c == '\0') c = ' ';
        if (c == '\\') {
            size_t j = i + 1;
            if (j < size && text[j] == '\r') ++j;
            if (j < size && text[j] == '\n') {
                buf[n++] = ' ';
                i = j;
                continue;
            }
        }
        buf[n++] = c;
    }
    buf[n] = '\0';

    scan s;
    memset(&s, 0, sizeof s);
    s.t = out;
    s.name = name;
    s.diag = diag;
    wc_status st = scan_text(&s, buf);
    if (st == WC_OK) {
        out->v = WC_NEW(A, float, 3 * (size_t)out->n_v + 1);
        out->face_start = WC_NEW(A, int, (size_t)out->n_faces + 1);
        out->face_v = WC_NEW(A, int, (size_t)s.n_corners + 1);
        if (!out->v || !out->face_start || !out->face_v)
            st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory for %d v lines", name,
                         out->n_v);
    }
    if (st == WC_OK) {
        s.fill = 1;
        s.cap = s.n_corners;
        st = scan_text(&s, buf);
    }
    wc_free(A, buf);
    if (st != WC_OK) {
        wc_obj_text_free(out);
        memset(out, 0, sizeof *out);
    }
    return st;
}
