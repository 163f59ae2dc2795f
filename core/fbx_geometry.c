/* wc_fbx_geometry_read: the control points and polygons of an FBX file's mesh Geometry objects
 * (fbx_geometry.h), binary or ASCII. Two passes over the file: find the arrays (count the
 * geometries, then record where each one's two arrays are), then decode them. */
#include "fbx_geometry.h"
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#define FBX_MAGIC "Kaydara FBX Binary  "   /* then NUL, 0x1A, 0x00 and a uint32 version */
#define FBX_HEADER 27
#define FBX_MAX_RATIO 1032                   /* deflate expands at most ~1032:1 */

/* One array as the file stores it, before decoding. */
typedef struct raw_array {
    int present;
    char type;               /* binary: 'd', 'f', 'i', 'l'; ASCII: 'a' */
    uint32_t encoding;       /* binary: 0 raw, 1 zlib */
    uint64_t count;          /* elements */
    const unsigned char* p;  /* binary: the encoded bytes; ASCII: the text after "a:" */
    size_t bytes;
} raw_array;

typedef struct raw_geometry {
    raw_array points, index;
} raw_geometry;

typedef struct finder {
    const unsigned char* d;
    size_t size;
    raw_geometry* geo;       /* NULL while counting */
    int n_geo;
    const char* name;
    wc_diag* diag;
} finder;

void wc_fbx_geometry_free(wc_fbx_geometries* set) {
    if (!set) return;
    wc_allocator a = set->alloc;
    for (int i = 0; i < set->n && set->g; ++i) {
        wc_free(&a, set->g[i].points);
        wc_free(&a, set->g[i].poly_start);
        wc_free(&a, set->g[i].poly_points);
    }
    wc_free(&a, set->g);
    memset(set, 0, sizeof *set);
}

/* ---- binary ----------------------------------------------------------------------------- */

static uint64_t le(const unsigned char* p, int bytes) {
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = v << 8 | p[i];
    return v;
}

typedef struct node {
    size_t end;              /* first byte after the record */
    uint64_t n_props;
    size_t props, props_end; /* the property list */
    const unsigned char* name;
    size_t name_len;
} node;

static int named(const node* n, const char* s) {
    return n->name_len == strlen(s) && memcmp(n->name, s, n->name_len) == 0;
}

/* The record at off, inside [off, limit). *last: a NULL record (end of its list). */
static wc_status read_node(const finder* f, int wide, size_t off, size_t limit, node* n,
                             int* last) {
    const size_t w = wide ? 8 : 4, head = 3 * w + 1;
    if (off > limit || limit - off < head)
        return wc_fail(f->diag, WC_ERROR_IMPORT,
                       "'%s': FBX record at byte %zu runs past the end of its list (byte %zu)",
                       f->name, off, limit);
    const unsigned char* p = f->d + off;
    const uint64_t end = le(p, (int)w), n_props = le(p + w, (int)w), len = le(p + 2 * w, (int)w);
    const size_t name_len = p[3 * w];
    *last = end == 0 && n_props == 0 && len == 0 && name_len == 0;
    if (*last) return WC_OK;
    if (end <= off + head || end > limit || name_len > end - off - head ||
        len > end - off - head - name_len)
        return wc_fail(f->diag, WC_ERROR_IMPORT,
                       "'%s': FBX record at byte %zu has end offset %llu or property length "
                       "%llu outside its list (bytes %zu..%zu; corrupt file)",
                       f->name, off, (unsigned long long)end, (unsigned long long)len, off, limit);
    n->end = (size_t)end;
    n->n_props = n_props;
    n->name = p + head;
    n->name_len = name_len;
    n->props = off + head + name_len;
    n->props_end = n->props + (size_t)len;
    return WC_OK;
}

static size_t elem_size(char t) {
    switch (t) {
    case 'd': case 'l': return 8;
    case 'f': case 'i': return 4;
    case 'b': case 'c': return 1;
    default: return 0;
    }
}

