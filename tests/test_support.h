/* Helpers shared by the test programs: generated meshes and scratch files. */
#ifndef WEFT_TESTS_SUPPORT_H
#define WEFT_TESTS_SUPPORT_H
#include "model.h"
#include "state.h"
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
/* Running the built `weft` tool (WEFT_CLI) as a user would. */
typedef struct ts_cli_result {
    int rc;            /* exit status, -1 when the tool did not exit normally */
    char out[65536];   /* stdout */
    char err[8192];    /* stderr */
} ts_cli_result;
/* Run `WEFT_CLI args` (args is shell text), capturing stdout and stderr. */
void ts_run_cli(const char* args, ts_cli_result* r);
/* Read a whole text file into buf (truncated to cap - 1; "" when it cannot be opened). */
void ts_read_text(const char* path, char* buf, size_t cap);
/* Number of '\n' in s. */
int ts_count_lines(const char* s);

/* An n x n quad-grid sheet of size x size metres, horizontal (XZ plane) at height y when
 * vertical is 0, else hanging in the XY plane with its top edge at height y. Material: defaults
 * with every k and d multiplied by k_scale. Host vertex (i, j) is i + n j (i along X). Returns
 * 1 on success. */
int ts_sheet(wc_model* m, int n, double size, double y, int vertical, double k_scale);
/* Particle of host grid vertex (i, j) of a ts_sheet. */
int ts_sheet_particle(const wc_model* m, int n, int i, int j);
/* Pin the two corners of a ts_sheet's row j = n - 1 (host vertices (0, n-1) and (n-1, n-1)) at
 * their current positions moved by `move` (metres; NULL: where they are), the hanging sheets' two
 * pins. Returns wc_state_set_pins' status. */
wc_status ts_pin_far_corners(wc_state* s, int n, const double* move);
/* |a - b| / |b| over n doubles (|a - b| when b is zero). */
double ts_rel_diff(const double* a, const double* b, int n);
/* An n x n ts_sheet (1 m) dropped from 0.47 m onto a sphere (radius 0.45 at the origin,
 * thickness 0.005, friction 0.3) and draped over it for `frames` frames on the CPU with def: a
 * system with contacts and friction. NULL on failure (m is then not built or freed). */
wc_state* ts_draped(wc_model* m, int n, const wc_sim_def* def, int frames);
/* `count` separate 3 x 3-vertex patches, 0.1 m apart, each hanging from a corner, stepped 3
 * frames on the CPU with def: a mesh whose multigrid coarsening stops at one aggregate a piece.
 * NULL on failure. */
wc_state* ts_patches(wc_model* m, int count, const wc_sim_def* def);
/* The defaults with PCG and the multigrid preconditioner, sleeping off: the GPU multigrid tests'
 * definition (both backends step it). */
wc_sim_def ts_amg_def(void);
/* An n x n ts_sheet (1 m, material x k_scale) hanging from its two far corners under ts_amg_def,
 * stepped `warm` frames on the CPU, its positions and velocities rounded to float: the same input
 * for a GPU test and core. NULL on failure. */
wc_state* ts_hanging_float(wc_model* m, int n, int warm, double k_scale);
/* An n x n vertical sheet (6 m in the XY plane, top at y = 6, host vertex (i, j) = i + n j as
 * ts_sheet's) hanging from its two far corners, and `pieces` separate single-quad pieces in the
 * plane z = 4e5 m at x = 4e5 m, 0.5 m apart in Y, welding off: the even ones 0.3 m squares, the
 * odd ones slivers (6 m along X, 0.3 m along Y). About the rotations' centre (the centroid of all
 * the rest positions, the sheet's, some 5.7e5 m away) the squares' three rotations are their
 * translations to within 1e-6 (as a 1-node aggregate's: all three dead), the slivers' rotation
 * about their line too (as a 2-node or collinear aggregate's: one dead); the sheet's quads are
 * far from the degenerate area (1e-14 x the bounding box's diagonal^2), and the pieces as well
 * conditioned as the sheet (smaller ones are not: float's floor). Stepped `warm` frames under
 * ts_amg_def; not rounded to float (the tests set the system, computed in double, on the GPU).
 * NULL on failure. */
wc_state* ts_dead_pieces(wc_model* m, int n, int pieces, int warm);
/* max |a_k| and max |a_k - b_k| over n doubles. */
double ts_max_abs(const double* a, int n);
double ts_max_diff(const double* a, const double* b, int n);

#endif
