/* wc_import_file / wc_import_memory: any format assimp reads -> wc_source_mesh (metres, polygons
 * kept as polygons).
 *
 * Steps: probe the file with fopen (IO errors), import with no post-processing, resolve the
 * selection and the list of mesh instances (node tree walked from the root, world transforms
 * accumulated), check the raw positions of those meshes for NaN/Inf, then run
 * aiProcess_JoinIdenticalVertices (JoinIdenticalVertices treats a NaN position as equal to
 * anything, so the check must come first) and concatenate the instances. An OBJ's vertices are
 * then renumbered by its own `v` lines (import_obj_order.h), an FBX's by its control points
 * (import_fbx_order.h, reading the file's geometry with fbx_geometry.h).
 *
 * Found with assimp 5.2.5: the FBX importer applies every node's Lcl transform (and pre/post
 * rotations and pivots) but neither GlobalSettings UpAxis/FrontAxis/CoordAxis (the root node stays
 * identity) nor UnitScaleFactor (centimetres per file unit; only in aiScene::mMetaData, as a
 * float). We apply UnitScaleFactor / 100 ourselves and leave the axes as the file has them. */
#include "source_mesh.h"
#include "import_fbx_order.h"
#include "import_obj_order.h"
#include "import_precheck.h"
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define WC_IMPORT_MAX_DEPTH 512   /* node hierarchy depth limit (recursion) */
#define WC_IMPORT_HEAD 64         /* bytes read up front to diagnose files with no meshes */
#define WC_IMPORT_MAX_HINT 15     /* characters of a memory import's format hint */

wc_import_opts wc_default_import_opts(void) {
    wc_import_opts o;
    memset(&o, 0, sizeof o);
    o.scale = 1.0;
    o.select = NULL;
    return o;
}

/* ---- small helpers ---------------------------------------------------------------------- */

/* The double nearest the shortest decimal that round-trips the float (2.54f -> 2.54). */
static double float_to_double_shortest(float f) {
    char buf[48];
    for (int prec = 6; prec <= 9; ++prec) {
        snprintf(buf, sizeof buf, "%.*g", prec, (double)f);
        double d = strtod(buf, NULL);
        if ((float)d == f) return d;
    }
    return (double)f;
}

static int ends_with_ci(const char* s, const char* suffix) {
    size_t n = strlen(s), m = strlen(suffix);
    if (m > n) return 0;
    for (size_t i = 0; i < m; ++i) {
        char a = s[n - m + i], b = suffix[i];
        if (a >= 'A' && a <= 'Z') a = (char)(a - 'A' + 'a');
        if (a != b) return 0;
    }
    return 1;
}

static const struct aiMetadataEntry* meta_find(const struct aiScene* s, const char* key) {
    const struct aiMetadata* md = s->mMetaData;
    if (!md || !md->mKeys || !md->mValues) return NULL;
    for (unsigned i = 0; i < md->mNumProperties; ++i)
        if (strcmp(md->mKeys[i].data, key) == 0) return &md->mValues[i];
    return NULL;
}

/* Numeric metadata value as a double; 0 when missing or not numeric. */
static int meta_number(const struct aiMetadataEntry* e, double* out) {
    if (!e || !e->mData) return 0;
    switch (e->mType) {
    case AI_FLOAT: *out = float_to_double_shortest(*(const float*)e->mData); return 1;
    case AI_DOUBLE: *out = *(const double*)e->mData; return 1;
    case AI_INT32: *out = (double)*(const int32_t*)e->mData; return 1;
    case AI_UINT64: *out = (double)*(const uint64_t*)e->mData; return 1;
    default: return 0;
    }
}

static int is_fbx_scene(const struct aiScene* s, const char* path) {
    const struct aiMetadataEntry* e = meta_find(s, "SourceAsset_Format");
    if (e && e->mType == AI_AISTRING && e->mData &&
        strstr(((const struct aiString*)e->mData)->data, "FBX"))
        return 1;
    return ends_with_ci(path, ".fbx");
}

/* Names for an error message: distinct non-empty names while they fit, then "...". */
typedef struct name_list {
    char buf[176];
    size_t len;
    int full;
} name_list;

static void name_list_add(name_list* l, const char* name) {
    if (l->full || !name[0]) return;
    char quoted[136];
    int n = snprintf(quoted, sizeof quoted, "'%s'", name);
    if (n < 0 || (size_t)n >= sizeof quoted) { l->full = 1; return; }
    if (l->len && strstr(l->buf, quoted)) return;   /* already listed */
    if (l->len + (size_t)n + 2 + 5 >= sizeof l->buf) { l->full = 1; return; }
    l->len += (size_t)snprintf(l->buf + l->len, sizeof l->buf - l->len, "%s%s",
                               l->len ? ", " : "", quoted);
}

