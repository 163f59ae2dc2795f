/* The GPU backend of a cloth (core/cloth_backend.h) over wg_sim: the device is a GL context
 * (headless EGL or the host's current one) with its wg_device, shared by the context's cloths;
 * each cloth's particles live in its wg_sim's textures and the wc_state holds their mirror.
 * What the GPU lacks is refused at create, and told by `supports` before it (wg_sim_supports:
 * the direct solver, the multigrid on fragment passes). */
#ifndef WEFT_GPU_SOLVER_BACKEND_H
#define WEFT_GPU_SOLVER_BACKEND_H

#include "cloth_backend.h"
#include "egl_context.h"

extern const wc_cloth_backend wg_cloth_backend;

/* The GL context of a device made by wg_cloth_backend.device_create (others share it: the
 * preview renderer). */
wg_gl_context* wg_backend_gl_context(void* device);
/* Its GL renderer string, and whether that is a software rasteriser. */
const char* wg_backend_renderer(const void* device, int* software);

#endif
