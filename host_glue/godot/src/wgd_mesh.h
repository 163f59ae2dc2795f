/* A Godot mesh surface as Weft host arrays: the cloth's own mesh and a body's (mesh collider). */
#ifndef WEFT_GODOT_MESH_H
#define WEFT_GODOT_MESH_H

#include "gd_api.h"

enum { WGD_ARRAY_VERTEX = 0, WGD_ARRAY_NORMAL = 1, WGD_ARRAY_BONES = 6, WGD_ARRAY_WEIGHTS = 7,
       WGD_ARRAY_INDEX = 8 };

/* mesh.surface_get_arrays(surface) into *arrays (the caller destroys it). Returns 0 when the mesh
 * has no such surface (then *arrays is an empty array all the same). */
int wgd_mesh_surface(godot_object* mesh, int surface, godot_array* arrays);

/* The surface's vertices (each axis times scale[k]: the node's scale baked in) and triangles
 * wound counter-clockwise (Godot's front faces are clockwise; an unindexed surface is taken three
 * vertices a triangle). *pos and *tris are malloc'ed (the caller frees them, also on failure).
 * Returns 0 on no memory or an empty surface. */
int wgd_mesh_triangles(const godot_array* arrays, const float scale[3], float** pos, int* n_vertices, int** tris,
                       int* n_tris);

#endif