static void name_list_finish(name_list* l) {
    if (l->len == 0 && !l->full)
        snprintf(l->buf, sizeof l->buf, "(none)");
    else if (l->full)
        snprintf(l->buf + l->len, sizeof l->buf - l->len, "%s...", l->len ? ", " : "");
}

/* ---- node walk -------------------------------------------------------------------------- */

typedef wc_import_instance instance;

enum { SEL_ALL, SEL_NODE, SEL_MESH };

typedef struct walk {
    const struct aiScene* scene;
    int mode;
    const char* name;
    instance* inst;       /* NULL while counting */
    size_t n_inst;
    int too_deep;
    int bad_mesh_ref;
} walk;

static void mat_mul(double r[16], const double a[16], const double b[16]) {
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            r[4 * i + j] = a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] +
                           a[4 * i + 3] * b[12 + j];
}

static void walk_node(walk* w, const struct aiNode* node, const double parent[16], int emitting,
                      int depth) {
    if (!node) return;
    if (depth > WC_IMPORT_MAX_DEPTH) { w->too_deep = 1; return; }
    const struct aiMatrix4x4* t = &node->mTransformation;
    const double local[16] = {t->a1, t->a2, t->a3, t->a4, t->b1, t->b2, t->b3, t->b4,
                              t->c1, t->c2, t->c3, t->c4, t->d1, t->d2, t->d3, t->d4};
    double world[16];
    mat_mul(world, parent, local);
    if (w->mode == SEL_NODE && !emitting && strcmp(node->mName.data, w->name) == 0) emitting = 1;
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
        unsigned mi = node->mMeshes[i];
        if (mi >= w->scene->mNumMeshes || !w->scene->mMeshes[mi]) { w->bad_mesh_ref = 1; continue; }
        int take = w->mode == SEL_ALL || (w->mode == SEL_NODE && emitting) ||
                   (w->mode == SEL_MESH && strcmp(w->scene->mMeshes[mi]->mName.data, w->name) == 0);
        if (!take) continue;
        if (w->inst) {
            instance* in = &w->inst[w->n_inst];
            in->mesh = mi;
            in->node = node;
            memcpy(in->m, world, sizeof in->m);
        }
        ++w->n_inst;
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c)
        walk_node(w, node->mChildren[c], world, emitting, depth + 1);
}

static int node_named(const struct aiNode* n, const char* name, int depth) {
    if (!n || depth > WC_IMPORT_MAX_DEPTH) return 0;
    if (strcmp(n->mName.data, name) == 0) return 1;
    for (unsigned c = 0; c < n->mNumChildren; ++c)
        if (node_named(n->mChildren[c], name, depth + 1)) return 1;
    return 0;
}

static void list_node_names(const struct aiNode* n, name_list* l, int* count, int depth) {
    if (!n || depth > WC_IMPORT_MAX_DEPTH) return;
    ++*count;
    name_list_add(l, n->mName.data);
    for (unsigned c = 0; c < n->mNumChildren; ++c)
        list_node_names(n->mChildren[c], l, count, depth + 1);
}

/* ---- import ----------------------------------------------------------------------------- */

/* First bytes look like UTF-16 (BOM, or NUL bytes in text): assimp reads such OBJ as empty. */
static int looks_utf16(const unsigned char* b, size_t n) {
    if (n >= 2 && ((b[0] == 0xFF && b[1] == 0xFE) || (b[0] == 0xFE && b[1] == 0xFF))) return 1;
    size_t zeros = 0;
    for (size_t i = 0; i < n; ++i) zeros += b[i] == 0;
    return n >= 4 && zeros * 3 >= n && zeros * 3 <= 2 * n;
}

/* First bytes hold control characters other than whitespace: not a text file. */
static int looks_binary(const unsigned char* b, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if ((b[i] < 0x20 && b[i] != '\t' && b[i] != '\n' && b[i] != '\r' && b[i] != '\f' &&
             b[i] != '\v') || b[i] == 0x7F)
            return 1;
    return 0;
}

