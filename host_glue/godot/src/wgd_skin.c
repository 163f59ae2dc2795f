/* CPU skinning of a Godot MeshInstance (wgd_skin.h). Transforms are kept as godot_transform
 * lays them out: 9 floats of basis rows, then the origin. */
#include "wgd_skin.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { XF = 12 };
_Static_assert(sizeof(godot_transform) == XF * sizeof(float), "Godot's real_t is float");

/* obj.method(arg), or obj.method() when arg < 0, as a Transform / an int. */
static godot_transform call_transform(godot_object* obj, const char* method, int arg) {
    godot_variant v = arg >= 0 ? gd_call_int(obj, method, arg) : gd_call(obj, method, 0, NULL, NULL);
    godot_transform t = gd->godot_variant_as_transform(&v);
    gd->godot_variant_destroy(&v);
    return t;
}

static int64_t call_int(godot_object* obj, const char* method, int arg) {
    godot_variant v = arg >= 0 ? gd_call_int(obj, method, arg) : gd_call(obj, method, 0, NULL, NULL);
    int64_t x = gd->godot_variant_as_int(&v);
    gd->godot_variant_destroy(&v);
    return x;
}

/* out = a x b (affine). out may not alias a or b. */
static void xf_mul(const float* a, const float* b, float* out) {
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) {
            out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
        }
        out[9 + r] = a[3 * r] * b[9] + a[3 * r + 1] * b[10] + a[3 * r + 2] * b[11] + a[9 + r];
    }
}

/* Bone `bone`'s global rest: its ancestors' rests times its own (what Godot inverts when it makes
 * a Skin for a node that has none). */
static godot_transform global_rest(godot_object* skeleton, int bone, int n_bones) {
    godot_transform g = call_transform(skeleton, "get_bone_rest", bone);
    int p = (int)call_int(skeleton, "get_bone_parent", bone);
    for (int depth = 0; p >= 0 && p < n_bones && depth < n_bones; depth++) {
        godot_transform r = call_transform(skeleton, "get_bone_rest", p);
        g = gd->godot_transform_operator_multiply(&r, &g);
        p = (int)call_int(skeleton, "get_bone_parent", p);
    }
    return g;
}

/* The node's binds: from its Skin, or one per bone from the rests. Returns 0 after an error. */
static int read_binds(wgd_skin* s, godot_object* node, godot_object* skeleton, const char* who) {
    int n_bones = (int)call_int(skeleton, "get_bone_count", -1);
    godot_object* skin = gd_call_object(node, "get_skin", 0, NULL);
    s->n_binds = skin ? (int)call_int(skin, "get_bind_count", -1) : n_bones;
    size_t n = (size_t)(s->n_binds > 0 ? s->n_binds : 1);
    s->bone = malloc(n * sizeof(int));
    s->pose = malloc(n * XF * sizeof(float));
    s->world = malloc(n * XF * sizeof(float));
    if (!s->bone || !s->pose || !s->world) {
        gd_error("%s: no memory for its skin", who);
        return 0;
    }
    for (int i = 0; i < s->n_binds; i++) {
        godot_transform pose;
        if (!skin) {
            s->bone[i] = i;
            godot_transform g = global_rest(skeleton, i, n_bones);
            pose = gd->godot_transform_affine_inverse(&g);
        } else {
            godot_variant nv = gd_call_int(skin, "get_bind_name", i);
            godot_string name = gd->godot_variant_as_string(&nv);
            char text[128];
            gd_string_text(&name, text, sizeof text);
            s->bone[i] = text[0] != '\0' ? gd_find_bone(skeleton, &name) : (int)call_int(skin, "get_bind_bone", i);
            gd->godot_string_destroy(&name);
            gd->godot_variant_destroy(&nv);
            if (s->bone[i] < 0 || s->bone[i] >= n_bones) {
                if (text[0] != '\0') {
                    gd_error("%s: its Skin's bind %d names bone '%s', which its Skeleton does not have", who, i, text);
                } else {
                    gd_error("%s: its Skin's bind %d is bone %d; its Skeleton has %d bones", who, i, s->bone[i],
                             n_bones);
                }
                return 0;
            }
            pose = call_transform(skin, "get_bind_pose", i);
        }
        memcpy(s->pose + XF * i, &pose, sizeof pose);
    }
    return 1;
}

/* ARRAY_BONES and ARRAY_WEIGHTS into s->bind and s->weight. Returns 0 after an error. */
static int read_influences(wgd_skin* s, const godot_array* arrays, const char* who) {
    godot_variant bv = gd->godot_array_get(arrays, WGD_ARRAY_BONES);
    godot_variant wv = gd->godot_array_get(arrays, WGD_ARRAY_WEIGHTS);
    godot_pool_int_array bones = gd->godot_variant_as_pool_int_array(&bv);
    godot_pool_real_array weights = gd->godot_variant_as_pool_real_array(&wv);
    int nb = (int)gd->godot_pool_int_array_size(&bones), nw = (int)gd->godot_pool_real_array_size(&weights);
    size_t n = (size_t)s->n_vertices * WGD_BONES_PER_VERTEX;
    int ok = 0;
    if (nb != (int)n || nw != (int)n) {
        gd_error("%s: its mesh has %d bone indices and %d weights for %d vertices (4 each)", who, nb, nw,
                 s->n_vertices);
    } else if (!(s->bind = malloc(n * sizeof(int))) || !(s->weight = malloc(n * sizeof(float)))) {
        gd_error("%s: no memory for its skin", who);
    } else {
        godot_pool_int_array_read_access* br = gd->godot_pool_int_array_read(&bones);
        godot_pool_real_array_read_access* wr = gd->godot_pool_real_array_read(&weights);
        const godot_int* b = gd->godot_pool_int_array_read_access_ptr(br);
        const godot_real* w = gd->godot_pool_real_array_read_access_ptr(wr);
        ok = 1;
        for (size_t k = 0; k < n && ok; k++) {
            s->bind[k] = (int)b[k];
            s->weight[k] = (float)w[k];
            int v = (int)(k / WGD_BONES_PER_VERTEX);
            if (!isfinite(w[k])) {
                gd_error("%s: vertex %d has a non-finite bone weight", who, v);
                ok = 0;
            } else if (w[k] != 0.0f && (b[k] < 0 || b[k] >= s->n_binds)) {
                gd_error("%s: vertex %d is weighted to bind %d; its skin has %d binds", who, v, (int)b[k],
                         s->n_binds);
                ok = 0;
            }
        }
        gd->godot_pool_real_array_read_access_destroy(wr);
        gd->godot_pool_int_array_read_access_destroy(br);
    }
    gd->godot_pool_real_array_destroy(&weights);
    gd->godot_pool_int_array_destroy(&bones);
    gd->godot_variant_destroy(&wv);
    gd->godot_variant_destroy(&bv);
    return ok;
}

