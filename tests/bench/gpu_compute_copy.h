/* For bench_gpu: the same copy of an n-particle array as the solver's fragment-shader copy pass,
 * done by a compute shader (GL 4.3), so that the two ways of running a pass on one device can be
 * set side by side. Needs a current context with GLEW initialised. */
#ifndef WEFT_BENCH_GPU_COMPUTE_COPY_H
#define WEFT_BENCH_GPU_COMPUTE_COPY_H

/* Mean ms of one copy over `reps` dispatches (after one warm-up): *ms_tex for RGBA32F texture
 * -> image (the solver's layout: 1024 texels a row), *ms_buf for a shader storage buffer ->
 * buffer of n vec4. Returns 1, or 0 where the context has no compute shaders (both set to -1). */
int gpu_compute_copy(int n, int reps, double* ms_tex, double* ms_buf);

#endif
