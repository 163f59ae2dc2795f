/* The mesh of a scene: read from a file through the public API (weft_mesh_read, the import a
 * cloth's mesh goes through) or generated as a grid, then transformed; and the checks of pin
 * vertices against it. Used by scene.c once the JSON has been validated. */
#ifndef WEFT_CLI_SCENE_MESH_H
#define WEFT_CLI_SCENE_MESH_H
#include <stddef.h>

#include "cli.h"
#include "scene_types.h"

/* Make s->mesh from s's mesh fields (file or grid) and apply s->transform. Errors are prefixed
 * "NAME: mesh.file: " (the reader's status) or "NAME: mesh.grid: ". */
weft_status scene_mesh_make(scene* s, const char* name, cli_diag* diag);

/* Check every pins[i].vertices index against s->mesh (in range, used by a polygon) and fill the
 * vertex lists of pins[i].select (SCENE errors naming the field). */
weft_status scene_mesh_check_pins(scene* s, const char* name, cli_diag* diag);

/* An nx x nz vertex quad grid in the XZ plane at y = 0, centred on the origin, sx x sz metres:
 * vertex i + nx j at (-sx/2 + sx i/(nx-1), 0, -sz/2 + sz j/(nz-1)); quad (i, j) has corners
 * (i,j), (i,j+1), (i+1,j+1), (i+1,j) in that order (normal +Y); quads in the same i-fastest order. */
weft_status scene_make_grid(scene_mesh* out, int nx, int nz, double sx, double sz, cli_diag* diag);

/* The file's mesh through weft_mesh_read (a CPU context of its own for the call): scale metres
 * per file unit, select a node or mesh name (NULL: all). On failure *out is zeroed and diag holds
 * the library's message. */
weft_status scene_mesh_read(scene_mesh* out, const char* path, const char* select, double scale, cli_diag* diag);

/* The mesh from polygon lists (n_faces sizes, their corners in indices), copied; positions in
 * metres. OUT_OF_MEMORY only. */
weft_status scene_mesh_from_arrays(scene_mesh* out, const double* positions, int n_vertices, const int* face_sizes,
                                   int n_faces, const int* indices, cli_diag* diag);
void scene_mesh_free(scene_mesh* m);

/* p <- T p (T 4x4 column-major, affine) for n points (n x 3). */
void scene_transform_points(const double t[16], double* pos, int n);

#endif