/* The property at *at (inside [*at, end)): its type, payload and, for arrays, their header.
 * Moves *at past it. */
static wc_status read_prop(const finder* f, size_t* at, size_t end, char* type, raw_array* arr,
                             const unsigned char** str, size_t* str_len) {
    static const char scalar[] = "YCIFDL";
    static const size_t scalar_size[] = {2, 1, 4, 4, 8, 8};
    const size_t off = *at;
    if (off >= end) goto bad;
    *type = (char)f->d[off];
    const char* s = *type ? strchr(scalar, *type) : NULL;
    if (s) {
        if (end - off - 1 < scalar_size[s - scalar]) goto bad;
        *at = off + 1 + scalar_size[s - scalar];
        return WC_OK;
    }
    if (*type == 'S' || *type == 'R') {
        if (end - off - 1 < 4) goto bad;
        const uint64_t len = le(f->d + off + 1, 4);
        if (len > end - off - 5) goto bad;
        *str = f->d + off + 5;
        *str_len = (size_t)len;
        *at = off + 5 + (size_t)len;
        return WC_OK;
    }
    if (elem_size(*type)) {
        if (end - off - 1 < 12) goto bad;
        const unsigned char* h = f->d + off + 1;
        const uint64_t bytes = le(h + 8, 4);
        if (bytes > end - off - 13) goto bad;
        arr->present = 1;
        arr->type = *type;
        arr->count = le(h, 4);
        arr->encoding = (uint32_t)le(h + 4, 4);
        arr->p = h + 12;
        arr->bytes = (size_t)bytes;
        *at = off + 13 + (size_t)bytes;
        return WC_OK;
    }
bad:
    return wc_fail(f->diag, WC_ERROR_IMPORT,
                   "'%s': FBX property at byte %zu runs past its record or has an unknown type "
                   "(corrupt file)", f->name, off);
}

/* A Geometry record's third property is the string "Mesh". */
static wc_status is_mesh_geometry(const finder* f, const node* n, int* mesh) {
    *mesh = 0;
    size_t at = n->props;
    for (uint64_t i = 0; i < n->n_props && i < 3; ++i) {
        char type = 0;
        raw_array arr;
        const unsigned char* s = NULL;
        size_t len = 0;
        wc_status st = read_prop(f, &at, n->props_end, &type, &arr, &s, &len);
        if (st != WC_OK) return st;
        if (i == 2) *mesh = type == 'S' && len == 4 && memcmp(s, "Mesh", 4) == 0;
    }
    return WC_OK;
}

/* The first property of n as an array (Vertices, PolygonVertexIndex). */
static wc_status node_array(const finder* f, const node* n, raw_array* arr) {
    char type = 0;
    const unsigned char* s = NULL;
    size_t len = 0, at = n->props;
    raw_array a;
    memset(&a, 0, sizeof a);
    wc_status st = n->n_props ? read_prop(f, &at, n->props_end, &type, &a, &s, &len) : WC_OK;
    if (st != WC_OK) return st;
    if (!a.present || (type != 'd' && type != 'f' && type != 'i' && type != 'l'))
        return wc_fail(f->diag, WC_ERROR_IMPORT,
                       "'%s': FBX Geometry #%d: %.*s is not an array of numbers (type '%c')",
                       f->name, f->n_geo, (int)n->name_len, (const char*)n->name,
                       type >= 32 && type < 127 ? type : '?');
    *arr = a;
    return WC_OK;
}

