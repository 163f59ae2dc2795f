/* WeftCloth's colliders from Godot shapes: SphereShape, CapsuleShape (Godot's axis is local Z,
 * its height the cylinder part) and PlaneShape (normal and distance) on CollisionShape nodes,
 * mapped onto weft's sphere, capsule (local Y, half_height) and plane (local y = 0). The node's
 * global scale at _ready is applied as Godot applies it to the shape: a sphere's or capsule's
 * sizes times a uniform scale (a non-uniform one would make an ellipsoid: refused with an error
 * naming the node), a plane moved and turned exactly as the scaled transform maps it. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "weft_cloth_node.h"

static void mat_mul(const float a[16], const float b[16], float out[16]) {
    for (int c = 0; c < 4; c++) {
        for (int r = 0; r < 4; r++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++) s += a[4 * k + r] * b[4 * c + k];
            out[4 * c + r] = s;
        }
    }
}

static void mat_identity(float m[16]) {
    memset(m, 0, 16 * sizeof(float));
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

static double call_real(godot_object* obj, const char* method) {
    godot_variant v = gd_call(obj, method, 0, NULL, NULL);
    double x = gd->godot_variant_as_real(&v);
    gd->godot_variant_destroy(&v);
    return x;
}

/* The frame (Y the normal, the origin on the plane) in the rigid frame m of a node whose
 * global transform is t, of the PlaneShape plane (normal, d) in the node's space: the plane
 * t maps it to (normal: t's basis inverse-transposed; a point: t of normal x d). */
static void plane_frame(const godot_transform* t, const float m[16], const float plane[4], float local[16]) {
    float e[12];   /* basis rows, then the origin */
    memcpy(e, t, sizeof e);
    float cof[9];   /* the basis's cofactors: its inverse transposed times its determinant */
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) {
            cof[3 * r + c] = e[3 * ((r + 1) % 3) + (c + 1) % 3] * e[3 * ((r + 2) % 3) + (c + 2) % 3] -
                             e[3 * ((r + 1) % 3) + (c + 2) % 3] * e[3 * ((r + 2) % 3) + (c + 1) % 3];
        }
    }
    float sign = e[0] * cof[0] + e[1] * cof[1] + e[2] * cof[2] < 0.0f ? -1.0f : 1.0f;   /* the determinant's */
    float nw[3], pw[3], n[3], p[3];
    for (int r = 0; r < 3; r++) {
        nw[r] = sign * (cof[3 * r] * plane[0] + cof[3 * r + 1] * plane[1] + cof[3 * r + 2] * plane[2]);
        pw[r] = (e[3 * r] * plane[0] + e[3 * r + 1] * plane[1] + e[3 * r + 2] * plane[2]) * plane[3];
    }
    for (int i = 0; i < 3; i++) {   /* into the rigid frame: R^T */
        n[i] = m[4 * i] * nw[0] + m[4 * i + 1] * nw[1] + m[4 * i + 2] * nw[2];
        p[i] = m[4 * i] * pw[0] + m[4 * i + 1] * pw[1] + m[4 * i + 2] * pw[2];
    }
    float nl = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int i = 0; i < 3; i++) n[i] = nl > 0.0f ? n[i] / nl : (i == 1);
    float tx[3] = {1.0f, 0.0f, 0.0f};
    if (n[0] > 0.9f || n[0] < -0.9f) {
        tx[0] = 0.0f;
        tx[2] = 1.0f;
    }
    float z[3] = {tx[1] * n[2] - tx[2] * n[1], tx[2] * n[0] - tx[0] * n[2], tx[0] * n[1] - tx[1] * n[0]};
    float zl = sqrtf(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    for (int i = 0; i < 3; i++) z[i] /= zl;
    float x[3] = {n[1] * z[2] - n[2] * z[1], n[2] * z[0] - n[0] * z[2], n[0] * z[1] - n[1] * z[0]};
    for (int i = 0; i < 3; i++) {
        local[i] = x[i];
        local[4 + i] = n[i];
        local[8 + i] = z[i];
        local[12 + i] = p[i];
    }
}

