/* The solver's per-GL-context objects: every pass program (wg_passes.h; compiled once per context
 * from gpu/solver/shaders, its inputs checked against the pass's table, and shared by the
 * context's cloths), the empty vertex array the full-screen triangle needs, and what the device
 * can do (texture size, float render targets, timer queries). Created and used inside
 * wg_gl_begin/wg_gl_end. */
#ifndef WEFT_GPU_SOLVER_DEVICE_H
#define WEFT_GPU_SOLVER_DEVICE_H

#include "egl_context.h"
#include "gl_program.h"
#include "status.h"
#include "wg_passes.h"

/* How PCG runs on compute passes (wg_solve.c), with block Jacobi or the multigrid: the whole
 * solve in one work group (pcg_group.glsl; pcg_group_amg.glsl after the multigrid's setup passes,
 * only where WEFT_GPU_SOLVE=group asks for it) for a cloth of at most WG_GROUP_MAX_PARTICLES
 * particles on a hardware device, the multi-pass chain above that and on software rasterisers;
 * WEFT_GPU_SOLVE=group or =passes forces one. */
typedef enum wg_solve_mode { WG_SOLVE_AUTO = 0, WG_SOLVE_GROUP, WG_SOLVE_PASSES } wg_solve_mode;
/* The most particles the one-group solve takes: its shared memory holds one vector of them
 * (3 floats each, within the 32 KiB every GL 4.3 device has), its 1,024 invocations 3 rows each. */
#define WG_GROUP_MAX_PARTICLES 2560

typedef struct wg_device {
    wg_gl_context* gl;
    wg_program prog[WGP_COUNT];
    GLuint vao;
    int max_texture_size;
    int max_draw_buffers;
    int software;               /* 1 on a software rasteriser (llvmpipe, softpipe, swrast) */
    int has_timer;              /* GL_TIMESTAMP queries work */
    int compute;                /* the passes are compute shaders (wg_compute.h), not fragment shaders */
    wg_solve_mode solve;        /* WEFT_GPU_SOLVE's choice (compute passes) */
    int amg_cross;              /* WEFT_GPU_AMG_CROSS=1: the penalty pairs' cross terms in the
                                   multigrid's levels (opt-in: fewer iterations, but where layers
                                   touch only here and there, as on the suit, their blocks cost
                                   about what they save on llvmpipe, docs/bench/gpu_amg_cross.md) */
    int amg_smooth;             /* WEFT_GPU_AMG_SMOOTH: the multigrid's prolongator smoothed (1, the
                                   default: WG_AMG_SMOOTHED) or P = P_tent (0) (wg_amg.smoothed) */
    int amg_rot;                /* WEFT_GPU_AMG_ROT: the multigrid's near-null space with the
                                   smoothed prolongator: rotations (1, the default: WG_AMG_ROTATIONS)
                                   or translations (0) (wg_amg.rotations) */
    int amg_current;            /* WEFT_GPU_AMG_CURRENT: the rotations about the current positions
                                   (1) or the rest positions (0, the default: WG_AMG_CURRENT)
                                   (wg_amg.current) */
    int amg_fuse;               /* WEFT_GPU_AMG_FUSE: the V-cycle's fused passes (1, the default)
                                   or a pass a step (0; the same arithmetic) (wg_amg.fuse) */
    int body_host;              /* WEFT_GPU_BODY: a mesh collider given by the host's arrays or a rigid
                                   transform moved to each substep on the device (0: "device", the
                                   default, compute passes; wg_mesh_host.c) or by core on the host
                                   (1: "host"); -1: another value (logged at a cloth's creation; the
                                   default then) */
    int max_groups_x;           /* compute: work groups along x a dispatch may have (65535 at least;
                                   wg_compute_dispatch_groups goes 2D past it; tests lower it) */
    char renderer[128];
} wg_device;

/* Compile every program and check that RGBA32F textures can be rendered into and read back
 * exactly (a context lacking float render targets is refused: WC_ERROR_GPU naming what is
 * missing). Inside wg_gl_begin. The passes are compute shaders made from the same sources
 * (wg_compute.h) where the context has GL 4.3, fragment shaders rendering into FBOs elsewhere;
 * the environment's WEFT_GPU_PASSES=fragment or =compute picks one. Any other value, or compute
 * on a context without GL 4.3, is WC_ERROR_GPU with a message, as is a pass whose shader's
 * samplers are not its table's (the message names the pass and the sampler). WEFT_GPU_SOLVE
 * (wg_solve_mode) is read here too: "group", "passes" or unset/empty; any other value, or group
 * on fragment passes, is WC_ERROR_GPU with a message naming it. */
wc_status wg_device_create(wg_gl_context* gl, wg_device** out, char* err, size_t err_len);
/* Inside wg_gl_begin (or with the context current). NULL is ignored. */
void wg_device_destroy(wg_device* d);
/* Free the memory only (no GL call): the context is gone or cannot be made current. */
void wg_device_forget(wg_device* d);

/* 1 when the renderer string names a software rasteriser. */
int wg_renderer_is_software(const char* renderer);

#endif
