/* WeftCloth's attachments to Skeleton bones: attach_bones[i] (a bone name of the Skeleton at
 * attach_skeleton) holds the vertices attach_vertices[i] (a PoolIntArray of the mesh's vertex
 * indices). Each is a Weft attachment whose transform is the bone's world pose (the skeleton's
 * global transform times the bone's global pose), bound at _ready and followed every frame. */
#include <stdlib.h>
#include <string.h>

#include "weft_cloth_node.h"

static int list_size(const godot_variant* v) {
    godot_variant_type t = gd->godot_variant_get_type(v);
    if (t == GODOT_VARIANT_TYPE_POOL_INT_ARRAY) {
        godot_pool_int_array a = gd->godot_variant_as_pool_int_array(v);
        int n = (int)gd->godot_pool_int_array_size(&a);
        gd->godot_pool_int_array_destroy(&a);
        return n;
    }
    if (t == GODOT_VARIANT_TYPE_ARRAY) {
        godot_array a = gd->godot_variant_as_array(v);
        int n = (int)gd->godot_array_size(&a);
        gd->godot_array_destroy(&a);
        return n;
    }
    return -1;
}

int wgd_cloth_bone_attachments(wgd_cloth* c, weft_attachment_def* defs, int** storage) {
    char name[128], path[256], bone[128];
    gd_node_name(c->owner, name, sizeof name);
    *storage = NULL;
    c->first_bone = c->n_attachments;
    int n = (int)gd->godot_pool_string_array_size(&c->attach_bones);
    int nv = (int)gd->godot_array_size(&c->attach_vertices);
    gd_node_path_text(&c->attach_skeleton, path, sizeof path);
    if (path[0] == '\0') {
        if (n == 0 && nv == 0) return 0;
        gd_error("WeftCloth '%s': attach_bones / attach_vertices given but attach_skeleton is empty", name);
        return -1;
    }
    godot_object* sk = gd_get_node(c->owner, &c->attach_skeleton);
    if (!sk || !gd_is_class(sk, "Skeleton")) {
        gd_error("WeftCloth '%s': attach_skeleton '%s' is %s", name, path, sk ? "not a Skeleton" : "not a node");
        return -1;
    }
    if (n != nv) {
        gd_error("WeftCloth '%s': attach_bones has %d names but attach_vertices %d vertex lists", name, n, nv);
        return -1;
    }
    if (n > WGD_MAX_BONE_ATTACHMENTS) {
        gd_error("WeftCloth '%s': attach_bones has %d names, more than %d", name, n, WGD_MAX_BONE_ATTACHMENTS);
        return -1;
    }
    int total = 0;
    for (int i = 0; i < n; i++) {
        godot_variant v = gd->godot_array_get(&c->attach_vertices, i);
        int k = list_size(&v);
        gd->godot_variant_destroy(&v);
        if (k < 0) {
            gd_error("WeftCloth '%s': attach_vertices[%d] is not a PoolIntArray of vertex indices", name, i);
            return -1;
        }
        total += k;
    }
    *storage = malloc((size_t)(total > 0 ? total : 1) * sizeof(int));
    if (!*storage) return -1;
    int at = 0;
    for (int i = 0; i < n; i++) {
        godot_string s = gd->godot_pool_string_array_get(&c->attach_bones, i);
        gd_string_text(&s, bone, sizeof bone);
        c->bone_index[i] = gd_find_bone(sk, &s);
        gd->godot_string_destroy(&s);
        if (c->bone_index[i] < 0) {
            gd_error("WeftCloth '%s': attach_bones[%d] '%s' is not a bone of Skeleton '%s'", name, i, bone, path);
            return -1;
        }
        godot_variant v = gd->godot_array_get(&c->attach_vertices, i);
        godot_pool_int_array a = gd->godot_variant_as_pool_int_array(&v);
        int k = (int)gd->godot_pool_int_array_size(&a);
        godot_pool_int_array_read_access* ra = gd->godot_pool_int_array_read(&a);
        const godot_int* p = gd->godot_pool_int_array_read_access_ptr(ra);
        for (int j = 0; j < k; j++) (*storage)[at + j] = (int)p[j];
        gd->godot_pool_int_array_read_access_destroy(ra);
        gd->godot_pool_int_array_destroy(&a);
        gd->godot_variant_destroy(&v);
        defs[i] = weft_default_attachment_def();
        defs[i].vertices = *storage + at;
        defs[i].n_vertices = k;
        gd_bone_global_transform(sk, c->bone_index[i], defs[i].bind_transform);
        memcpy(c->attach_xf + 16 * (c->first_bone + i), defs[i].bind_transform, 16 * sizeof(float));
        at += k;
    }
    gd->godot_node_path_destroy(&c->skeleton_path);
    gd->godot_node_path_new_copy(&c->skeleton_path, &c->attach_skeleton);
    c->n_attachments += n;
    return n;
}

void wgd_cloth_bone_transforms(wgd_cloth* c) {
    if (c->n_attachments <= c->first_bone) return;
    godot_object* sk = gd_get_node(c->owner, &c->skeleton_path);
    if (!sk) return;   /* removed from the tree: the bones stay where they were */
    for (int i = c->first_bone; i < c->n_attachments; i++) {
        gd_bone_global_transform(sk, c->bone_index[i - c->first_bone], c->attach_xf + 16 * i);
    }
}
