/* Minimal FBX 7.4 / 7.5 files written by the tests (test_fbx_order.c): Geometry objects of type "Mesh"
 * with the given control points and polygons, Models with a Lcl Translation showing them,
 * connected to the root; binary (node records with 32-bit offsets, arrays raw or
 * zlib-deflated; 32-bit record offsets for 7400, 64-bit for 7500) or ASCII (7.4, one geometry, one
 * model).
 * Enough for assimp 5.2 to import, and written independently of core/fbx_geometry.c. Also
 * hands back the byte offsets a corruption test patches. Header-only; polygons of at most 8
 * corners. */
#ifndef WEFT_TESTS_FBX_WRITER_H
#define WEFT_TESTS_FBX_WRITER_H
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

typedef struct fw_mesh {
    int n_points;
    const double* points;     /* (n_points x 3) */
    int n_polys;
    const int* sizes;         /* (n_polys) corners */
    const int* corners;       /* control point of each corner */
    double translation[3];    /* the Model's Lcl Translation */
    int compress;             /* binary: deflate the arrays */
    int version;              /* binary: 7400 (32-bit record offsets, also for 0) or 7500 (64-bit) */
    const int* materials;     /* binary: each polygon's material index (a LayerElementMaterial
                                 mapped by polygon), or NULL */
} fw_mesh;

typedef struct fw_buf {
    unsigned char* b;
    size_t n, cap;
    /* offsets of interest, filled while writing */
    size_t geometry_record;   /* the Geometry record (its EndOffset field) */
    size_t vertices_array;    /* the Vertices array property's type byte */
    size_t index_array;       /* the PolygonVertexIndex array property's type byte */
    int wide;                 /* 64-bit record header fields (version 7500) */
} fw_buf;

static inline void fw_put(fw_buf* w, const void* p, size_t n) {
    if (w->n + n > w->cap) {
        w->cap = 2 * (w->n + n) + 256;
        w->b = realloc(w->b, w->cap);
        if (!w->b) abort();
    }
    memcpy(w->b + w->n, p, n);
    w->n += n;
}

static inline void fw_u32(fw_buf* w, uint32_t v) {
    unsigned char b[4] = {(unsigned char)v, (unsigned char)(v >> 8), (unsigned char)(v >> 16),
                          (unsigned char)(v >> 24)};
    fw_put(w, b, 4);
}

static inline void fw_patch32(fw_buf* w, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) w->b[at + (size_t)i] = (unsigned char)(v >> (8 * i));
}

/* Bytes of one record header field: 4, or 8 from version 7500. */
static inline size_t fw_field(const fw_buf* w) { return w->wide ? 8 : 4; }

/* NULL record: the end of a list of records. */
static inline void fw_null(fw_buf* w) {
    static const unsigned char zero[25] = {0};
    fw_put(w, zero, 3 * fw_field(w) + 1);
}

/* A record: header with placeholders (zero), then the name. Returns the record's offset. */
static inline size_t fw_begin(fw_buf* w, const char* name) {
    size_t at = w->n;
    for (int i = 0; i < (w->wide ? 6 : 3); ++i) fw_u32(w, 0);
    unsigned char len = (unsigned char)strlen(name);
    fw_put(w, &len, 1);
    fw_put(w, name, len);
    return at;
}

/* After the properties (n of them, from props_at on). */
static inline void fw_props(fw_buf* w, size_t rec, uint32_t n) {
    const size_t f = fw_field(w), name_end = rec + 3 * f + 1 + w->b[rec + 3 * f];
    fw_patch32(w, rec + f, n);
    fw_patch32(w, rec + 2 * f, (uint32_t)(w->n - name_end));
}

/* End a record; with children, the NULL record that closes their list first. */
static inline void fw_end(fw_buf* w, size_t rec, int children) {
    if (children) fw_null(w);
    fw_patch32(w, rec, (uint32_t)w->n);
}

static inline void fw_str(fw_buf* w, const char* s, size_t len) {
    fw_put(w, "S", 1);
    fw_u32(w, (uint32_t)len);
    fw_put(w, s, len);
}

static inline void fw_i32(fw_buf* w, int32_t v) {
    fw_put(w, "I", 1);
    fw_u32(w, (uint32_t)v);
}