static int has_array(const godot_array* arrays, int which) {
    godot_variant v = gd->godot_array_get(arrays, which);
    int has = gd->godot_variant_get_type(&v) != GODOT_VARIANT_TYPE_NIL;
    gd->godot_variant_destroy(&v);
    return has;
}

int wgd_skin_init(wgd_skin* s, godot_object* node, const godot_array* arrays, const char* who) {
    memset(s, 0, sizeof *s);
    godot_variant pv = gd_call(node, "get_skeleton_path", 0, NULL, NULL);
    s->skeleton = gd->godot_variant_as_node_path(&pv);
    s->has_skeleton_path = 1;
    gd->godot_variant_destroy(&pv);
    godot_object* skeleton = gd_get_node(node, &s->skeleton);
    if (gd->godot_array_size(arrays) <= WGD_ARRAY_INDEX || !has_array(arrays, WGD_ARRAY_BONES) ||
        !has_array(arrays, WGD_ARRAY_WEIGHTS) || !skeleton || !gd_is_class(skeleton, "Skeleton")) {
        wgd_skin_free(s);
        return 0;
    }
    godot_variant vv = gd->godot_array_get(arrays, WGD_ARRAY_VERTEX);
    godot_pool_vector3_array verts = gd->godot_variant_as_pool_vector3_array(&vv);
    s->n_vertices = (int)gd->godot_pool_vector3_array_size(&verts);
    s->rest = malloc((size_t)(s->n_vertices > 0 ? s->n_vertices : 1) * 3 * sizeof(float));
    if (s->rest) {
        godot_pool_vector3_array_read_access* r = gd->godot_pool_vector3_array_read(&verts);
        memcpy(s->rest, gd->godot_pool_vector3_array_read_access_ptr(r), (size_t)s->n_vertices * 3 * sizeof(float));
        gd->godot_pool_vector3_array_read_access_destroy(r);
    }
    gd->godot_pool_vector3_array_destroy(&verts);
    gd->godot_variant_destroy(&vv);
    if (!s->rest) gd_error("%s: no memory for its skin", who);
    if (!s->rest || !read_binds(s, node, skeleton, who) || !read_influences(s, arrays, who)) {
        wgd_skin_free(s);
        return -1;
    }
    return 1;
}

int wgd_skin_world(wgd_skin* s, godot_object* node, float* out) {
    godot_object* skeleton = gd_get_node(node, &s->skeleton);
    if (!skeleton) return 0;
    godot_variant gv = gd_call(node, "get_global_transform", 0, NULL, NULL);
    godot_transform g = gd->godot_variant_as_transform(&gv);
    gd->godot_variant_destroy(&gv);
    float node_xf[XF], bone_pose[XF];
    memcpy(node_xf, &g, sizeof node_xf);
    for (int i = 0; i < s->n_binds; i++) {
        godot_transform p = call_transform(skeleton, "get_bone_global_pose", s->bone[i]);
        float skinning[XF];
        memcpy(bone_pose, &p, sizeof bone_pose);
        xf_mul(bone_pose, s->pose + XF * i, skinning);
        xf_mul(node_xf, skinning, s->world + XF * i);
    }
    for (int v = 0; v < s->n_vertices; v++) {
        const float* p = s->rest + 3 * v;
        float q[3] = {0.0f, 0.0f, 0.0f};
        for (int j = 0; j < WGD_BONES_PER_VERTEX; j++) {
            float w = s->weight[WGD_BONES_PER_VERTEX * v + j];
            if (w == 0.0f) continue;
            const float* m = s->world + XF * s->bind[WGD_BONES_PER_VERTEX * v + j];
            for (int r = 0; r < 3; r++) {
                q[r] += w * (m[3 * r] * p[0] + m[3 * r + 1] * p[1] + m[3 * r + 2] * p[2] + m[9 + r]);
            }
        }
        memcpy(out + 3 * v, q, sizeof q);
    }
    return 1;
}

void wgd_skin_free(wgd_skin* s) {
    free(s->rest);
    free(s->bind);
    free(s->weight);
    free(s->bone);
    free(s->pose);
    free(s->world);
    s->rest = s->weight = s->pose = s->world = NULL;
    s->bind = s->bone = NULL;
    s->n_vertices = s->n_binds = 0;
    if (s->has_skeleton_path) gd->godot_node_path_destroy(&s->skeleton);
    s->has_skeleton_path = 0;
}
