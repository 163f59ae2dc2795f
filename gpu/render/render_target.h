/* The renderer's framebuffers (gpu/ internal): a multisampled RGBA8 + depth24 framebuffer
 * resolved into a single-sampled RGBA8 one, or (1 sample) the single-sampled one with depth. */
#ifndef WEFT_GPU_RENDER_TARGET_H
#define WEFT_GPU_RENDER_TARGET_H

#include <GL/glew.h>
#include <stddef.h>

#include "status.h"

typedef struct wg_target {
    int width, height, samples;   /* 0 x 0 before the first wg_target_ensure */
    GLuint ms_fbo, ms_color, ms_depth;   /* samples > 1 */
    GLuint fbo, color, depth;            /* depth only when samples == 1 */
} wg_target;

/* (Re)allocate for this size and sample count unless it already matches. On failure everything
 * is deleted and err names the incomplete status or GL error. */
wc_status wg_target_ensure(wg_target* t, int width, int height, int samples, char* err,
                             size_t err_len);
void wg_target_destroy(wg_target* t);
/* Framebuffer to draw into. */
GLuint wg_target_draw_fbo(const wg_target* t);
/* Resolve the samples into the single-sampled framebuffer and leave it bound for reading. */
void wg_target_resolve(const wg_target* t);

#endif