static inline void fw_i64(fw_buf* w, int64_t v) {
    fw_put(w, "L", 1);
    fw_u32(w, (uint32_t)(uint64_t)v);
    fw_u32(w, (uint32_t)((uint64_t)v >> 32));
}

static inline void fw_f64(fw_buf* w, double d) {
    uint64_t u;
    memcpy(&u, &d, sizeof u);
    fw_put(w, "D", 1);
    fw_u32(w, (uint32_t)u);
    fw_u32(w, (uint32_t)(u >> 32));
}

/* An array property of type 'd' or 'i' (little-endian elements in raw, n elements). */
static inline void fw_array(fw_buf* w, char type, const unsigned char* raw, uint32_t n,
                            size_t elem, int compress) {
    fw_put(w, &type, 1);
    fw_u32(w, n);
    size_t bytes = (size_t)n * elem;
    if (!compress) {
        fw_u32(w, 0);
        fw_u32(w, (uint32_t)bytes);
        fw_put(w, raw, bytes);
        return;
    }
    uLongf zn = compressBound((uLong)bytes);
    unsigned char* z = malloc(zn);
    if (!z || compress2(z, &zn, raw, (uLong)bytes, 6) != Z_OK) abort();
    fw_u32(w, 1);
    fw_u32(w, (uint32_t)zn);
    fw_put(w, z, zn);
    free(z);
}

/* A leaf record with one integer or string property. */
static inline void fw_leaf_i32(fw_buf* w, const char* name, int32_t v) {
    size_t r = fw_begin(w, name);
    fw_i32(w, v);
    fw_props(w, r, 1);
    fw_end(w, r, 0);
}

static inline void fw_leaf_str(fw_buf* w, const char* name, const char* v) {
    size_t r = fw_begin(w, name);
    fw_str(w, v, strlen(v));
    fw_props(w, r, 1);
    fw_end(w, r, 0);
}

/* Little-endian int32 elements (n of them), malloc'd. */
static inline unsigned char* fw_le32(const int* v, int n) {
    unsigned char* raw = malloc(4 * (size_t)n + 4);
    if (!raw) abort();
    for (int i = 0; i < n; ++i)
        for (int b = 0; b < 4; ++b) raw[4 * (size_t)i + (size_t)b] = (unsigned char)((uint32_t)v[i] >> (8 * b));
    return raw;
}

/* The polygons' materials: a LayerElementMaterial (by polygon, index to direct) and the Layer
 * that uses it. */
static inline void fw_materials(fw_buf* w, const fw_mesh* m) {
    size_t le = fw_begin(w, "LayerElementMaterial");
    fw_i32(w, 0);
    fw_props(w, le, 1);
    fw_leaf_i32(w, "Version", 101);
    fw_leaf_str(w, "Name", "");
    fw_leaf_str(w, "MappingInformationType", "ByPolygon");
    fw_leaf_str(w, "ReferenceInformationType", "IndexToDirect");
    size_t r = fw_begin(w, "Materials");
    unsigned char* raw = fw_le32(m->materials, m->n_polys);
    fw_array(w, 'i', raw, (uint32_t)m->n_polys, 4, 0);
    free(raw);
    fw_props(w, r, 1);
    fw_end(w, r, 0);
    fw_end(w, le, 1);
    size_t layer = fw_begin(w, "Layer");
    fw_i32(w, 0);
    fw_props(w, layer, 1);
    fw_leaf_i32(w, "Version", 100);
    size_t e = fw_begin(w, "LayerElement");
    fw_props(w, e, 0);
    fw_leaf_str(w, "Type", "LayerElementMaterial");
    fw_leaf_i32(w, "TypedIndex", 0);
    fw_end(w, e, 1);
    fw_end(w, layer, 1);
}

/* A Properties70 block of one P record: four strings, then n doubles. */
static inline void fw_properties70(fw_buf* w, const char* name, const char* type,
                                   const char* label, const char* flags, const double* v, int n) {
    size_t p70 = fw_begin(w, "Properties70");
    fw_props(w, p70, 0);
    size_t p = fw_begin(w, "P");
    const char* s[4] = {name, type, label, flags};
    for (int i = 0; i < 4; ++i) fw_str(w, s[i], strlen(s[i]));
    for (int i = 0; i < n; ++i) fw_f64(w, v[i]);
    fw_props(w, p, (uint32_t)(4 + n));
    fw_end(w, p, 0);
    fw_end(w, p70, 1);
}

