/* Running one cloth's passes. A pass is a program of the device (wg_device.h) put in use with
 * its inputs (WG_USE: the pass's input struct, wg_passes.h), then its uniforms set by name, then
 * run over its output arrays: a draw into a cached framebuffer (fragment passes,
 * wg_fbo_cache.h) or a dispatch writing images (compute passes, wg_compute.h), one fragment or
 * invocation per texel; every run is counted. The runner knows the device and the cloth's
 * layout, nothing else of the cloth. Calls are made with the cloth's GL context current.
 *
 * A call site that breaks a pass's contract (an input struct of another size, an input left
 * NULL) is a bug: the runner binds no texture there and keeps the first such fault's message in
 * `fault`, which the frame reports as a GPU error (wg_sim_step_frame). */
#ifndef WEFT_GPU_SOLVER_RUNNER_H
#define WEFT_GPU_SOLVER_RUNNER_H

#include "wg_device.h"
#include "wg_fbo_cache.h"
#include "wg_layout.h"

typedef struct wg_runner {
    wg_device* dev;
    const wg_layout* layout;
    wg_fbo_cache fbo;
    wg_program* prog;           /* the program in use */
    long long passes;           /* passes run since init */
    char fault[128];            /* the first broken pass contract ("" when none) */
} wg_runner;

void wg_runner_init(wg_runner* r, wg_device* dev, const wg_layout* layout);
void wg_runner_destroy(wg_runner* r);

/* Put pass p in use with its inputs: in points at p's input struct (size in_size), each field
 * of p's table bound to its texture unit. */
void wg_use_pass(wg_runner* r, wg_pass_id p, const void* in, size_t in_size);
#define WG_USE(r, p, ...) wg_use_pass((r), (p), (__VA_ARGS__), sizeof *(__VA_ARGS__))
/* Scalar uniforms of the program in use, by name (a string literal: gl_program.h caches the
 * location per program); doubles are set as floats. */
void wg_u1i(wg_runner* r, const char* name, int v);
void wg_u1f(wg_runner* r, const char* name, double v);
void wg_u2f(wg_runner* r, const char* name, double a, double b);
void wg_u3f(wg_runner* r, const char* name, const double* v);
void wg_u4f(wg_runner* r, const char* name, const double* v);
void wg_u2i(wg_runner* r, const char* name, int a, int b);
void wg_u4i(wg_runner* r, const char* name, int a, int b, int c, int d);
void wg_umat3(wg_runner* r, const char* name, const double* row_major);

/* Run the program in use into the outputs (all of one size), one fragment or invocation per
 * texel; count = items of the output array (u_n). */
void wg_run(wg_runner* r, int count, const wg_tex* const* out, int n_out);
#define WG_RUN(r, count, ...) \
    wg_run((r), (count), (const wg_tex* const[]){__VA_ARGS__}, \
           (int)(sizeof((const wg_tex* const[]){__VA_ARGS__}) / sizeof(const wg_tex*)))
/* Run the program in use into texel (x, 0) of out only. */
void wg_run_texel(wg_runner* r, const wg_tex* out, int x);
/* Compute passes only: dispatch the native compute program in use (*_groups.glsl) as `groups`
 * work groups writing out (image 0); count = items (u_n). */
void wg_run_groups(wg_runner* r, int count, const wg_tex* out, int groups);
/* The same with outputs out[0..n_out-1] as images 0..n_out-1 (WG_RUN_GROUPS lists them). */
void wg_run_groups_into(wg_runner* r, int count, int groups, const wg_tex* const* out, int n_out);
#define WG_RUN_GROUPS(r, count, groups, ...) \
    wg_run_groups_into((r), (count), (groups), (const wg_tex* const[]){__VA_ARGS__}, \
                       (int)(sizeof((const wg_tex* const[]){__VA_ARGS__}) / sizeof(const wg_tex*)))
/* The same with scratch bound read-write as image n_out after the outputs. */
void wg_run_groups_scratch(wg_runner* r, int count, int groups, const wg_tex* const* out, int n_out,
                           const wg_tex* scratch);
/* Compute passes only: `groups` work groups of the native compute program in use, updating img
 * (RGBA32F, image 0) in place; count = items (u_n). */
void wg_run_groups_rw(wg_runner* r, int count, int groups, const wg_tex* img);
/* A tree's bottom-up sweep with the program in use (64 invocations a group): one wg_run_groups_rw
 * over img per height, height k's items [first[k], first[k + 1]) passed as u_first and u_count
 * (n_heights + 1 entries; an empty height takes no pass). */
void wg_run_by_height(wg_runner* r, const int* first, int n_heights, const wg_tex* img);
/* Compute passes only: one work group of the native compute program in use, reading and writing
 * img in place (image 0, RGBA32F); count = items (u_n). */
void wg_run_in_place(wg_runner* r, int count, const wg_tex* img);
/* dst = src (same size), a copy pass. */
void wg_copy(wg_runner* r, const wg_tex* dst, const wg_tex* src);

#endif
