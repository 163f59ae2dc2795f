/* The mesh of a scene: imported from a file or generated as a grid, then transformed; and the
 * checks of pin vertices against it. Used by scene.c once the JSON has been validated. */
#ifndef WEFT_CLI_SCENE_MESH_H
#define WEFT_CLI_SCENE_MESH_H
#include "scene.h"

/* Make s->src from s's mesh fields (file or grid) and apply s->transform. Errors are prefixed
 * "NAME: mesh.file: " (the importer's status) or "NAME: mesh.grid: ". */
weft_status scene_mesh_make(scene* s, const char* name, cli_diag* diag);

/* Check every pins[i].vertices index against s->src (in range, used by a polygon) and fill the
 * vertex lists of pins[i].select (SCENE errors naming the field). */
weft_status scene_mesh_check_pins(scene* s, const char* name, cli_diag* diag);

/* An nx x nz vertex quad grid in the XZ plane at y = 0, centred on the origin, sx x sz metres:
 * vertex i + nx j at (-sx/2 + sx i/(nx-1), 0, -sz/2 + sz j/(nz-1)); quad (i, j) has corners
 * (i,j), (i,j+1), (i+1,j+1), (i+1,j) in that order (normal +Y); quads in the same i-fastest order. */
weft_status scene_make_grid(wc_source_mesh* out, int nx, int nz, double sx, double sz, cli_diag* diag);

/* p <- T p (T 4x4 column-major, affine) for n points (n x 3). */
void scene_transform_points(const double t[16], double* pos, int n);

#endif