/* Walk the list [off, limit) at depth 0 (top level), 1 (Objects) or 2 (a mesh Geometry). */
static wc_status walk_binary(finder* f, int wide, size_t off, size_t limit, int depth) {
    while (off < limit) {
        node n;
        int last = 0;
        wc_status st = read_node(f, wide, off, limit, &n, &last);
        if (st != WC_OK) return st;
        if (last) break;
        if (depth == 0 && named(&n, "Objects")) {
            st = walk_binary(f, wide, n.props_end, n.end, 1);
        } else if (depth == 1 && named(&n, "Geometry")) {
            int mesh = 0;
            st = is_mesh_geometry(f, &n, &mesh);
            if (st == WC_OK && mesh) {
                if (f->n_geo == INT_MAX)
                    return wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': too many FBX Geometry objects", f->name);
                st = walk_binary(f, wide, n.props_end, n.end, 2);
                ++f->n_geo;
            }
        } else if (depth == 2 && f->geo && named(&n, "Vertices")) {
            st = node_array(f, &n, &f->geo[f->n_geo].points);
        } else if (depth == 2 && f->geo && named(&n, "PolygonVertexIndex")) {
            st = node_array(f, &n, &f->geo[f->n_geo].index);
        }
        if (st != WC_OK) return st;
        off = n.end;
    }
    return WC_OK;
}

static wc_status find_binary(finder* f) {
    if (f->size < FBX_HEADER)
        return wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': binary FBX header cut short (%zu bytes)",
                       f->name, f->size);
    const uint64_t version = le(f->d + 23, 4);
    return walk_binary(f, version >= 7500, FBX_HEADER, f->size, 0);
}

/* ---- ASCII ------------------------------------------------------------------------------ */

static int ident_char(unsigned char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '|' || c == '-';
}

static int text_is(const unsigned char* p, size_t n, const char* s) {
    return n == strlen(s) && memcmp(p, s, n) == 0;
}

static size_t skip_blank(const finder* f, size_t i) {
    while (i < f->size && (f->d[i] == ' ' || f->d[i] == '\t' || f->d[i] == '\r' || f->d[i] == '\n'))
        ++i;
    return i;
}

/* `*N { a: ... }` at i (after a key's colon) -> arr; *next: past the closing brace. */
static wc_status ascii_array(const finder* f, size_t i, const char* key, raw_array* arr,
                               size_t* next) {
    i = skip_blank(f, i);
    uint64_t count = 0;
    int digits = 0;
    if (i < f->size && f->d[i] == '*')
        for (++i; i < f->size && f->d[i] >= '0' && f->d[i] <= '9' && digits < 12; ++i, ++digits)
            count = 10 * count + (uint64_t)(f->d[i] - '0');
    i = skip_blank(f, i);
    int ok = digits > 0 && digits < 12 && i < f->size && f->d[i] == '{';
    if (ok) {
        i = skip_blank(f, i + 1);
        ok = f->size - i >= 2 && f->d[i] == 'a' && f->d[i + 1] == ':';
    }
    const unsigned char* close = ok ? memchr(f->d + i + 2, '}', f->size - i - 2) : NULL;
    if (!close)
        return wc_fail(f->diag, WC_ERROR_IMPORT,
                       "'%s': FBX Geometry #%d: %s is not in the form `*N { a: ... }` (FBX 7 "
                       "ASCII; corrupt or older file)", f->name, f->n_geo, key);
    arr->present = 1;
    arr->type = 'a';
    arr->count = count;
    arr->p = f->d + i + 2;
    arr->bytes = (size_t)(close - arr->p);
    *next = (size_t)(close - f->d) + 1;
    return WC_OK;
}

/* Keys and braces, skipping comments (';' to the end of the line) and strings. A brace opens a
 * block of the key before it; a Geometry block under Objects whose last string is "Mesh" is a
 * mesh geometry, and its Vertices and PolygonVertexIndex arrays are recorded. */
