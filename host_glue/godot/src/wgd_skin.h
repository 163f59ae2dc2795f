/* A skinned Godot MeshInstance's vertices computed on the CPU, as Godot 3.2 places them on the
 * GPU (GDNative cannot read those back): the node's global transform times, for each vertex,
 * the weighted sum over its four (bind, weight) pairs of the bind's bone global pose times the
 * bind's pose, applied to the rest vertex. Binds come from the node's Skin (a bind's name, else
 * its bone index, picks the bone), or, with no Skin, one per bone with the inverse of the bone's
 * global rest, as Godot makes one. Weights are used as given (Godot's shader does not
 * renormalise them). */
#ifndef WEFT_GODOT_SKIN_H
#define WEFT_GODOT_SKIN_H

#include "wgd_mesh.h"

enum { WGD_BONES_PER_VERTEX = 4 };

typedef struct wgd_skin {
    int n_vertices;
    float* rest;                /* (n_vertices x 3) mesh space */
    int* bind;                  /* (n_vertices x 4) bind index of each influence */
    float* weight;              /* (n_vertices x 4) */
    int n_binds;
    int* bone;                  /* (n_binds) the skeleton's bone of each bind */
    float* pose;                /* (n_binds x 12) each bind's pose (godot_transform layout) */
    float* world;               /* (n_binds x 12) per frame: node x bone global pose x bind pose */
    godot_node_path skeleton;   /* the MeshInstance's `skeleton` path (from the MeshInstance) */
    int has_skeleton_path;      /* skeleton is to be destroyed */
} wgd_skin;

/* Read a MeshInstance's skinning: its surface's arrays (ARRAY_BONES / ARRAY_WEIGHTS), its
 * skeleton path and Skin. Returns 1 (s filled: wgd_skin_free it), 0 when Godot draws the node
 * unskinned (no bones or weights in the surface, or `skeleton` names no Skeleton), -1 after a
 * Godot error starting with `who` and naming what is wrong (bone and weight arrays of the wrong
 * size, a non-finite weight, an influence naming no bind, a bind naming no bone, no memory). */
int wgd_skin_init(wgd_skin* s, godot_object* node, const godot_array* arrays, const char* who);

/* The skinned vertices in world space into out (n_vertices x 3), with the skeleton's current
 * bone poses and the node's global transform. Returns 0 (out untouched) when the skeleton is
 * no longer found from the node. */
int wgd_skin_world(wgd_skin* s, godot_object* node, float* out);

/* Frees what wgd_skin_init made; a zeroed wgd_skin is fine too. */
void wgd_skin_free(wgd_skin* s);

#endif