/* fopen(path, "rb") into *f, or IO naming the file and the reason. */
static wc_status open_file(const char* path, FILE** f, wc_diag* diag) {
    errno = 0;
    *f = fopen(path, "rb");
    if (!*f)
        return wc_fail(diag, WC_ERROR_IO, "cannot open '%s': %s", path,
                       errno ? strerror(errno) : "fopen failed");
    return WC_OK;
}

static wc_status probe_file(const char* path, unsigned char* head, size_t* n_head,
                              wc_diag* diag) {
    FILE* f;
    wc_status st = open_file(path, &f, diag);
    if (st != WC_OK) return st;
    *n_head = fread(head, 1, WC_IMPORT_HEAD, f);
    int err = ferror(f);
    int saved = errno;
    fclose(f);
    if (err)
        return wc_fail(diag, WC_ERROR_IO, "cannot read '%s': %s", path,
                       saved ? strerror(saved) : "read error");
    if (*n_head == 0)
        return wc_fail(diag, WC_ERROR_IMPORT, "cannot import '%s': the file is empty (0 bytes)",
                       path);
    return WC_OK;
}

/* The whole file in *text (allocated with alloc, size bytes). */
static wc_status read_all(const char* path, const wc_allocator* alloc, char** text, size_t* size,
                            wc_diag* diag) {
    *text = NULL;
    *size = 0;
    FILE* f;
    wc_status st = open_file(path, &f, diag);
    if (st != WC_OK) return st;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0) n = ftell(f);
    if (n < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        return wc_fail(diag, WC_ERROR_IO, "cannot read '%s': not seekable", path);
    }
    *text = WC_NEW(alloc, char, (size_t)n + 1);
    if (!*text) {
        fclose(f);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory for %ld bytes", path, n);
    }
    *size = fread(*text, 1, (size_t)n, f);
    int err = ferror(f);
    fclose(f);
    if (err) {
        wc_free(alloc, *text);
        *text = NULL;
        return wc_fail(diag, WC_ERROR_IO, "cannot read '%s'", path);
    }
    return WC_OK;
}

static wc_status check_raw_finite(const struct aiScene* s, const instance* inst, size_t n_inst,
                                    const char* path, wc_diag* diag) {
    for (size_t i = 0; i < n_inst; ++i) {
        const struct aiMesh* m = s->mMeshes[inst[i].mesh];
        if (i > 0 && inst[i].mesh == inst[i - 1].mesh) continue;
        for (unsigned v = 0; v < m->mNumVertices; ++v) {
            const struct aiVector3D* p = &m->mVertices[v];
            if (!isfinite(p->x) || !isfinite(p->y) || !isfinite(p->z))
                return wc_fail(diag, WC_ERROR_NONFINITE,
                               "'%s': mesh '%s' (#%u) has a non-finite position (%g, %g, %g) "
                               "at its vertex %u (assimp's order before joining)",
                               path, m->mName.data, inst[i].mesh, (double)p->x, (double)p->y,
                               (double)p->z, v);
        }
    }
    return WC_OK;
}

/* Every mesh's faces index its own vertices. assimp's importers can return a scene that breaks
 * this for a damaged file (found by fuzz/fuzz_import: a binary PLY whose face list reads past its
 * vertices), and aiProcess_JoinIdenticalVertices then reads out of bounds and crashes inside
 * assimp 5.2.5. It runs on every mesh of the scene, selected or not, so every mesh is checked. */
static wc_status check_faces(const struct aiScene* s, const char* path, wc_diag* diag) {
    for (unsigned i = 0; i < s->mNumMeshes; ++i) {
        const struct aiMesh* m = s->mMeshes[i];
        if (!m) continue;   /* walk_node reports references to it */
        if ((m->mNumVertices > 0 && !m->mVertices) || (m->mNumFaces > 0 && !m->mFaces))
            return wc_fail(diag, WC_ERROR_IMPORT, "'%s': mesh '%s' has no %s (corrupt file)", path,
                           m->mName.data, m->mVertices ? "faces" : "positions");
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const struct aiFace* face = &m->mFaces[f];
            if (face->mNumIndices > 0 && !face->mIndices)
                return wc_fail(diag, WC_ERROR_IMPORT, "'%s': mesh '%s' face %u has no indices (corrupt file)",
                               path, m->mName.data, f);
            for (unsigned k = 0; k < face->mNumIndices; ++k)
                if (face->mIndices[k] >= m->mNumVertices)
                    return wc_fail(diag, WC_ERROR_IMPORT,
                                   "'%s': mesh '%s' face %u uses vertex %u of %u (corrupt file)", path,
                                   m->mName.data, f, face->mIndices[k], m->mNumVertices);
        }
    }
    return WC_OK;
}

