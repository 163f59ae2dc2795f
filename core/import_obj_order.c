/* wc_obj_match_faces: assimp's OBJ polygons -> the file's `f` lines (import_obj_order.h). */
#include "import_obj_order.h"
#include <assimp/scene.h>
#include <math.h>
#include <string.h>

static int same_coord(float a, float b) {
    return a == b || fabsf(a - b) <= 1e-5f * fmaxf(fabsf(a), fabsf(b));
}

/* Face f of mesh m has the corner count and positions of the file's face j. */
static int face_matches(const struct aiMesh* m, const struct aiFace* f, const wc_obj_text* obj,
                        int j) {
    const int s = obj->face_start[j], k = obj->face_start[j + 1] - s;
    if ((int)f->mNumIndices != k) return 0;
    for (int c = 0; c < k; ++c) {
        const struct aiVector3D* p = &m->mVertices[f->mIndices[c]];
        const float* q = obj->v + 3 * (size_t)obj->face_v[s + c];
        if (!same_coord(p->x, q[0]) || !same_coord(p->y, q[1]) || !same_coord(p->z, q[2]))
            return 0;
    }
    return 1;
}

wc_status wc_obj_match_faces(const struct aiScene* s, const unsigned* meshes, size_t n_inst,
                               const wc_obj_text* obj, int* poly_face, const wc_allocator* alloc,
                               const char* path, wc_diag* diag) {
    unsigned char* claimed = WC_NEW(alloc, unsigned char, (size_t)obj->n_faces + 1);
    if (!claimed) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "'%s': out of memory", path);
    wc_status st = WC_OK;
    size_t q = 0;
    for (size_t i = 0; i < n_inst && st == WC_OK; ++i) {
        const struct aiMesh* m = s->mMeshes[meshes[i]];
        size_t earlier = 0, q0 = 0;   /* a mesh used twice takes its first instance's faces */
        for (; earlier < i && meshes[earlier] != meshes[i]; ++earlier)
            for (unsigned f = 0; f < s->mMeshes[meshes[earlier]]->mNumFaces; ++f)
                q0 += s->mMeshes[meshes[earlier]]->mFaces[f].mNumIndices >= 3;
        int j = 0;
        for (unsigned f = 0; f < m->mNumFaces; ++f) {
            const struct aiFace* face = &m->mFaces[f];
            if (face->mNumIndices < 3) continue;
            if (earlier < i) {
                poly_face[q++] = poly_face[q0++];
                continue;
            }
            while (j < obj->n_faces && (claimed[j] || !face_matches(m, face, obj, j))) ++j;
            if (j == obj->n_faces) {
                st = wc_fail(diag, WC_ERROR_IMPORT,
                             "'%s': cannot tell which f line assimp's face %u of mesh '%s' "
                             "came from (its corners match no remaining f line in order), so "
                             "the file's vertex order cannot be kept", path, f, m->mName.data);
                break;
            }
            claimed[j] = 1;
            poly_face[q++] = j++;
        }
    }
    wc_free(alloc, claimed);
    return st;
}
