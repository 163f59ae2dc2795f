/* Saving, restoring and setting the GL state gpu/ touches. */
#include "gl_state.h"

/* Capabilities that change what a draw, a blit or a read-back produces. Version-gated ones are
 * only listed when the context has them (querying an unknown cap is a GL error). */
static int list_caps(GLenum* caps) {
    int n = 0;
    caps[n++] = GL_DEPTH_TEST;
    caps[n++] = GL_CULL_FACE;
    caps[n++] = GL_BLEND;
    caps[n++] = GL_SCISSOR_TEST;
    caps[n++] = GL_STENCIL_TEST;
    caps[n++] = GL_MULTISAMPLE;
    caps[n++] = GL_FRAMEBUFFER_SRGB;
    caps[n++] = GL_POLYGON_OFFSET_FILL;
    caps[n++] = GL_RASTERIZER_DISCARD;
    caps[n++] = GL_SAMPLE_ALPHA_TO_COVERAGE;
    caps[n++] = GL_SAMPLE_COVERAGE;
    caps[n++] = GL_SAMPLE_MASK;
    caps[n++] = GL_PRIMITIVE_RESTART;
    caps[n++] = GL_DITHER;
    caps[n++] = GL_COLOR_LOGIC_OP;
    caps[n++] = GL_DEPTH_CLAMP;
    for (int i = 0; i < 8; ++i) caps[n++] = GL_CLIP_DISTANCE0 + (GLenum)i;
    if (GLEW_VERSION_4_0) caps[n++] = GL_SAMPLE_SHADING;
    if (GLEW_VERSION_4_3) caps[n++] = GL_PRIMITIVE_RESTART_FIXED_INDEX;
    return n; /* at most WG_GL_STATE_MAX_ENABLES */
}

void wg_gl_state_save(wg_gl_saved_state* s) {
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &s->draw_fbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &s->read_fbo);
    glGetIntegerv(GL_RENDERBUFFER_BINDING, &s->renderbuffer);
    glGetIntegerv(GL_CURRENT_PROGRAM, &s->program);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &s->vao);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &s->array_buffer);
    glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &s->pack_buffer);
    glGetIntegerv(GL_PACK_ALIGNMENT, &s->pack_alignment);
    glGetIntegerv(GL_PACK_ROW_LENGTH, &s->pack_row_length);
    glGetIntegerv(GL_PACK_SKIP_ROWS, &s->pack_skip_rows);
    glGetIntegerv(GL_PACK_SKIP_PIXELS, &s->pack_skip_pixels);
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &s->unpack_buffer);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &s->unpack_alignment);
    glGetIntegerv(GL_UNPACK_ROW_LENGTH, &s->unpack_row_length);
    glGetIntegerv(GL_UNPACK_SKIP_ROWS, &s->unpack_skip_rows);
    glGetIntegerv(GL_UNPACK_SKIP_PIXELS, &s->unpack_skip_pixels);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &s->active_texture);
    for (int u = 0; u < WG_GL_STATE_TEXTURE_UNITS; ++u) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &s->texture_2d[u]);
    }
    glActiveTexture((GLenum)s->active_texture);
    s->has_images = GLEW_VERSION_4_2 ? 1 : 0;
    for (int u = 0; s->has_images && u < WG_GL_STATE_IMAGE_UNITS; ++u) {
        wg_gl_image_binding* b = &s->image[u];
        glGetIntegeri_v(GL_IMAGE_BINDING_NAME, (GLuint)u, &b->name);
        glGetIntegeri_v(GL_IMAGE_BINDING_LEVEL, (GLuint)u, &b->level);
        glGetIntegeri_v(GL_IMAGE_BINDING_LAYER, (GLuint)u, &b->layer);
        glGetIntegeri_v(GL_IMAGE_BINDING_ACCESS, (GLuint)u, &b->access);
        glGetIntegeri_v(GL_IMAGE_BINDING_FORMAT, (GLuint)u, &b->format);
        glGetBooleani_v(GL_IMAGE_BINDING_LAYERED, (GLuint)u, &b->layered);
    }
    glGetIntegerv(GL_VIEWPORT, s->viewport);
    glGetFloatv(GL_COLOR_CLEAR_VALUE, s->clear_color);
    glGetFloatv(GL_DEPTH_CLEAR_VALUE, &s->clear_depth);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s->depth_mask);
    glGetBooleanv(GL_COLOR_WRITEMASK, s->color_mask);
    glGetIntegerv(GL_DEPTH_FUNC, &s->depth_func);
    glGetIntegerv(GL_FRONT_FACE, &s->front_face);
    s->polygon_mode[0] = s->polygon_mode[1] = GL_FILL;
    glGetIntegerv(GL_POLYGON_MODE, s->polygon_mode); /* core: one value, compatibility: two */
    s->n_enables = list_caps(s->enable_caps);
    for (int i = 0; i < s->n_enables; ++i) s->enabled[i] = glIsEnabled(s->enable_caps[i]);
}