/* One CollisionShape: its weft def and the frame from the node's rigid frame to weft's. */
static int shape_collider(wgd_cloth* c, godot_object* node, const char* path, weft_collider_def* def,
                          wgd_collider* col) {
    godot_variant dis = gd_call(node, "is_disabled", 0, NULL, NULL);
    int disabled = gd->godot_variant_as_bool(&dis);
    gd->godot_variant_destroy(&dis);
    godot_object* shape = gd_call_object(node, "get_shape", 0, NULL);
    if (disabled || !shape) return 0;
    godot_variant tv = gd_call(node, "get_global_transform", 0, NULL, NULL);
    godot_transform t = gd->godot_variant_as_transform(&tv);
    gd->godot_variant_destroy(&tv);
    float m[16], *scale = col->scale, *local = col->local;
    gd_rigid_matrix(&t, m, scale);
    float lo = fminf(scale[0], fminf(scale[1], scale[2])), hi = fmaxf(scale[0], fmaxf(scale[1], scale[2]));
    double s = (scale[0] + scale[1] + scale[2]) / 3.0;
    int uniform = hi - lo <= WGD_UNIFORM_SCALE * hi;
    *def = weft_default_collider_def();
    def->thickness = c->collider_thickness;
    def->friction = c->collider_friction;
    mat_identity(local);
    int round = gd_is_class(shape, "SphereShape") || gd_is_class(shape, "CapsuleShape");
    if (round && !uniform) {
        char name[128];
        gd_error("WeftCloth '%s': collider '%s' has a non-uniform scale (%g, %g, %g), which would make its %s "
                 "an ellipsoid: not a collider", gd_node_name(c->owner, name, sizeof name), path, scale[0], scale[1],
                 scale[2], gd_is_class(shape, "SphereShape") ? "sphere" : "capsule");
        return 0;
    }
    if (gd_is_class(shape, "SphereShape")) {
        def->type = WEFT_COLLIDER_SPHERE;
        def->radius = s * call_real(shape, "get_radius");
    } else if (gd_is_class(shape, "CapsuleShape")) {
        def->type = WEFT_COLLIDER_CAPSULE;
        def->radius = s * call_real(shape, "get_radius");
        def->half_height = s * 0.5 * call_real(shape, "get_height");
        /* rotation +90 degrees about X: weft's local Y onto Godot's local Z */
        local[5] = 0.0f;
        local[6] = 1.0f;
        local[9] = -1.0f;
        local[10] = 0.0f;
    } else if (gd_is_class(shape, "PlaneShape")) {
        def->type = WEFT_COLLIDER_PLANE;
        godot_variant pv = gd_call(shape, "get_plane", 0, NULL, NULL);
        godot_plane p = gd->godot_variant_as_plane(&pv);
        gd->godot_variant_destroy(&pv);
        float e[4];   /* Plane: normal (Vector3), then d */
        memcpy(e, &p, sizeof e);
        plane_frame(&t, m, e, local);
    } else {
        return 0;
    }
    return 1;
}

static void walk(wgd_cloth* c, godot_object* node, weft_collider_def* defs, int depth) {
    if (depth > 16 || c->n_colliders >= WGD_MAX_COLLIDERS) return;
    if (node != c->owner && gd_is_class(node, "CollisionShape")) {
        wgd_collider* col = &c->colliders[c->n_colliders];
        godot_variant arg;
        gd->godot_variant_new_object(&arg, node);
        const godot_variant* args[1] = {&arg};
        godot_variant pv = gd_call(c->owner, "get_path_to", 1, args, NULL);
        col->path = gd->godot_variant_as_node_path(&pv);
        gd->godot_variant_destroy(&pv);
        gd->godot_variant_destroy(&arg);
        char path[256];
        if (shape_collider(c, node, gd_node_path_text(&col->path, path, sizeof path), &defs[c->n_colliders], col)) {
            col->scale_warned = 0;
            c->n_colliders++;
        } else {
            gd->godot_node_path_destroy(&col->path);
        }
    }
    godot_variant kids = gd_call(node, "get_children", 0, NULL, NULL);
    godot_array a = gd->godot_variant_as_array(&kids);
    for (godot_int i = 0; i < gd->godot_array_size(&a); i++) {
        godot_variant k = gd->godot_array_get(&a, i);
        godot_object* child = gd->godot_variant_as_object(&k);
        gd->godot_variant_destroy(&k);
        if (child) walk(c, child, defs, depth + 1);
    }
    gd->godot_array_destroy(&a);
    gd->godot_variant_destroy(&kids);
}

int wgd_cloth_find_colliders(wgd_cloth* c, weft_collider_def* defs) {
    c->n_colliders = 0;
    godot_object* root = gd_get_node(c->owner, &c->colliders_root);
    if (!root) {
        char path[256];
        gd_error("WeftCloth: colliders_root '%s' is not a node: no colliders",
                 gd_node_path_text(&c->colliders_root, path, sizeof path));
        return 0;
    }
    walk(c, root, defs, 0);
    wgd_cloth_collider_transforms(c);
    for (int i = 0; i < c->n_colliders; i++) memcpy(defs[i].transform, c->collider_xf + 16 * i, 16 * sizeof(float));
    return c->n_colliders;
}

void wgd_cloth_collider_transforms(wgd_cloth* c) {
    for (int i = 0; i < c->n_colliders; i++) {
        wgd_collider* col = &c->colliders[i];
        godot_object* node = gd_get_node(c->owner, &col->path);
        if (!node) continue;   /* removed from the tree: it stays where it was */
        float g[16], scale[3];
        gd_global_transform(node, g, scale);
        mat_mul(g, col->local, c->collider_xf + 16 * i);
        for (int k = 0; k < 3 && !col->scale_warned; k++) {
            if (fabsf(scale[k] - col->scale[k]) > WGD_UNIFORM_SCALE * col->scale[k]) {
                char name[128], path[256];
                gd_warning("WeftCloth '%s': collider '%s' was scaled after _ready; it keeps its size and shape from "
                           "then", gd_node_name(c->owner, name, sizeof name),
                           gd_node_path_text(&col->path, path, sizeof path));
                col->scale_warned = 1;
            }
        }
    }
}