/* o = scale x (t p): one vertex in metres; 0 when it is not finite. */
static int place(double o[3], const struct aiVector3D* p, const double t[12], double scale) {
    const double x = p->x, y = p->y, z = p->z;
    for (int r = 0; r < 3; ++r)
        o[r] = scale * (t[4 * r] * x + t[4 * r + 1] * y + t[4 * r + 2] * z + t[4 * r + 3]);
    return isfinite(o[0]) && isfinite(o[1]) && isfinite(o[2]);
}

static wc_status bad_vertex(wc_source_mesh* m, int v, const struct aiMesh* am, double scale,
                              const char* path, wc_diag* diag) {
    wc_source_mesh_free(m);
    return wc_fail(diag, WC_ERROR_NONFINITE,
                   "'%s': vertex %d (mesh '%s') is not finite after applying the node "
                   "transform and scale %g", path, v, am->mName.data, scale);
}

/* Drop the vertices of m (nv of them, n_corners corners) that no polygon uses, keeping the
 * order of the rest; returns how many are left, or -1 when out of memory. */
static int keep_used(wc_source_mesh* m, int nv, int n_corners) {
    int* to = WC_NEW(&m->alloc, int, (size_t)nv + 1);
    if (!to) return -1;
    for (int v = 0; v < nv; ++v) to[v] = -1;
    for (int i = 0; i < n_corners; ++i) to[m->poly_verts[i]] = 0;
    int n = 0;
    for (int v = 0; v < nv; ++v) {
        if (to[v] < 0) continue;
        memmove(m->pos + 3 * (size_t)n, m->pos + 3 * (size_t)v, 3 * sizeof(double));
        to[v] = n++;
    }
    for (int i = 0; i < n_corners; ++i) m->poly_verts[i] = to[m->poly_verts[i]];
    wc_free(&m->alloc, to);
    return n;
}

/* Concatenate the instances into out (allocated with alloc). Scene already joined.
 * With order (an OBJ's `v` lines, an FBX's control points) the vertices are the file's instead:
 * each corner writes its assimp position to its file vertex, and a file vertex no polygon uses
 * keeps its own position times scale; used_only keeps only the file vertices the polygons use
 * (a selection), still in file order. */
static wc_status build_mesh(wc_source_mesh* out, const wc_allocator* alloc,
                              const struct aiScene* s, const instance* inst, size_t n_inst,
                              double scale, const wc_file_order* order, int used_only,
                              const char* path, wc_diag* diag) {
    long long nv = 0, np = 0, nc = 0;
    int n_points = 0, n_lines = 0;
    for (size_t i = 0; i < n_inst; ++i) {
        const struct aiMesh* m = s->mMeshes[inst[i].mesh];
        if (m->mNumVertices > 0 && !m->mVertices)
            return wc_fail(diag, WC_ERROR_IMPORT, "'%s': mesh '%s' has no positions", path,
                           m->mName.data);
        nv += m->mNumVertices;
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const struct aiFace* face = &m->mFaces[f];
            for (unsigned k = 0; k < face->mNumIndices; ++k)
                if (face->mIndices[k] >= m->mNumVertices)
                    return wc_fail(diag, WC_ERROR_IMPORT,
                                   "'%s': mesh '%s' face %u uses vertex %u of %u (corrupt file)",
                                   path, m->mName.data, f, face->mIndices[k], m->mNumVertices);
            if (face->mNumIndices == 1) ++n_points;
            else if (face->mNumIndices == 2) ++n_lines;
            else if (face->mNumIndices >= 3) { ++np; nc += face->mNumIndices; }
        }
        if (nv > INT_MAX / 3 || np >= INT_MAX || nc > INT_MAX)
            return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "'%s': too many vertices or polygons",
                           path);
    }
    if (order && order->n_corners != nc)
        return wc_fail(diag, WC_ERROR_IMPORT, "'%s': %lld corners, the file's order has %d",
                       path, nc, order->n_corners);   /* the matchers count as this loop */
    if (order) nv = order->n_v;
    if (np == 0)
        return wc_fail(diag, WC_ERROR_EMPTY_MESH,
                       "'%s': no polygons with >= 3 corners in %zu mesh instance(s) (%lld "
                       "vertices, %d points, %d lines)", path, n_inst, nv, n_points, n_lines);

    wc_source_mesh m;
    memset(&m, 0, sizeof m);
    if (alloc) m.alloc = *alloc;
    m.pos = WC_NEW(&m.alloc, double, 3 * (size_t)nv);
    m.poly_start = WC_NEW(&m.alloc, int, (size_t)np + 1);
    m.poly_verts = WC_NEW(&m.alloc, int, (size_t)nc);
    if (!m.pos || !m.poly_start || !m.poly_verts) {
        wc_source_mesh_free(&m);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory for %lld vertices",
                       path, nv);
    }
    if (order)
        for (long long v = 0; v < 3 * nv; ++v) m.pos[v] = scale * order->v[v];
    int base = 0, q = 0, c = 0;
    for (size_t i = 0; i < n_inst; ++i) {
        const struct aiMesh* am = s->mMeshes[inst[i].mesh];
        for (unsigned v = 0; v < am->mNumVertices && !order; ++v)
            if (!place(m.pos + 3 * (size_t)(base + (int)v), &am->mVertices[v], inst[i].m, scale))
                return bad_vertex(&m, base + (int)v, am, scale, path, diag);
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            const struct aiFace* face = &am->mFaces[f];
            if (face->mNumIndices < 3) continue;
            m.poly_start[q++] = c;
            for (unsigned k = 0; k < face->mNumIndices; ++k, ++c) {
                const unsigned v = face->mIndices[k];
                const int file_v = order ? order->corner_v[c] : -1;
                if (order && !place(m.pos + 3 * (size_t)file_v, &am->mVertices[v], inst[i].m, scale))
                    return bad_vertex(&m, file_v, am, scale, path, diag);
                m.poly_verts[c] = order ? file_v : base + (int)v;
            }
        }
        base += (int)am->mNumVertices;
    }
    m.poly_start[q] = c;
    if (order && used_only && (nv = keep_used(&m, (int)nv, c)) < 0) {
        wc_source_mesh_free(&m);
        return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", path);
    }
    m.n_verts = (int)nv;
    m.n_polys = (int)np;
    m.n_points = n_points;
    m.n_lines = n_lines;
    m.n_meshes = (int)n_inst;
    m.unit_scale = scale;
    *out = m;
    return WC_OK;
}

