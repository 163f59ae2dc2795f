/* The host's GL buffer objects, in WEFT_GL_HOST_CURRENT mode (names of the host's context,
 * current at the call): a name's check (a buffer object holding the bytes asked for), and a
 * deforming body's vertices read from one into the cloth's memory (wg_sim_read_host_vertices,
 * wg_sim.h). Calls are made inside wg_gl_begin/end; the host's buffer bindings are left as they
 * were. */
#ifndef WEFT_GPU_SOLVER_HOST_BUFFER_H
#define WEFT_GPU_SOLVER_HOST_BUFFER_H

#include <stddef.h>

#include "diag.h"

/* `name` is a buffer object of the current context holding `need` bytes from `offset`;
 * INVALID_ARGUMENT naming `what` (and `layout`, what the bytes hold) otherwise. */
wc_status wg_host_buffer_check(unsigned name, size_t offset, size_t need, const char* what, const char* layout,
                               wc_diag* d);

#endif
