/* WeftCloth's body: the MeshInstance at `body` as a Weft mesh collider. Its surface 0 (its node's
 * scale baked in) moves rigidly with the node's global transform every frame. A skinned body's
 * deformation is not followed (Godot 3.2's GDNative has no call that returns skinned vertices):
 * it is taken at its rest shape, moving with its node. */
#include <stdlib.h>
#include <string.h>

#include "weft_cloth_node.h"
#include "wgd_mesh.h"

int wgd_cloth_body_collider(wgd_cloth* c, weft_mesh_collider_def* def, float** pos, int** tris) {
    char name[128], path[256];
    *pos = NULL;
    *tris = NULL;
    c->has_body = 0;
    gd_node_path_text(&c->body, path, sizeof path);
    if (path[0] == '\0') return 0;
    gd_node_name(c->owner, name, sizeof name);
    godot_object* node = gd_get_node(c->owner, &c->body);
    if (!node || !gd_is_class(node, "MeshInstance")) {
        gd_error("WeftCloth '%s': body '%s' is %s: no mesh collider", name, path,
                 node ? "not a MeshInstance" : "not a node");
        return 0;
    }
    godot_object* mesh = gd_call_object(node, "get_mesh", 0, NULL);
    godot_array arrays;
    int ok = mesh && wgd_mesh_surface(mesh, &arrays);
    if (mesh) {
        float scale[3];
        gd_global_transform(node, c->body_xf, scale);
        int n = 0, nt = 0;
        ok = ok && wgd_mesh_triangles(&arrays, scale, pos, &n, tris, &nt);
        if (ok) {
            godot_variant bones = gd->godot_array_get(&arrays, WGD_ARRAY_BONES);
            if (gd->godot_variant_get_type(&bones) != GODOT_VARIANT_TYPE_NIL) {
                gd_warning("WeftCloth '%s': body '%s' is skinned; it collides at its rest shape, moving with its "
                           "node", name, path);
            }
            gd->godot_variant_destroy(&bones);
        }
        gd->godot_array_destroy(&arrays);
        *def = weft_default_mesh_collider_def();
        def->mesh.positions = *pos;
        def->mesh.n_vertices = n;
        def->mesh.indices = *tris;
        def->mesh.n_faces = nt;
        memcpy(def->transform, c->body_xf, sizeof c->body_xf);
        def->thickness = c->collider_thickness;
        def->friction = c->collider_friction;
    }
    if (!ok) {
        gd_error("WeftCloth '%s': body '%s' has no mesh with triangles in surface 0: no mesh collider", name, path);
        return 0;
    }
    gd->godot_node_path_destroy(&c->body_path);
    gd->godot_node_path_new_copy(&c->body_path, &c->body);
    c->has_body = 1;
    return 1;
}

void wgd_cloth_body_transform(wgd_cloth* c) {
    if (!c->has_body) return;
    godot_object* node = gd_get_node(c->owner, &c->body_path);
    if (node) gd_global_transform(node, c->body_xf, NULL);
}