/* Unit factor of the file (metres per file unit) before the user's scale. */
static wc_status file_unit(const struct aiScene* s, const char* path, double* unit,
                             wc_diag* diag) {
    *unit = 1.0;
    if (!is_fbx_scene(s, path)) return WC_OK;
    double usf = 1.0;   /* FBX default: centimetres */
    const struct aiMetadataEntry* e = meta_find(s, "UnitScaleFactor");
    if (e && !meta_number(e, &usf))
        return wc_fail(diag, WC_ERROR_IMPORT, "'%s': FBX UnitScaleFactor has metadata type %d",
                       path, (int)e->mType);
    if (!(isfinite(usf) && usf > 0.0))
        return wc_fail(diag, WC_ERROR_IMPORT, "'%s': invalid FBX UnitScaleFactor %g", path, usf);
    *unit = usf / 100.0;
    return WC_OK;
}

/* The importer's settings (the same for files and memory); NULL on allocation failure. */
static struct aiPropertyStore* new_props(const char* name, wc_diag* diag) {
    struct aiPropertyStore* props = aiCreatePropertyStore();
    if (!props) {
        wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "import '%s': no property store", name);
        return NULL;
    }
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_PRESERVE_PIVOTS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_ANIMATIONS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_CAMERAS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_FBX_READ_LIGHTS, 0);
    aiSetImportPropertyInteger(props, AI_CONFIG_IMPORT_NO_SKELETON_MESHES, 1);
    return props;
}

/* Options checked and defaulted (scale 0 -> 1, select "" -> NULL). */
static wc_status check_opts(const wc_import_opts* opts, const char* name, wc_import_opts* o,
                              wc_diag* diag) {
    *o = opts ? *opts : wc_default_import_opts();
    if (o->scale == 0.0) o->scale = 1.0;
    if (!(isfinite(o->scale) && o->scale > 0.0))
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT,
                       "import '%s': scale %g must be finite and > 0 (0 means 1)", name, o->scale);
    if (o->select && !o->select[0]) o->select = NULL;
    return WC_OK;
}

/* The OBJ's own numbering for the instances: its `v` lines, and each corner's `v` line from
 * wc_obj_match_faces (the file's `f` line of each polygon). */