/* Geometry g (id 1001 + g, named "sheet" then "sheet1", ...) of m. */
static inline void fw_geometry(fw_buf* w, const fw_mesh* m, int g) {
    char name[32];
    int len = snprintf(name, sizeof name, g ? "sheet%d" : "sheet", g);
    memcpy(name + len, "\0\1Geometry", 10);
    size_t rec = fw_begin(w, "Geometry");
    if (g == 0) w->geometry_record = rec;
    fw_i64(w, 1001 + g);
    fw_str(w, name, (size_t)len + 10);
    fw_str(w, "Mesh", 4);
    fw_props(w, rec, 3);
    size_t r = fw_begin(w, "Vertices");
    unsigned char* raw = malloc(8 * 3 * (size_t)m->n_points + 8);
    for (int i = 0; i < 3 * m->n_points; ++i) {
        uint64_t u;
        memcpy(&u, &m->points[i], 8);
        for (int k = 0; k < 8; ++k) raw[8 * (size_t)i + (size_t)k] = (unsigned char)(u >> (8 * k));
    }
    if (g == 0) w->vertices_array = w->n;
    fw_array(w, 'd', raw, (uint32_t)(3 * m->n_points), 8, m->compress);
    fw_props(w, r, 1);
    fw_end(w, r, 0);
    free(raw);
    int n_idx = 0;
    for (int q = 0; q < m->n_polys; ++q) n_idx += m->sizes[q];
    raw = malloc(4 * (size_t)n_idx + 4);
    for (int q = 0, c = 0; q < m->n_polys; ++q)
        for (int k = 0; k < m->sizes[q]; ++k, ++c) {
            int32_t v = k + 1 == m->sizes[q] ? -m->corners[c] - 1 : m->corners[c];
            for (int b = 0; b < 4; ++b) raw[4 * (size_t)c + (size_t)b] = (unsigned char)((uint32_t)v >> (8 * b));
        }
    r = fw_begin(w, "PolygonVertexIndex");
    if (g == 0) w->index_array = w->n;
    fw_array(w, 'i', raw, (uint32_t)n_idx, 4, m->compress);
    fw_props(w, r, 1);
    fw_end(w, r, 0);
    free(raw);
    fw_leaf_i32(w, "GeometryVersion", 124);
    if (m->materials) fw_materials(w, m);
    fw_end(w, rec, 1);
}

/* A binary file (geo[0].version) of n_geo geometries and n_models Models under the root, model k
 * (id 2001 + k) showing geometry model_geo[k] at its translation model_t[k]. */