static wc_status find_ascii(finder* f) {
    int depth = 0, mesh_depth = -1;
    int in_objects = 0;                     /* the open top-level block is Objects */
    const unsigned char* key = NULL;        /* the last key at this depth, and its length */
    size_t key_len = 0;
    const unsigned char* str = NULL;        /* the last string since that key */
    size_t str_len = 0;
    raw_geometry scratch;
    for (size_t i = 0; i < f->size;) {
        const unsigned char c = f->d[i];
        if (c == ';') {
            const unsigned char* nl = memchr(f->d + i, '\n', f->size - i);
            i = nl ? (size_t)(nl - f->d) + 1 : f->size;
        } else if (c == '"') {
            const unsigned char* q = memchr(f->d + i + 1, '"', f->size - i - 1);
            str = f->d + i + 1;
            str_len = q ? (size_t)(q - str) : 0;
            i = q ? (size_t)(q - f->d) + 1 : f->size;
        } else if (c == '{') {
            ++depth;
            if (depth == 1) in_objects = key && text_is(key, key_len, "Objects");
            if (depth == 2 && in_objects && key && text_is(key, key_len, "Geometry") && str &&
                text_is(str, str_len, "Mesh")) {
                if (f->n_geo == INT_MAX)
                    return wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': too many FBX Geometry objects", f->name);
                mesh_depth = depth;
            }
            key = str = NULL;
            ++i;
        } else if (c == '}') {
            if (depth == mesh_depth) {
                mesh_depth = -1;
                ++f->n_geo;
            }
            if (depth > 0) --depth;
            key = str = NULL;
            ++i;
        } else if (ident_char(c)) {
            size_t j = i;
            while (j < f->size && ident_char(f->d[j])) ++j;
            if (j < f->size && f->d[j] == ':' && (i == 0 || !ident_char(f->d[i - 1]))) {
                key = f->d + i;
                key_len = j - i;
                str = NULL;
                raw_array* arr = NULL;
                raw_geometry* into = f->geo ? &f->geo[f->n_geo] : &scratch;   /* counting */
                if (depth == mesh_depth && text_is(key, key_len, "Vertices"))
                    arr = &into->points;
                else if (depth == mesh_depth && text_is(key, key_len, "PolygonVertexIndex"))
                    arr = &into->index;
                if (arr) {
                    wc_status st = ascii_array(f, j + 1, text_is(key, key_len, "Vertices")
                                                          ? "Vertices" : "PolygonVertexIndex",
                                               arr, &j);
                    if (st != WC_OK) return st;
                    key = NULL;
                } else {
                    ++j;
                }
            }
            i = j;
        } else {
            ++i;
        }
    }
    if (mesh_depth >= 0)
        return wc_fail(f->diag, WC_ERROR_IMPORT,
                       "'%s': FBX Geometry #%d has no closing brace (the file is cut short)",
                       f->name, f->n_geo);
    return WC_OK;
}

/* ---- decoding --------------------------------------------------------------------------- */

/* Element i of a decoded binary array (little-endian) as a double or an integer. */
static double bin_double(const unsigned char* p, char type, size_t i) {
    if (type == 'd') {
        uint64_t u = le(p + 8 * i, 8);
        double d;
        memcpy(&d, &u, sizeof d);
        return d;
    }
    if (type == 'f') {
        uint32_t u = (uint32_t)le(p + 4 * i, 4);
        float x;
        memcpy(&x, &u, sizeof x);
        return (double)x;
    }
    if (type == 'i') return (double)(int32_t)(uint32_t)le(p + 4 * i, 4);
    return (double)(int64_t)le(p + 8 * i, 8);
}

static int64_t bin_int(const unsigned char* p, char type, size_t i) {
    if (type == 'i') return (int32_t)(uint32_t)le(p + 4 * i, 4);
    if (type == 'l') return (int64_t)le(p + 8 * i, 8);
    const double d = bin_double(p, type, i);
    return d >= -9.0e18 && d <= 9.0e18 ? (int64_t)d : INT64_MIN;
}