static wc_status obj_order(const struct aiScene* s, const instance* inst, size_t n_inst,
                             const char* text, size_t size, const wc_allocator* alloc,
                             const char* path, wc_file_order* order, wc_diag* diag) {
    size_t np = 0, nc = 0;
    for (size_t i = 0; i < n_inst; ++i)
        for (unsigned f = 0; f < s->mMeshes[inst[i].mesh]->mNumFaces; ++f) {
            const unsigned k = s->mMeshes[inst[i].mesh]->mFaces[f].mNumIndices;
            np += k >= 3;
            nc += k >= 3 ? k : 0;
        }
    if (nc > INT_MAX)
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "'%s': too many polygon corners", path);
    unsigned* meshes = WC_NEW(alloc, unsigned, n_inst);
    int* poly_face = WC_NEW(alloc, int, np + 1);
    wc_obj_text obj;
    memset(&obj, 0, sizeof obj);
    wc_status st = WC_OK;
    if (!meshes || !poly_face)
        st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", path);
    for (size_t i = 0; i < n_inst && st == WC_OK; ++i) meshes[i] = inst[i].mesh;
    if (st == WC_OK) st = wc_obj_text_read(&obj, alloc, text, size, path, diag);
    if (st == WC_OK)
        st = wc_obj_match_faces(s, meshes, n_inst, &obj, poly_face, alloc, path, diag);
    if (st == WC_OK) st = wc_file_order_alloc(order, alloc, obj.n_v, (int)nc, path, diag);
    for (long long v = 0; st == WC_OK && v < 3LL * obj.n_v; ++v) order->v[v] = (double)obj.v[v];
    for (size_t q = 0, c = 0; st == WC_OK && q < np; ++q)
        for (int k = obj.face_start[poly_face[q]]; k < obj.face_start[poly_face[q] + 1]; ++k)
            order->corner_v[c++] = obj.face_v[k];
    wc_obj_text_free(&obj);
    wc_free(alloc, poly_face);
    wc_free(alloc, meshes);
    return st;
}

/* The FBX's own numbering for the instances: its control points (import_fbx_order.h), from the
 * file's bytes (data, size). */
static wc_status fbx_order(const struct aiScene* s, const instance* inst, size_t n_inst,
                             const void* data, size_t size, const wc_allocator* alloc,
                             const char* path, wc_file_order* order, wc_diag* diag) {
    wc_fbx_geometries geo;
    wc_status st = wc_fbx_geometry_read(&geo, alloc, data, size, path, diag);
    if (st == WC_OK) st = wc_fbx_file_order(s, inst, n_inst, &geo, order, alloc, path, diag);
    wc_fbx_geometry_free(&geo);
    return st;
}

/* An FBX file (data, or read from path when NULL) whose geometry fbx_geometry.c refuses; the
 * reason is in diag. */
static int fbx_damaged(const char* data, size_t size, const char* path,
                       const wc_allocator* alloc, wc_diag* diag) {
    char* own = NULL;
    wc_diag quiet;
    memset(&quiet, 0, sizeof quiet);
    if (!data && read_all(path, alloc, &own, &size, &quiet) != WC_OK) return 0;
    wc_fbx_geometries geo;
    const int bad = wc_fbx_geometry_read(&geo, alloc, data ? data : own, size, path, diag) ==
                    WC_ERROR_IMPORT;
    wc_fbx_geometry_free(&geo);
    wc_free(alloc, own);
    return bad;
}

/* The rest of an import, shared by files and memory: scene (NULL: assimp failed) -> *out.
 * text (text_size bytes) is the file's content when the caller has it (NULL: a file at path
 * read here when it turns out to be FBX). Releases scene and props. */
