/* The solver's passes as compute shaders (GL 4.3), from the same fragment-shader sources: on a
 * compute part a fragment pass reaches a small share of the bandwidth a compute shader does, and
 * the solver's step runs faster with these passes (docs/bench/gpu_h100.md). The default on every
 * GL 4.3 context; WEFT_GPU_PASSES=fragment keeps the fragment passes (wg_device.h).
 *
 * The transformation (wg_compute_source): the #version line becomes 430 with a 64 x 1 work
 * group; gl_FragCoord becomes a global the generated main() sets from the invocation's texel;
 * the `out` declarations (o0..o7) become globals, zeroed before the pass's own main (renamed
 * wg_main) runs and then stored with imageStore into the images bound at units 0..7. A run
 * (wg_runner.h) dispatches one invocation per texel of the output (the fragment path's viewport)
 * and puts a memory barrier after it, so the next pass's texelFetch sees the writes. */
#ifndef WEFT_GPU_SOLVER_COMPUTE_H
#define WEFT_GPU_SOLVER_COMPUTE_H

#include "egl_context.h"
#include "gl_program.h"
#include "gl_texture.h"

/* The compute source of a composed pass source (common.glsl + body); an allocation of gl's (free
 * with wg_gl_free), or NULL when out of memory or when the source has no #version line. */
char* wg_compute_source(wg_gl_context* gl, const char* frag);
/* A native compute shader's source (a body written as a compute shader, like reduce_groups.glsl
 * or spmv_groups.glsl): #version 430, then common.glsl without its #version line (its
 * gl_FragCoord a dummy global), then the body without its own #version line. An allocation of
 * gl's, or NULL when out of memory. */
char* wg_compute_native_source(wg_gl_context* gl, const char* common, const char* body);
/* Run program p (in use, its inputs and own uniforms set) over the w x h texels at (x0, 0): the
 * outputs as images 0..n_out-1, then the barrier for whatever reads them next (texelFetch,
 * read-backs, copies). */
void wg_compute_dispatch(wg_program* p, const wg_tex* const* out, int n_out, int x0, int w, int h);
/* Run a native compute program in use (reduce_groups.glsl, spmv_groups.glsl, ...) as `groups`
 * work groups (in rows of max_x past max_x of them: the shader counts groups linearly), the
 * outputs as images 0..n_out-1, then the same barrier. */
void wg_compute_dispatch_groups(const wg_tex* const* out, int n_out, int groups, int max_x);
/* The same with scratch bound read-write as image n_out after the outputs (a program that
 * reads back what it wrote). */
void wg_compute_dispatch_groups_scratch(const wg_tex* const* out, int n_out, const wg_tex* scratch, int groups,
                                        int max_x);
/* The same with img (RGBA32F) bound read-write as image 0, for a program that updates texels in
 * place. */
void wg_compute_dispatch_groups_rw(const wg_tex* img, int groups, int max_x);
/* Run a native compute program in use as one work group that reads and writes img in place
 * (image 0, bound read-write as RGBA32F), then a barrier for texture fetches and image access. */
void wg_compute_dispatch_in_place(const wg_tex* img);

#endif
