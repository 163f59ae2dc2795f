/* WeftCloth's body: the MeshInstance at `body` as a Weft mesh collider, from its surface 0. A
 * body Godot draws skinned (bone indices and weights in the surface, its `skeleton` naming a
 * Skeleton) is skinned here every frame (wgd_skin.h) and handed to Weft as world vertices (a
 * deforming mesh collider); any other body moves rigidly with its node's global transform, its
 * node's scale baked into the mesh. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "weft_cloth_node.h"
#include "wgd_mesh.h"

int wgd_cloth_body_collider(wgd_cloth* c, weft_mesh_collider_def* def, int** tris) {
    char name[128], path[256], who[512];
    *tris = NULL;
    wgd_cloth_body_release(c);
    gd_node_path_text(&c->body, path, sizeof path);
    if (path[0] == '\0') return 0;
    gd_node_name(c->owner, name, sizeof name);
    snprintf(who, sizeof who, "WeftCloth '%s': body '%s'", name, path);
    godot_object* node = gd_get_node(c->owner, &c->body);
    if (!node || !gd_is_class(node, "MeshInstance")) {
        gd_error("%s is %s: no mesh collider", who, node ? "not a MeshInstance" : "not a node");
        return 0;
    }
    godot_object* mesh = gd_call_object(node, "get_mesh", 0, NULL);
    godot_array arrays;
    int ok = mesh && wgd_mesh_surface(mesh, 0, &arrays);
    int skinned = 0;
    if (mesh) {
        float scale[3];
        gd_global_transform(node, c->body_xf, scale);
        skinned = ok ? wgd_skin_init(&c->skin, node, &arrays, who) : 0;
        float one[3] = {1.0f, 1.0f, 1.0f};
        int nt = 0;
        ok = ok && skinned >= 0 &&
             wgd_mesh_triangles(&arrays, skinned ? one : scale, &c->body_pos, &c->body_n_vertices, tris, &nt);
        gd->godot_array_destroy(&arrays);
        if (ok && skinned) wgd_skin_world(&c->skin, node, c->body_pos);
        *def = weft_default_mesh_collider_def();
        def->mesh.positions = c->body_pos;
        def->mesh.n_vertices = c->body_n_vertices;
        def->mesh.indices = *tris;
        def->mesh.n_faces = nt;
        if (!skinned) memcpy(def->transform, c->body_xf, sizeof c->body_xf);   /* else world: identity */
        def->thickness = c->collider_thickness;
        def->friction = c->collider_friction;
    }
    if (!ok) {
        if (skinned >= 0) gd_error("%s has no mesh with triangles in surface 0: no mesh collider", who);
        wgd_cloth_body_release(c);
        return 0;
    }
    gd->godot_node_path_destroy(&c->body_path);
    gd->godot_node_path_new_copy(&c->body_path, &c->body);
    c->has_body = 1;
    c->body_skinned = skinned;
    return 1;
}

void wgd_cloth_body_update(wgd_cloth* c) {
    if (!c->has_body) return;
    godot_object* node = gd_get_node(c->owner, &c->body_path);
    if (!node) return;   /* removed from the tree: it stays where it was */
    if (!c->body_skinned) {
        gd_global_transform(node, c->body_xf, NULL);
    } else if (wgd_skin_world(&c->skin, node, c->body_pos)) {
        weft_cloth_set_mesh_collider_vertices(c->ctx, c->cloth, 0, c->body_pos, c->body_n_vertices);   /* logged */
    }
}

godot_variant wgd_cloth_body_vertices(const wgd_cloth* c) {
    godot_pool_vector3_array a;
    gd->godot_pool_vector3_array_new(&a);
    int n = c->has_body ? c->body_n_vertices : 0;
    gd->godot_pool_vector3_array_resize(&a, n);
    godot_pool_vector3_array_write_access* w = gd->godot_pool_vector3_array_write(&a);
    float* p = (float*)gd->godot_pool_vector3_array_write_access_ptr(w);
    const float* m = c->body_xf;
    for (int i = 0; i < n; i++) {
        const float* q = c->body_pos + 3 * i;
        for (int r = 0; r < 3; r++) {
            p[3 * i + r] = c->body_skinned ? q[r] : m[r] * q[0] + m[4 + r] * q[1] + m[8 + r] * q[2] + m[12 + r];
        }
    }
    gd->godot_pool_vector3_array_write_access_destroy(w);
    godot_variant v;
    gd->godot_variant_new_pool_vector3_array(&v, &a);
    gd->godot_pool_vector3_array_destroy(&a);
    return v;
}

void wgd_cloth_body_release(wgd_cloth* c) {
    free(c->body_pos);
    c->body_pos = NULL;
    c->body_n_vertices = 0;
    c->has_body = c->body_skinned = 0;
    wgd_skin_free(&c->skin);
}