static wc_status import_scene(wc_source_mesh* out, const wc_allocator* alloc,
                                const struct aiScene* scene, struct aiPropertyStore* props,
                                const char* path, const unsigned char* head, size_t n_head,
                                const char* text, size_t text_size, const wc_import_opts* opts,
                                wc_diag* diag) {
    wc_status st = WC_OK;
    wc_import_opts o = *opts;
    if (!scene) {
        const char* why = aiGetErrorString();   /* process-global in assimp: copy it now */
        char reason[256];
        snprintf(reason, sizeof reason, "%s", why && why[0] ? why : "unknown error");
        aiReleasePropertyStore(props);
        return wc_fail(diag, WC_ERROR_IMPORT, "cannot import '%s': %s", path, reason);
    }

    instance* inst = NULL;
    wc_file_order order;
    memset(&order, 0, sizeof order);
    char* own_text = NULL;
    walk w;
    memset(&w, 0, sizeof w);
    w.scene = scene;
    static const double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    double unit = 1.0;

    if (scene->mNumMeshes == 0 || !scene->mRootNode) {
        /* assimp's OBJ importer accepts any bytes and returns zero meshes: tell an unreadable
         * file (UTF-16, binary garbage) apart from a readable one without geometry. */
        if (looks_utf16(head, n_head))
            st = wc_fail(diag, WC_ERROR_IMPORT,
                         "cannot import '%s': it looks like UTF-16 text, which assimp reads as "
                         "no meshes; re-save it as UTF-8 or ASCII", path);
        else if (ends_with_ci(path, ".obj") && looks_binary(head, n_head))
            st = wc_fail(diag, WC_ERROR_IMPORT,
                         "cannot import '%s': assimp found no meshes and the file holds binary "
                         "bytes (corrupt, or not an OBJ file)", path);
        else if (is_fbx_scene(scene, path) && fbx_damaged(text, text_size, path, alloc, diag))
            st = WC_ERROR_IMPORT;   /* assimp drops a geometry it cannot read: say why */
        else
            st = wc_fail(diag, WC_ERROR_EMPTY_MESH, "'%s' has no meshes", path);
        goto done;
    }
    st = file_unit(scene, path, &unit, diag);
    if (st != WC_OK) goto done;

    w.mode = SEL_ALL;
    if (o.select) {
        w.name = o.select;
        if (node_named(scene->mRootNode, o.select, 0)) {
            w.mode = SEL_NODE;
        } else {
            int found = 0;
            for (unsigned i = 0; i < scene->mNumMeshes && !found; ++i)
                found = scene->mMeshes[i] && strcmp(scene->mMeshes[i]->mName.data, o.select) == 0;
            if (!found) {
                name_list nodes, meshes;
                memset(&nodes, 0, sizeof nodes);
                memset(&meshes, 0, sizeof meshes);
                int n_nodes = 0;
                list_node_names(scene->mRootNode, &nodes, &n_nodes, 0);
                for (unsigned i = 0; i < scene->mNumMeshes; ++i)
                    if (scene->mMeshes[i]) name_list_add(&meshes, scene->mMeshes[i]->mName.data);
                name_list_finish(&nodes);
                name_list_finish(&meshes);
                st = wc_fail(diag, WC_ERROR_IMPORT,
                             "'%s': no node or mesh named '%s'; meshes (%u): %s; nodes (%d): %s",
                             path, o.select, scene->mNumMeshes, meshes.buf, n_nodes, nodes.buf);
                goto done;
            }
            w.mode = SEL_MESH;
        }
    }
    walk_node(&w, scene->mRootNode, identity, 0, 0);   /* count */
    if (w.too_deep) {
        st = wc_fail(diag, WC_ERROR_IMPORT, "'%s': node hierarchy deeper than %d levels", path,
                     WC_IMPORT_MAX_DEPTH);
        goto done;
    }
    if (w.bad_mesh_ref) {
        st = wc_fail(diag, WC_ERROR_IMPORT, "'%s': a node references a missing mesh", path);
        goto done;
    }
    if (w.n_inst == 0) {
        st = wc_fail(diag, WC_ERROR_EMPTY_MESH, "'%s': %s%s%s has no mesh instances", path,
                     o.select ? (w.mode == SEL_NODE ? "node '" : "mesh '") : "the scene",
                     o.select ? o.select : "", o.select ? "'" : "");
        goto done;
    }
    inst = WC_NEW(alloc, instance, w.n_inst);
    if (!inst) {
        st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", path);
        goto done;
    }
    w.inst = inst;
    w.n_inst = 0;
    walk_node(&w, scene->mRootNode, identity, 0, 0);   /* fill */

    st = check_raw_finite(scene, inst, w.n_inst, path, diag);
    if (st == WC_OK) st = check_faces(scene, path, diag);   /* before assimp's post-processing */
    if (st != WC_OK) goto done;

    scene = aiApplyPostProcessing(scene, aiProcess_JoinIdenticalVertices);
    if (!scene) {   /* assimp released the scene */
        char reason[256];
        const char* why = aiGetErrorString();
        snprintf(reason, sizeof reason, "%s", why && why[0] ? why : "unknown error");
        st = wc_fail(diag, WC_ERROR_IMPORT, "'%s': joining identical vertices failed: %s", path,
                     reason);
        goto done;
    }
    if (is_fbx_scene(scene, path)) {   /* number vertices by the control points */
        if (!text) {
            st = read_all(path, alloc, &own_text, &text_size, diag);
            text = own_text;
        }
        if (st == WC_OK)
            st = fbx_order(scene, inst, w.n_inst, text, text_size, alloc, path, &order, diag);
    } else if (text && ends_with_ci(path, ".obj")) {   /* number vertices by the `v` lines */
        st = obj_order(scene, inst, w.n_inst, text, text_size, alloc, path, &order, diag);
    }
    if (st != WC_OK) goto done;
    st = build_mesh(out, alloc, scene, inst, w.n_inst, unit * o.scale,
                    order.corner_v ? &order : NULL, o.select != NULL, path, diag);
    if (st == WC_OK)
        wc_log(diag, WC_LOG_INFO,
               "imported '%s': %d vertices, %d polygons, %d mesh instance(s), %g m per unit",
               path, out->n_verts, out->n_polys, out->n_meshes, out->unit_scale);

done:
    wc_free(alloc, inst);
    wc_file_order_free(&order);
    wc_free(alloc, own_text);
    if (scene) aiReleaseImport(scene);
    aiReleasePropertyStore(props);
    if (st != WC_OK) memset(out, 0, sizeof *out);
    return st;
}

