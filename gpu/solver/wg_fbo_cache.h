/* The framebuffers a cloth's fragment passes render into: one per set of colour attachments,
 * made at the first pass that writes that set and kept (the textures are the cloth's own, so no
 * entry outlives them); past WG_FBO_CACHE sets, one spare framebuffer is re-attached each time.
 * Calls are made with the cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_FBO_CACHE_H
#define WEFT_GPU_SOLVER_FBO_CACHE_H

#include "gl_texture.h"

#define WG_FBO_CACHE 96
#define WG_MAX_OUT 8            /* a pass's outputs at most (draw buffers, or images) */

typedef struct wg_fbo_entry {
    GLuint fbo;
    int n;
    GLuint tex[WG_MAX_OUT];
} wg_fbo_entry;

typedef struct wg_fbo_cache {
    wg_fbo_entry e[WG_FBO_CACHE];
    int n;
    GLuint spare;
} wg_fbo_cache;

/* Bind (GL_DRAW_FRAMEBUFFER) a framebuffer whose colour attachments 0..n_out-1 are out, with
 * those draw buffers on. */
void wg_fbo_bind(wg_fbo_cache* c, const wg_tex* const* out, int n_out);
/* Delete every framebuffer (the context current). */
void wg_fbo_cache_destroy(wg_fbo_cache* c);

#endif
