/* WeftCloth: a NativeScript class on a MeshInstance that simulates the node's mesh with Weft.
 * The instance holds its exported properties (read when the node enters the tree: _ready) and,
 * once _ready has built the cloth, the Weft context, the cloth and the Godot objects the
 * result is written into. */
#ifndef WEFT_GODOT_CLOTH_NODE_H
#define WEFT_GODOT_CLOTH_NODE_H

#include <stdint.h>

#include "gd_api.h"
#include "weft/weft.h"

/* The godot plugin's names start with wgd_ (gpu/ owns wg_). */
#define WGD_MAX_COLLIDERS 64

typedef struct wgd_collider {
    godot_node_path path;       /* the CollisionShape, from the WeftCloth node (looked up every
                                   frame: a shape freed since _ready is simply skipped) */
    float local[16];            /* shape frame -> weft's collider frame (capsule axis, plane) */
} wgd_collider;

typedef struct wgd_cloth {
    godot_object* owner;        /* the MeshInstance */

    /* exported properties (weft_cloth_def fields, read at _ready) */
    double density;
    double stiffness[3];        /* per weft_spring_type */
    double damping[3];
    double wind[3];
    double tolerance;
    int64_t substeps;
    int64_t max_iterations;
    int64_t backend;            /* weft_backend */
    godot_pool_int_array pinned_vertices;
    godot_node_path colliders_root;
    double collider_thickness;
    double collider_friction;

    /* built at _ready */
    weft_context* ctx;
    weft_cloth cloth;
    int n_vertices;
    float scale[3];             /* the node's scale, baked into the positions Weft gets */
    float* positions;           /* (n_vertices x 3) object space, the last result */
    float* normals;
    float collider_xf[WGD_MAX_COLLIDERS * 16]; /* (n_colliders x 16) world */
    int n_colliders;
    wgd_collider colliders[WGD_MAX_COLLIDERS];
    godot_array arrays;         /* the surface's arrays, vertex and normal replaced each frame */
    godot_variant mesh;         /* the ArrayMesh the node shows (held: a reference) */
    godot_variant material;     /* the source surface's material */
    int has_arrays;
    int64_t frames;
} wgd_cloth;

/* NativeScript registration of the class, its methods and its properties. */
void wgd_cloth_register(void* handle);
void wgd_cloth_register_properties(void* handle);

/* Colliders: every enabled CollisionShape (sphere, capsule, plane) under colliders_root.
 * Fills c->colliders and defs (at most WGD_MAX_COLLIDERS); returns the count. */
int wgd_cloth_find_colliders(wgd_cloth* c, weft_collider_def* defs);
/* Each collider's current world transform into c->collider_xf. */
void wgd_cloth_collider_transforms(wgd_cloth* c);

#endif
