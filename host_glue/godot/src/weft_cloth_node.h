/* WeftCloth: a NativeScript class on a MeshInstance that simulates the node's mesh with Weft.
 * The instance holds its exported properties (read when the node enters the tree: _ready) and,
 * once _ready has built the cloth, the Weft context, the cloth and the Godot objects the
 * result is written into. */
#ifndef WEFT_GODOT_CLOTH_NODE_H
#define WEFT_GODOT_CLOTH_NODE_H

#include <stdint.h>

#include "gd_api.h"
#include "weft/weft.h"
#include "wgd_skin.h"

/* The godot plugin's names start with wgd_ (gpu/ owns wg_). */
#define WGD_MAX_COLLIDERS 64
#define WGD_MAX_BONE_ATTACHMENTS 64

typedef struct wgd_collider {
    godot_node_path path;       /* the CollisionShape, from the WeftCloth node (looked up every
                                   frame: a shape freed since _ready is simply skipped) */
    float local[16];            /* the node's rigid frame -> weft's collider frame (capsule axis,
                                   plane) */
    float scale[3];             /* the node's global scale at _ready (sizes, plane) */
    int scale_warned;           /* a later change of scale was reported */
} wgd_collider;

/* Scales whose axes differ by no more than this fraction are uniform. */
#define WGD_UNIFORM_SCALE 1e-4f

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
    godot_node_path attach_skeleton;        /* a Skeleton; empty: no bone attachments */
    godot_pool_string_array attach_bones;   /* bone names ... */
    godot_array attach_vertices;            /* ... and a PoolIntArray of vertices for each */
    godot_node_path body;                   /* a MeshInstance: a mesh collider; empty: none */

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
    int n_attachments;          /* the pins' (when there are pins: slot 0), then the bones' */
    int first_bone;             /* the first bone's slot */
    int bone_index[WGD_MAX_BONE_ATTACHMENTS];
    godot_node_path skeleton_path;   /* attach_skeleton as _ready found it */
    float attach_xf[(1 + WGD_MAX_BONE_ATTACHMENTS) * 16]; /* (n_attachments x 16) world */
    int has_body;
    int body_skinned;           /* the body is skinned (skin): body_pos is world, per frame */
    godot_node_path body_path;  /* body as _ready found it */
    float body_xf[16];          /* the body's world transform (rigid; its scale is in the mesh) */
    float* body_pos;            /* (body_n_vertices x 3) rigid: mesh space, the node's scale baked
                                   in; skinned: world, this frame's */
    int body_n_vertices;
    wgd_skin skin;              /* a skinned body's skinning */
    int n_surfaces;             /* the mesh's surfaces, joined into the one cloth: */
    godot_array* surfaces;      /* (n_surfaces) each one's arrays, vertex and normal replaced each
                                   frame */
    godot_variant* materials;   /* (n_surfaces) each one's material */
    int* surface_first;         /* (n_surfaces + 1) each one's first vertex in the cloth */
    godot_variant mesh;         /* the ArrayMesh the node shows (held: a reference) */
    int64_t frames;
} wgd_cloth;

/* NativeScript registration of the class, its methods and its properties. */
void wgd_cloth_register(void* handle);
void wgd_cloth_register_properties(void* handle);

/* The node's mesh as one cloth: every surface (triangles; an error names a surface that is not)
 * as Weft host arrays, surface k's vertices after those of the surfaces before it (the node's
 * scale baked in). *pos and *tris are malloc'ed (the caller frees them, also on failure); the
 * surfaces' arrays and materials stay in c for wgd_cloth_write_surfaces. Returns 0 after a Godot
 * error. */
int wgd_cloth_read_surfaces(wgd_cloth* c, float** pos, int** tris, int* n_tris);
/* The result (c->positions, c->normals) into each surface of c->mesh, with its material. */
void wgd_cloth_write_surfaces(wgd_cloth* c);
void wgd_cloth_surfaces_release(wgd_cloth* c);

/* Colliders: every enabled CollisionShape (sphere, capsule, plane) under colliders_root.
 * Fills c->colliders and defs (at most WGD_MAX_COLLIDERS); returns the count. */
int wgd_cloth_find_colliders(wgd_cloth* c, weft_collider_def* defs);
/* Each collider's current world transform into c->collider_xf. */
void wgd_cloth_collider_transforms(wgd_cloth* c);

/* Bone attachments (attach_skeleton, attach_bones, attach_vertices), one def each into defs (at
 * most WGD_MAX_BONE_ATTACHMENTS), their vertex lists in *storage (malloc'ed; the caller frees
 * it), the bones into c. Returns the count (0: none asked), or -1 after a Godot error naming
 * the property at fault. */
int wgd_cloth_bone_attachments(wgd_cloth* c, weft_attachment_def* defs, int** storage);
/* Each bone's current world transform into c->attach_xf from slot c->first_bone. */
void wgd_cloth_bone_transforms(wgd_cloth* c);

/* The body (a MeshInstance) as a mesh collider from its surface 0: skinned (world vertices,
 * identity transform) when Godot draws it skinned, else rigid (its node's scale baked in, at its
 * node's global transform). *tris (malloc'ed) backs def->mesh until the cloth is built; the
 * caller frees it (the positions are c's). Returns 1 (c->has_body), 0 when body is empty or after
 * a Godot error naming it (no mesh collider then). */
int wgd_cloth_body_collider(wgd_cloth* c, weft_mesh_collider_def* def, int** tris);
/* Before a step: the body's world transform into c->body_xf, or a skinned body's world vertices
 * handed to Weft (weft_cloth_set_mesh_collider_vertices). A body gone from the tree stays. */
void wgd_cloth_body_update(wgd_cloth* c);
/* The body's world vertices of the last frame (PoolVector3Array; empty without a body). */
godot_variant wgd_cloth_body_vertices(const wgd_cloth* c);
void wgd_cloth_body_release(wgd_cloth* c);

#endif