wc_status wc_import_file(wc_source_mesh* out, const wc_allocator* alloc, const char* path,
                           const wc_import_opts* opts, wc_diag* diag) {
    if (!out) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "import: out is NULL");
    memset(out, 0, sizeof *out);
    if (!path || !path[0])
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "import: path is %s",
                       path ? "empty" : "NULL");
    wc_import_opts o;
    wc_status st = check_opts(opts, path, &o, diag);
    if (st != WC_OK) return st;

    unsigned char head[WC_IMPORT_HEAD];
    size_t n_head = 0;
    st = probe_file(path, head, &n_head, diag);
    if (st != WC_OK) return st;
    st = wc_import_precheck_file(path, head, n_head, diag);   /* inputs known to hang assimp */
    if (st != WC_OK) return st;

    struct aiPropertyStore* props = new_props(path, diag);
    if (!props) return WC_ERROR_OUT_OF_MEMORY;
    char* text = NULL;
    size_t text_size = 0;
    if (ends_with_ci(path, ".obj")) {
        st = read_all(path, alloc, &text, &text_size, diag);
        if (st != WC_OK) {
            aiReleasePropertyStore(props);
            return st;
        }
    }
    const struct aiScene* scene = aiImportFileExWithProperties(path, 0, NULL, props);
    st = import_scene(out, alloc, scene, props, path, head, n_head, text, text_size, &o, diag);
    wc_free(alloc, text);
    return st;
}

wc_status wc_import_memory(wc_source_mesh* out, const wc_allocator* alloc, const void* data,
                             size_t size, const char* hint, const wc_import_opts* opts,
                             wc_diag* diag) {
    if (!out) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "import: out is NULL");
    memset(out, 0, sizeof *out);
    if (!data) return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "import: data is NULL");
    if (!hint || !hint[0] || strlen(hint) > WC_IMPORT_MAX_HINT)
        return wc_fail(diag, WC_ERROR_INVALID_ARGUMENT, "import: the format hint is %s",
                       !hint ? "NULL" : hint[0] ? "too long" : "empty");
    char name[WC_IMPORT_MAX_HINT + 16];
    snprintf(name, sizeof name, "<memory>.%s", hint);   /* messages; FBX by its extension too */
    wc_import_opts o;
    wc_status st = check_opts(opts, name, &o, diag);
    if (st != WC_OK) return st;
    if (size == 0)
        return wc_fail(diag, WC_ERROR_IMPORT, "cannot import '%s': the buffer is empty (0 bytes)",
                       name);
    if (size > UINT_MAX)   /* assimp takes an unsigned length */
        return wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "cannot import '%s': %zu bytes is too large",
                       name, size);
    st = wc_import_precheck_memory(data, size, name, diag);   /* inputs known to hang assimp */
    if (st != WC_OK) return st;
    size_t n_head = size < WC_IMPORT_HEAD ? size : WC_IMPORT_HEAD;
    struct aiPropertyStore* props = new_props(name, diag);
    if (!props) return WC_ERROR_OUT_OF_MEMORY;
    const struct aiScene* scene =
        aiImportFileFromMemoryWithProperties(data, (unsigned)size, 0, hint, props);
    return import_scene(out, alloc, scene, props, name, data, n_head, data, size, &o, diag);
}
