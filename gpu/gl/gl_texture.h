/* Float and integer textures used as arrays by the compute passes, and the framebuffers they are
 * rendered into. Every texture has NEAREST filters and no mipmaps (a texture left on the default
 * mipmapped filter is incomplete and texelFetch returns zeros: ../shared/notes/platform.md).
 * Needs a current context with GLEW initialised. */
#ifndef WEFT_GPU_GL_TEXTURE_H
#define WEFT_GPU_GL_TEXTURE_H

#include <stddef.h>
#include <GL/glew.h>

typedef struct wg_tex {
    GLuint id;
    int w, h;
    GLenum internal;            /* GL_RGBA32F, GL_RG32F, GL_R32F, GL_RGBA32I, GL_R32I, ... */
} wg_tex;

/* Create a w x h texture of the internal format, filled from data (rows of w texels in the
 * format's natural client layout: float or int components), or with zeros where data is NULL
 * (GL leaves a new texture's contents undefined: gl_texture.c).
 * Returns 1, or 0 with the GL error in err. */
int wg_tex_create(wg_tex* t, GLenum internal, int w, int h, const void* data, char* err, size_t err_len);
/* Replace a rectangle (same client layout as wg_tex_create). */
void wg_tex_upload(const wg_tex* t, int x, int y, int w, int h, const void* data);
void wg_tex_destroy(wg_tex* t);
/* Components per texel (1..4) and whether the format is an integer one. */
int wg_tex_components(GLenum internal, int* is_int);
/* Client format/type for uploads and read-backs of the internal format. */
void wg_tex_client_format(GLenum internal, GLenum* format, GLenum* type);
/* Bytes of GPU memory the texture holds. */
size_t wg_tex_bytes(const wg_tex* t);

#endif