static inline fw_buf fw_binary_scene(const fw_mesh* geo, int n_geo, const int* model_geo,
                                     const double (*model_t)[3], int n_models) {
    fw_buf w;
    memset(&w, 0, sizeof w);
    const int version = geo[0].version ? geo[0].version : 7400;
    w.wide = version >= 7500;
    fw_put(&w, "Kaydara FBX Binary  \0\x1a\0", 23);
    fw_u32(&w, (uint32_t)version);

    size_t h = fw_begin(&w, "FBXHeaderExtension");
    fw_props(&w, h, 0);
    fw_leaf_i32(&w, "FBXHeaderVersion", 1003);
    fw_leaf_i32(&w, "FBXVersion", version);
    fw_end(&w, h, 1);

    size_t gs = fw_begin(&w, "GlobalSettings");
    fw_props(&w, gs, 0);
    fw_leaf_i32(&w, "Version", 1000);
    const double one = 1.0;
    fw_properties70(&w, "UnitScaleFactor", "double", "Number", "", &one, 1);
    fw_end(&w, gs, 1);

    size_t obj = fw_begin(&w, "Objects");
    fw_props(&w, obj, 0);
    for (int g = 0; g < n_geo; ++g) fw_geometry(&w, &geo[g], g);
    for (int k = 0; k < n_models; ++k) {
        char name[32];
        int len = snprintf(name, sizeof name, k ? "sheet%d" : "sheet", k);
        memcpy(name + len, "\0\1Model", 7);
        size_t mo = fw_begin(&w, "Model");
        fw_i64(&w, 2001 + k);
        fw_str(&w, name, (size_t)len + 7);
        fw_str(&w, "Mesh", 4);
        fw_props(&w, mo, 3);
        fw_leaf_i32(&w, "Version", 232);
        fw_properties70(&w, "Lcl Translation", "Lcl Translation", "", "A", model_t[k], 3);
        fw_end(&w, mo, 1);
    }
    fw_end(&w, obj, 1);

    size_t con = fw_begin(&w, "Connections");
    fw_props(&w, con, 0);
    for (int i = 0; i < 2 * n_models; ++i) {   /* model k: its geometry, then it to the root */
        const int k = i / 2;
        const int64_t from = i % 2 ? 2001 + k : 1001 + model_geo[k], to = i % 2 ? 0 : 2001 + k;
        size_t c = fw_begin(&w, "C");
        fw_str(&w, "OO", 2);
        fw_i64(&w, from);
        fw_i64(&w, to);
        fw_props(&w, c, 3);
        fw_end(&w, c, 0);
    }
    fw_end(&w, con, 1);
    fw_null(&w);   /* the top-level list's end */
    return w;
}

/* The binary file of m alone: one geometry, one model. */
static inline fw_buf fw_binary(const fw_mesh* m) {
    const int geo0 = 0;
    return fw_binary_scene(m, 1, &geo0, (const double(*)[3])m->translation, 1);
}

/* The ASCII file of m (FBX 7.4 text), malloc'd and NUL-terminated. */
static inline char* fw_ascii(const fw_mesh* m) {
    size_t cap = 4096 + 80 * (size_t)m->n_points + 16 * 8 * (size_t)m->n_polys, n = 0;
    char* t = malloc(cap);
    if (!t) abort();
#define FW_PRINT(...) (n += (size_t)snprintf(t + n, cap - n, __VA_ARGS__))
    FW_PRINT("; FBX 7.4.0 project file\n; written by Weft's tests\n\n"
             "FBXHeaderExtension:  {\n\tFBXHeaderVersion: 1003\n\tFBXVersion: 7400\n}\n"
             "GlobalSettings:  {\n\tVersion: 1000\n\tProperties70:  {\n"
             "\t\tP: \"UnitScaleFactor\", \"double\", \"Number\", \"\",1\n\t}\n}\n\n"
             "; Object properties\n;------\n\nObjects:  {\n"
             "\tGeometry: 1001, \"Geometry::sheet\", \"Mesh\" {\n\t\tVertices: *%d {\n\t\t\ta: ",
             3 * m->n_points);
    for (int i = 0; i < 3 * m->n_points; ++i) FW_PRINT("%s%.17g", i ? "," : "", m->points[i]);
    int n_idx = 0;
    for (int q = 0; q < m->n_polys; ++q) n_idx += m->sizes[q];
    FW_PRINT("\n\t\t} \n\t\tPolygonVertexIndex: *%d {\n\t\t\ta: ", n_idx);
    for (int q = 0, c = 0; q < m->n_polys; ++q)
        for (int k = 0; k < m->sizes[q]; ++k, ++c)
            FW_PRINT("%s%d", c ? "," : "", k + 1 == m->sizes[q] ? -m->corners[c] - 1 : m->corners[c]);
    FW_PRINT("\n\t\t} \n\t\tGeometryVersion: 124\n\t}\n"
             "\tModel: 2001, \"Model::sheet\", \"Mesh\" {\n\t\tVersion: 232\n\t\tProperties70:  {\n"
             "\t\t\tP: \"Lcl Translation\", \"Lcl Translation\", \"\", \"A\",%.17g,%.17g,%.17g\n"
             "\t\t}\n\t}\n}\n\nConnections:  {\n\tC: \"OO\",1001,2001\n\tC: \"OO\",2001,0\n}\n",
             m->translation[0], m->translation[1], m->translation[2]);
#undef FW_PRINT
    return t;
}

#endif
