/* Helpers shared by the test programs: generated meshes and scratch files. */
#ifndef WEFT_TESTS_SUPPORT_H
#define WEFT_TESTS_SUPPORT_H
#include "source_mesh.h"

/* nx x ny vertices, quads, in the XY plane, spanning size_x x size_y metres. With split_uv each
 * quad has its own four vertices (as with per-quad UVs): 4 (nx-1)(ny-1) host vertices. */
void ts_quad_grid(wc_source_mesh* out, int nx, int ny, double size_x, double size_y, int split_uv);
/* Same grid, each cell cut into two triangles along (i,j)-(i+1,j+1), given as triangles. */
void ts_tri_grid(wc_source_mesh* out, int nx, int ny, double size_x, double size_y);
/* Write text to WEFT_TEST_TMPDIR/name; returns the full path in a static buffer per call slot. */
const char* ts_write_tmp(const char* name, const char* text);
/* Full path of a scratch file name in WEFT_TEST_TMPDIR (static buffer, 4 rotating slots). */
const char* ts_tmp_path(const char* name);

#endif