/* The next number of an ASCII array at *i (separated by commas and white space). */
static int ascii_number(const raw_array* a, size_t* i, double* out) {
    while (*i < a->bytes && (a->p[*i] == ',' || a->p[*i] == ' ' || a->p[*i] == '\t' ||
                             a->p[*i] == '\r' || a->p[*i] == '\n'))
        ++*i;
    char buf[64];
    size_t n = 0;
    while (*i < a->bytes && n + 1 < sizeof buf && a->p[*i] != ',' && a->p[*i] != ' ' &&
           a->p[*i] != '\t' && a->p[*i] != '\r' && a->p[*i] != '\n')
        buf[n++] = (char)a->p[(*i)++];
    buf[n] = '\0';
    char* end = NULL;
    *out = n ? strtod(buf, &end) : 0.0;
    return n > 0 && end == buf + n;
}

/* Decoded numbers of a: *out (a->count doubles, allocated with alloc). */
static wc_status decode(const finder* f, const wc_allocator* alloc, const raw_array* a,
                          const char* what, int geo, double** out) {
    *out = NULL;
    const size_t es = a->type == 'a' ? 1 : elem_size(a->type);
    if (a->count > (uint64_t)INT_MAX || (a->type != 'a' && a->count > SIZE_MAX / es))
        return wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': FBX Geometry #%d: %s count %llu is too large",
                       f->name, geo, what, (unsigned long long)a->count);
    const size_t bytes = (size_t)a->count * es;
    unsigned char* inflated = NULL;
    const unsigned char* p = a->p;
    if (a->type != 'a' && a->encoding == 0 && bytes != a->bytes)
        return wc_fail(f->diag, WC_ERROR_IMPORT,
                       "'%s': FBX Geometry #%d: %s holds %zu bytes for %llu elements of %zu "
                       "bytes (corrupt file)", f->name, geo, what, a->bytes,
                       (unsigned long long)a->count, es);
    if (a->type != 'a' && a->encoding == 1) {
        if (bytes / FBX_MAX_RATIO > a->bytes || bytes > ULONG_MAX || a->bytes > ULONG_MAX)
            return wc_fail(f->diag, WC_ERROR_IMPORT,
                           "'%s': FBX Geometry #%d: %s claims %llu elements from %zu compressed "
                           "bytes (corrupt file)", f->name, geo, what,
                           (unsigned long long)a->count, a->bytes);
        inflated = WC_NEW(alloc, unsigned char, bytes + 1);
        if (!inflated) return wc_fail(f->diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", f->name);
        uLongf got = (uLongf)bytes;
        const int z = uncompress(inflated, &got, a->p, (uLong)a->bytes);
        if (z != Z_OK || got != bytes) {
            wc_free(alloc, inflated);
            return wc_fail(f->diag, WC_ERROR_IMPORT,
                           "'%s': FBX Geometry #%d: %s does not inflate to %zu bytes (zlib: %s, "
                           "%lu bytes; corrupt file)", f->name, geo, what, bytes,
                           z == Z_OK ? "ok" : zError(z), (unsigned long)got);
        }
        p = inflated;
    } else if (a->type != 'a' && a->encoding != 0) {
        return wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': FBX Geometry #%d: %s has unknown encoding %u",
                       f->name, geo, what, (unsigned)a->encoding);
    }
    double* v = WC_NEW(alloc, double, a->count + 1);
    wc_status st = v ? WC_OK : wc_fail(f->diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", f->name);
    size_t at = 0;
    for (size_t k = 0; k < a->count && st == WC_OK; ++k) {
        if (a->type != 'a') {
            v[k] = a->type == 'i' || a->type == 'l' ? (double)bin_int(p, a->type, k)
                                                    : bin_double(p, a->type, k);
        } else if (!ascii_number(a, &at, &v[k])) {
            st = wc_fail(f->diag, WC_ERROR_IMPORT,
                         "'%s': FBX Geometry #%d: %s has %zu numbers where *%llu says (or a "
                         "number that does not parse)", f->name, geo, what, k,
                         (unsigned long long)a->count);
        }
    }
    if (st == WC_OK && a->type == 'a') {
        double extra;
        if (ascii_number(a, &at, &extra))
            st = wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': FBX Geometry #%d: %s has more numbers "
                         "than *%llu", f->name, geo, what, (unsigned long long)a->count);
    }
    wc_free(alloc, inflated);
    if (st != WC_OK) wc_free(alloc, v);
    else *out = v;
    return st;
}

