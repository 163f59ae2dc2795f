/* wc_fbx_file_order: assimp's FBX meshes -> the file's control points (import_fbx_order.h). */
#include "import_fbx_order.h"
#include <assimp/scene.h>
#include <limits.h>
#include <math.h>
#include <string.h>

typedef struct matcher {
    const struct aiScene* s;
    const wc_fbx_geometries* geo;
    int* poly_base;          /* (geo->n + 1) offsets of each geometry's polygons in taken */
    unsigned char* taken;    /* polygon already matched by a mesh */
    double* reach;           /* (geo->n) largest coordinate of each geometry */
} matcher;

static int same_coord(double a, double b, double reach) {
    return a == b || fabs(a - b) <= 1e-5 * fmax(fabs(a), fabs(b)) + 1e-6 * reach;
}

/* Face f of mesh m has the corner count and positions of polygon j of geometry g. */
static int face_matches(const matcher* x, const struct aiMesh* m, const struct aiFace* f, int g,
                        int j) {
    const wc_fbx_geometry* G = &x->geo->g[g];
    const int s = G->poly_start[j], k = G->poly_start[j + 1] - s;
    if ((int)f->mNumIndices != k) return 0;
    for (int c = 0; c < k; ++c) {
        const struct aiVector3D* p = &m->mVertices[f->mIndices[c]];
        const double* q = G->points + 3 * (size_t)G->poly_points[s + c];
        if (!same_coord(p->x, (float)q[0], x->reach[g]) || !same_coord(p->y, (float)q[1], x->reach[g]) ||
            !same_coord(p->z, (float)q[2], x->reach[g]))
            return 0;
    }
    return 1;
}

/* Match every face of m, in order, to untaken polygons of geometry g, in order: face_poly gets
 * the polygon of each face. Returns the number of faces matched (m->mNumFaces: all). */
static unsigned match_mesh(const matcher* x, const struct aiMesh* m, int g, int* face_poly) {
    const wc_fbx_geometry* G = &x->geo->g[g];
    const unsigned char* taken = x->taken + x->poly_base[g];
    int j = 0;
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
        while (j < G->n_polys && (taken[j] || !face_matches(x, m, &m->mFaces[f], g, j))) ++j;
        if (j == G->n_polys) return f;
        face_poly[f] = j++;
    }
    return m->mNumFaces;
}

/* The geometry of mesh mi (*g) and each face's polygon; taken marks them. */
static wc_status find_geometry(matcher* x, unsigned mi, int* g, int* face_poly, const char* path,
                                 wc_diag* diag) {
    const struct aiMesh* m = x->s->mMeshes[mi];
    unsigned best = 0;
    int best_g = -1;
    for (int k = 0; k < x->geo->n; ++k) {
        const unsigned got = match_mesh(x, m, k, face_poly);
        if (got == m->mNumFaces) {
            for (unsigned f = 0; f < m->mNumFaces; ++f) x->taken[x->poly_base[k] + face_poly[f]] = 1;
            *g = k;
            return WC_OK;
        }
        if (best_g < 0 || got > best) { best = got; best_g = k; }
    }
    if (best_g < 0)
        return wc_fail(diag, WC_ERROR_IMPORT,
                       "'%s': the file holds no mesh Geometry with Vertices and "
                       "PolygonVertexIndex that this reader finds, so the file's control-point "
                       "order cannot be kept for mesh '%s'", path, m->mName.data);
    return wc_fail(diag, WC_ERROR_IMPORT,
                   "'%s': cannot tell which control points assimp's face %u of mesh '%s' came "
                   "from (it matches no remaining polygon of Geometry #%d in order, nor does the "
                   "mesh match another Geometry), so the file's control-point order cannot be "
                   "kept", path, best, m->mName.data, best_g);
}

/* o = t p for a control point rounded to float as assimp reads it; 0 when not finite. */
static int place(double o[3], const double p[3], const double t[12]) {
    const double x = (float)p[0], y = (float)p[1], z = (float)p[2];
    for (int r = 0; r < 3; ++r) o[r] = t[4 * r] * x + t[4 * r + 1] * y + t[4 * r + 2] * z + t[4 * r + 3];
    return isfinite(o[0]) && isfinite(o[1]) && isfinite(o[2]);
}

