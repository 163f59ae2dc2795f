/* The GL state gpu/ touches: saved before rendering inside a host's context, restored after, and
 * set to gpu/'s own known values before drawing (in either mode). Needs a current context with
 * GLEW initialised. */
#ifndef WEFT_GPU_GL_STATE_H
#define WEFT_GPU_GL_STATE_H

#include <GL/glew.h>

#define WG_GL_STATE_MAX_ENABLES 28
#define WG_GL_STATE_TEXTURE_UNITS 16   /* the units gpu/'s programs sample (t0..t15) */
#define WG_GL_STATE_IMAGE_UNITS 8      /* the image units compute passes write (images 0..7) */

typedef struct wg_gl_image_binding {
    GLint name, level, layer, access, format;
    GLboolean layered;
} wg_gl_image_binding;

typedef struct wg_gl_saved_state {
    GLint draw_fbo, read_fbo, renderbuffer, program, vao, array_buffer, pack_buffer;
    GLint pack_alignment, pack_row_length, pack_skip_rows, pack_skip_pixels;
    GLint unpack_buffer, unpack_alignment, unpack_row_length, unpack_skip_rows, unpack_skip_pixels;
    GLint active_texture;
    GLint texture_2d[WG_GL_STATE_TEXTURE_UNITS];   /* 2D texture bound on units 0..15 */
    int has_images;                                /* GL 4.2: image units saved */
    wg_gl_image_binding image[WG_GL_STATE_IMAGE_UNITS];
    GLint viewport[4];
    GLfloat clear_color[4];
    GLfloat clear_depth;
    GLboolean depth_mask;
    GLboolean color_mask[4];
    GLint depth_func, front_face;
    GLint polygon_mode[2];
    int n_enables;
    GLenum enable_caps[WG_GL_STATE_MAX_ENABLES];
    GLboolean enabled[WG_GL_STATE_MAX_ENABLES];
} wg_gl_saved_state;

void wg_gl_state_save(wg_gl_saved_state* s);
void wg_gl_state_restore(const wg_gl_saved_state* s);

/* Every capability in the saved list disabled except GL_DEPTH_TEST (GL_LESS, mask on) and, when
 * multisample is nonzero, GL_MULTISAMPLE; colour mask all on; CCW front faces; filled polygons;
 * pixel-pack and pixel-unpack buffers 0 with alignment 4 and no row length or skips. */
void wg_gl_state_set_defaults(int multisample);

#endif
