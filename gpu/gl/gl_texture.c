/* Textures as arrays (see gl_texture.h). */
#include "gl_texture.h"

#include <string.h>

#include "gpu_error.h"

int wg_tex_components(GLenum internal, int* is_int) {
    int i = 0, c = 4;
    switch (internal) {
    case GL_R32F: c = 1; break;
    case GL_RG32F: c = 2; break;
    case GL_RGBA32F: c = 4; break;
    case GL_R32I: c = 1; i = 1; break;
    case GL_RG32I: c = 2; i = 1; break;
    case GL_RGBA32I: c = 4; i = 1; break;
    default: break;
    }
    if (is_int) *is_int = i;
    return c;
}

void wg_tex_client_format(GLenum internal, GLenum* format, GLenum* type) {
    int is_int = 0, c = wg_tex_components(internal, &is_int);
    static const GLenum ffmt[5] = {0, GL_RED, GL_RG, GL_RGB, GL_RGBA};
    static const GLenum ifmt[5] = {0, GL_RED_INTEGER, GL_RG_INTEGER, GL_RGB_INTEGER, GL_RGBA_INTEGER};
    *format = is_int ? ifmt[c] : ffmt[c];
    *type = is_int ? GL_INT : GL_FLOAT;
}

size_t wg_tex_bytes(const wg_tex* t) {
    return (size_t)t->w * (size_t)t->h * 4u * (size_t)wg_tex_components(t->internal, NULL);
}

/* Zeros into a new texture, on the GPU (a framebuffer clear: no upload). A texture's first
 * contents are undefined: Mesa gives zeros, NVIDIA's driver what its memory held before (on an
 * H100: non-finite values, since 0 times them broke PCG's start), and a pass that multiplies an
 * unwritten texel by 0 then makes NaN. Clears follow the scissor test and the colour mask: gl_state's known state has
 * the one off and the other open. */
static void clear_zero(GLuint id, GLenum internal) {
    int is_int = 0;
    wg_tex_components(internal, &is_int);
    GLint prev = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev);
    GLuint fb = 0;
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb);
    glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, id, 0);
    const GLenum att = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &att);
    if (glCheckFramebufferStatus(GL_DRAW_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE) {
        const GLint zi[4] = {0, 0, 0, 0};
        const GLfloat zf[4] = {0.0f, 0.0f, 0.0f, 0.0f};
        if (is_int) glClearBufferiv(GL_COLOR, 0, zi);
        else glClearBufferfv(GL_COLOR, 0, zf);
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev);
    glDeleteFramebuffers(1, &fb);
}

int wg_tex_create(wg_tex* t, GLenum internal, int w, int h, const void* data, char* err, size_t err_len) {
    memset(t, 0, sizeof *t);
    if (w < 1) w = 1;
    if (h < 1) h = 1;
    GLenum format, type;
    wg_tex_client_format(internal, &format, &type);
    GLint prev = 0, prev_unpack = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &prev_unpack);
    glGenTextures(1, &t->id);
    glBindTexture(GL_TEXTURE_2D, t->id);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, w, h, 0, format, type, NULL);
    GLenum e = glGetError();
    if (e == GL_NO_ERROR) {
        if (data) glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, format, type, data);
        else clear_zero(t->id, internal);
        e = glGetError();
    }
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev);
    glPixelStorei(GL_UNPACK_ALIGNMENT, prev_unpack);
    if (e != GL_NO_ERROR) {
        wg_errorf(err, err_len, "texture %d x %d (internal format 0x%04x): %s", w, h, (unsigned)internal,
                  wg_gl_error_name(e));
        glDeleteTextures(1, &t->id);
        memset(t, 0, sizeof *t);
        return 0;
    }
    t->w = w;
    t->h = h;
    t->internal = internal;
    return 1;
}

void wg_tex_upload(const wg_tex* t, int x, int y, int w, int h, const void* data) {
    GLenum format, type;
    wg_tex_client_format(t->internal, &format, &type);
    GLint prev = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev);
    glBindTexture(GL_TEXTURE_2D, t->id);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, x, y, w, h, format, type, data);
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev);
}

void wg_tex_destroy(wg_tex* t) {
    if (t->id) glDeleteTextures(1, &t->id);
    memset(t, 0, sizeof *t);
}