wc_status wc_fbx_file_order(const struct aiScene* s, const wc_import_instance* inst,
                              size_t n_inst, const wc_fbx_geometries* geo, wc_file_order* out,
                              const wc_allocator* alloc, const char* path, wc_diag* diag) {
    memset(out, 0, sizeof *out);
    matcher x = {s, geo, NULL, NULL, NULL};
    long long n_polys = 0, n_faces = 0, n_v = 0, n_corners = 0;
    for (int g = 0; g < geo->n; ++g) n_polys += geo->g[g].n_polys;
    for (unsigned i = 0; i < s->mNumMeshes; ++i) n_faces += s->mMeshes[i] ? s->mMeshes[i]->mNumFaces : 0;
    x.poly_base = WC_NEW(alloc, int, (size_t)geo->n + 1);
    x.taken = WC_NEW(alloc, unsigned char, (size_t)n_polys + 1);
    x.reach = WC_NEW(alloc, double, (size_t)geo->n + 1);
    int* mesh_geo = WC_NEW(alloc, int, (size_t)s->mNumMeshes + 1);
    long long* mesh_face = WC_NEW(alloc, long long, (size_t)s->mNumMeshes + 1);
    int* face_poly = WC_NEW(alloc, int, (size_t)n_faces + 1);   /* per mesh, from mesh_face */
    int* block = WC_NEW(alloc, int, n_inst + 1);                 /* first host vertex */
    wc_status st = WC_OK;
    if (!x.poly_base || !x.taken || !x.reach || !mesh_geo || !mesh_face || !face_poly || !block) {
        st = wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", path);
        goto done;
    }
    if (n_polys > INT_MAX) {
        st = wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "'%s': too many FBX polygons", path);
        goto done;
    }
    for (int g = 0; g < geo->n; ++g) {
        x.poly_base[g + 1] = x.poly_base[g] + geo->g[g].n_polys;
        for (int k = 0; k < 3 * geo->g[g].n_points; ++k)
            if (isfinite(geo->g[g].points[k])) x.reach[g] = fmax(x.reach[g], fabs(geo->g[g].points[k]));
    }
    for (unsigned i = 0; i < s->mNumMeshes; ++i) {
        mesh_geo[i] = -1;
        mesh_face[i + 1] = mesh_face[i] + (s->mMeshes[i] ? s->mMeshes[i]->mNumFaces : 0);
    }

    for (size_t i = 0; i < n_inst && st == WC_OK; ++i) {
        const unsigned mi = inst[i].mesh;
        if (mesh_geo[mi] < 0)
            st = find_geometry(&x, mi, &mesh_geo[mi], face_poly + mesh_face[mi], path, diag);
        if (st != WC_OK) break;
        size_t e = 0;   /* an earlier instance of this node and geometry shares its block */
        while (e < i && !(inst[e].node == inst[i].node && mesh_geo[inst[e].mesh] == mesh_geo[mi])) ++e;
        if (e < i) {
            block[i] = block[e];
        } else {
            block[i] = (int)n_v;
            n_v += geo->g[mesh_geo[mi]].n_points;
        }
        const struct aiMesh* m = s->mMeshes[mi];
        for (unsigned f = 0; f < m->mNumFaces; ++f)
            if (m->mFaces[f].mNumIndices >= 3) n_corners += m->mFaces[f].mNumIndices;
        if (n_v > INT_MAX / 3 || n_corners > INT_MAX)
            st = wc_fail(diag, WC_ERROR_OUT_OF_RANGE, "'%s': too many vertices or polygons", path);
    }
    if (st == WC_OK) st = wc_file_order_alloc(out, alloc, (int)n_v, (int)n_corners, path, diag);
    long long c = 0, filled = 0;   /* blocks open in order: block[i] == filled opens one */
    for (size_t i = 0; i < n_inst && st == WC_OK; ++i) {
        const struct aiMesh* m = s->mMeshes[inst[i].mesh];
        const wc_fbx_geometry* G = &geo->g[mesh_geo[inst[i].mesh]];
        const int* fp = face_poly + mesh_face[inst[i].mesh];
        if (block[i] == filled) {
            filled += G->n_points;
            for (int p = 0; p < G->n_points && st == WC_OK; ++p)
                if (!place(out->v + 3 * ((size_t)block[i] + (size_t)p), G->points + 3 * (size_t)p, inst[i].m))
                    st = wc_fail(diag, WC_ERROR_NONFINITE,
                                 "'%s': control point %d of FBX Geometry #%d is not finite "
                                 "after the node transform", path, p, mesh_geo[inst[i].mesh]);
        }
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            if (m->mFaces[f].mNumIndices < 3) continue;
            const int* cp = G->poly_points + G->poly_start[fp[f]];
            for (unsigned k = 0; k < m->mFaces[f].mNumIndices; ++k) out->corner_v[c++] = block[i] + cp[k];
        }
    }
done:
    if (st != WC_OK) wc_file_order_free(out);
    wc_free(alloc, x.poly_base);
    wc_free(alloc, x.taken);
    wc_free(alloc, x.reach);
    wc_free(alloc, mesh_geo);
    wc_free(alloc, mesh_face);
    wc_free(alloc, face_poly);
    wc_free(alloc, block);
    return st;
}
