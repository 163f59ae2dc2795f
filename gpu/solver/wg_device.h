/* The solver's per-GL-context objects: every pass program (gpu/solver/shaders, compiled once per
 * context and shared by its cloths), the empty vertex array the full-screen triangle needs, and
 * what the device can do (texture size, float render targets, timer queries). Created and used
 * inside wg_gl_begin/wg_gl_end. */
#ifndef WEFT_GPU_SOLVER_DEVICE_H
#define WEFT_GPU_SOLVER_DEVICE_H

#include "egl_context.h"
#include "gl_program.h"

typedef enum wg_pass_id {
    WGP_SPRINGS, WGP_AIR, WGP_ASSEMBLE_B, WGP_ASSEMBLE_A, WGP_PINS, WGP_DINV, WGP_PROJECT, WGP_RESIDUAL,
    WGP_SPMV, WGP_PCG_UPDATE, WGP_PCG_DIRECTION, WGP_PCG_SCALARS, WGP_JACOBI_SWEEP, WGP_INTEGRATE,
    WGP_CHECK_PARTICLES, WGP_CHECK_SPRINGS, WGP_REDUCE, WGP_COPY, WGP_STRAIN_SPRINGS, WGP_STRAIN_GATHER,
    WGP_NORMALS, WGP_HOST_OUTPUT, WGP_LANCZOS_START, WGP_TRANSFORM, WGP_COPY_TEXEL,
    WGP_CONTACT_BEGIN, WGP_CONTACT_FRICTION, WGP_CONTACT_RECHECK, WGP_CONTACT_END, WGP_CONTACT_PROJECT,
    WGP_CONTACT_DIAG,
    WGP_REDUCE_GROUPS, WGP_SPMV_GROUPS,   /* compute passes only: native compute shaders (*_groups.glsl) */
    /* the multigrid preconditioner (wg_amg.h), compute passes only; *_GROUPS native; each *_FINE
       its pass over the finest level (amg_level_inputs.glsl's WG_AMG_FINE form) */
    WGP_AMG_GALERKIN, WGP_AMG_DINV, WGP_AMG_POWER, WGP_AMG_SMOOTH, WGP_AMG_RESTRICT, WGP_AMG_DOT,
    WGP_AMG_FACTOR_GROUPS, WGP_AMG_COARSE_GROUPS,
    WGP_AMG_GALERKIN_FINE, WGP_AMG_DINV_FINE, WGP_AMG_POWER_FINE, WGP_AMG_SMOOTH_FINE, WGP_AMG_RESTRICT_FINE,
    WGP_AMG_FACTOR_GROUPS_FINE,
    WGP_COUNT
} wg_pass_id;

typedef struct wg_device {
    wg_gl_context* gl;
    wg_program prog[WGP_COUNT];
    GLuint vao;
    int max_texture_size;
    int max_draw_buffers;
    int software;               /* 1 on a software rasteriser (llvmpipe, softpipe, swrast) */
    int has_timer;              /* GL_TIMESTAMP queries work */
    int compute;                /* the passes are compute shaders (wg_compute.h), not fragment shaders */
    int max_groups_x;           /* compute: work groups along x a dispatch may have (65535 at least;
                                   wg_compute_dispatch_groups goes 2D past it; tests lower it) */
    char renderer[128];
} wg_device;

/* Compile every program and check that RGBA32F textures can be rendered into and read back
 * exactly (a context lacking float render targets is refused: WC_ERROR_GPU naming what is
 * missing). Inside wg_gl_begin. The passes are compute shaders made from the same sources
 * (wg_compute.h) where the context has GL 4.3, fragment shaders rendering into FBOs elsewhere;
 * the environment's WEFT_GPU_PASSES=fragment or =compute picks one. Any other value, or compute
 * on a context without GL 4.3, is WC_ERROR_GPU with a message. */
wc_status wg_device_create(wg_gl_context* gl, wg_device** out, char* err, size_t err_len);
/* Inside wg_gl_begin (or with the context current). NULL is ignored. */
void wg_device_destroy(wg_device* d);
/* Free the memory only (no GL call): the context is gone or cannot be made current. */
void wg_device_forget(wg_device* d);

/* 1 when the renderer string names a software rasteriser. */
int wg_renderer_is_software(const char* renderer);

#endif