static void set_cap(GLenum cap, GLboolean on) {
    if (on)
        glEnable(cap);
    else
        glDisable(cap);
}

void wg_gl_state_restore(const wg_gl_saved_state* s) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)s->draw_fbo);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)s->read_fbo);
    glBindRenderbuffer(GL_RENDERBUFFER, (GLuint)s->renderbuffer);
    glUseProgram((GLuint)s->program);
    glBindVertexArray((GLuint)s->vao);
    glBindBuffer(GL_ARRAY_BUFFER, (GLuint)s->array_buffer);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)s->pack_buffer);
    glPixelStorei(GL_PACK_ALIGNMENT, s->pack_alignment);
    glPixelStorei(GL_PACK_ROW_LENGTH, s->pack_row_length);
    glPixelStorei(GL_PACK_SKIP_ROWS, s->pack_skip_rows);
    glPixelStorei(GL_PACK_SKIP_PIXELS, s->pack_skip_pixels);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, (GLuint)s->unpack_buffer);
    glPixelStorei(GL_UNPACK_ALIGNMENT, s->unpack_alignment);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, s->unpack_row_length);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, s->unpack_skip_rows);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, s->unpack_skip_pixels);
    for (int u = 0; u < WG_GL_STATE_TEXTURE_UNITS; ++u) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glBindTexture(GL_TEXTURE_2D, (GLuint)s->texture_2d[u]);
    }
    glActiveTexture((GLenum)s->active_texture);
    for (int u = 0; s->has_images && u < WG_GL_STATE_IMAGE_UNITS; ++u) {
        const wg_gl_image_binding* b = &s->image[u];
        glBindImageTexture((GLuint)u, (GLuint)b->name, b->level, b->layered, b->layer, (GLenum)b->access,
                           (GLenum)b->format);
    }
    glViewport(s->viewport[0], s->viewport[1], s->viewport[2], s->viewport[3]);
    glClearColor(s->clear_color[0], s->clear_color[1], s->clear_color[2], s->clear_color[3]);
    glClearDepth(s->clear_depth);
    glDepthMask(s->depth_mask);
    glColorMask(s->color_mask[0], s->color_mask[1], s->color_mask[2], s->color_mask[3]);
    glDepthFunc((GLenum)s->depth_func);
    glFrontFace((GLenum)s->front_face);
    glPolygonMode(GL_FRONT_AND_BACK, (GLenum)s->polygon_mode[0]);
    for (int i = 0; i < s->n_enables; ++i) set_cap(s->enable_caps[i], s->enabled[i]);
}

void wg_gl_state_set_defaults(int multisample) {
    GLenum caps[WG_GL_STATE_MAX_ENABLES];
    int n = list_caps(caps);
    for (int i = 0; i < n; ++i) glDisable(caps[i]);
    glEnable(GL_DEPTH_TEST);
    if (multisample) glEnable(GL_MULTISAMPLE);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glFrontFace(GL_CCW);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    glPixelStorei(GL_PACK_SKIP_ROWS, 0);
    glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
}