/* One geometry from its raw arrays. Index values arrive as doubles (exact below 2^53). */
static wc_status build(const finder* f, const wc_allocator* alloc, const raw_geometry* r, int geo,
                         wc_fbx_geometry* g) {
    double* pts = NULL;
    double* idx = NULL;
    wc_status st = r->points.present ? decode(f, alloc, &r->points, "Vertices", geo, &pts) : WC_OK;
    if (st == WC_OK && r->index.present)
        st = decode(f, alloc, &r->index, "PolygonVertexIndex", geo, &idx);
    const size_t n_pts = r->points.present ? (size_t)r->points.count : 0;
    const size_t n_idx = r->index.present ? (size_t)r->index.count : 0;
    if (st == WC_OK && n_pts % 3)
        st = wc_fail(f->diag, WC_ERROR_IMPORT, "'%s': FBX Geometry #%d: Vertices has %zu numbers, "
                     "not a multiple of 3", f->name, geo, n_pts);
    if (st == WC_OK) {
        g->n_points = (int)(n_pts / 3);
        g->points = pts;
        pts = NULL;
        int n_polys = 0;
        for (size_t k = 0; k < n_idx; ++k) n_polys += idx[k] < 0 || k + 1 == n_idx;
        g->poly_start = WC_NEW(alloc, int, (size_t)n_polys + 1);
        g->poly_points = WC_NEW(alloc, int, n_idx + 1);
        if (!g->poly_start || !g->poly_points)
            st = wc_fail(f->diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", f->name);
        int q = 0;
        for (size_t k = 0; k < n_idx && st == WC_OK; ++k) {
            const double v = idx[k] < 0 ? -idx[k] - 1.0 : idx[k];
            if (!(v < (double)g->n_points))
                st = wc_fail(f->diag, WC_ERROR_IMPORT,
                             "'%s': FBX Geometry #%d: PolygonVertexIndex entry %zu names control "
                             "point %.0f of %d (corrupt file)", f->name, geo, k, v, g->n_points);
            else g->poly_points[k] = (int)v;
            if (k == 0 || idx[k - 1] < 0) g->poly_start[q++] = (int)k;
        }
        if (st == WC_OK) {
            g->poly_start[q] = (int)n_idx;
            g->n_polys = q;
        }
    }
    wc_free(alloc, pts);
    wc_free(alloc, idx);
    return st;
}

wc_status wc_fbx_geometry_read(wc_fbx_geometries* out, const wc_allocator* alloc,
                                 const void* data, size_t size, const char* name, wc_diag* diag) {
    if (!out) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "FBX geometry: out is NULL");
    memset(out, 0, sizeof *out);
    if (alloc) out->alloc = *alloc;
    if (!data && size) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "FBX geometry: data is NULL");
    finder f = {data, size, NULL, 0, name, diag};
    const int binary = size >= sizeof FBX_MAGIC && memcmp(data, FBX_MAGIC, sizeof FBX_MAGIC) == 0;
    wc_status st = binary ? find_binary(&f) : find_ascii(&f);   /* count */
    if (st != WC_OK || f.n_geo == 0) return st;
    const int n = f.n_geo;
    f.geo = WC_NEW(&out->alloc, raw_geometry, (size_t)n);
    out->g = WC_NEW(&out->alloc, wc_fbx_geometry, (size_t)n);
    out->n = n;
    if (!f.geo || !out->g) st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", name);
    f.n_geo = 0;
    if (st == WC_OK) st = binary ? find_binary(&f) : find_ascii(&f);   /* record */
    for (int i = 0; i < n && st == WC_OK; ++i) st = build(&f, &out->alloc, &f.geo[i], i, &out->g[i]);
    wc_free(&out->alloc, f.geo);
    if (st != WC_OK) wc_fbx_geometry_free(out);
    return st;
}
