/* The host's GL buffer objects, in WEFT_GL_HOST_CURRENT mode (names of the host's context,
 * current at the call): a name's check (a buffer object holding the bytes asked for), a deforming
 * body's vertices unpacked from one into a texture (for wg_mesh_body_take), or read from one into
 * the cloth's memory (wg_sim_read_host_vertices, wg_sim.h). Calls are made inside wg_gl_begin/end; the host's buffer bindings are left as they
 * were. */
#ifndef WEFT_GPU_SOLVER_HOST_BUFFER_H
#define WEFT_GPU_SOLVER_HOST_BUFFER_H

#include <stddef.h>

#include "diag.h"
#include "gl_texture.h"

/* `name` is a buffer object of the current context holding `need` bytes from `offset`;
 * INVALID_ARGUMENT naming `what` (and `layout`, what the bytes hold) otherwise. */
wc_status wg_host_buffer_check(unsigned name, size_t offset, size_t need, const char* what, const char* layout,
                               wc_diag* d);

/* `floats` floats of `buffer` from byte `offset` (a multiple of 4) into raw (GL_R32F, w wide: float
 * k at texel (k mod w, k div w); (re)made w x h when it is not at least that), by
 * glTexSubImage2D from the buffer bound as the pixel-unpack source: on the GPU, after the host's
 * commands that write it. INVALID_ARGUMENT when the host has the buffer mapped (not
 * persistently), GPU on a GL error; the unpack state is left as it was. */
wc_status wg_host_buffer_unpack(unsigned buffer, size_t offset, size_t floats, wg_tex* raw, int w, int h,
                                wc_diag* d);

#endif
