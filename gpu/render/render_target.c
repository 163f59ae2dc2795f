/* Framebuffers of the preview renderer. */
#include "render_target.h"

#include <string.h>

#include "gpu_error.h"

void wg_target_destroy(wg_target* t) {
    GLuint fbos[2] = {t->ms_fbo, t->fbo};
    GLuint rbos[4] = {t->ms_color, t->ms_depth, t->color, t->depth};
    glDeleteFramebuffers(2, fbos); /* zero names are ignored */
    glDeleteRenderbuffers(4, rbos);
    memset(t, 0, sizeof *t);
}

static GLuint make_rbo(GLenum format, int width, int height, int samples) {
    GLuint rbo = 0;
    glGenRenderbuffers(1, &rbo);
    glBindRenderbuffer(GL_RENDERBUFFER, rbo);
    if (samples > 1)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, width, height);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, width, height);
    glBindRenderbuffer(GL_RENDERBUFFER, 0);
    return rbo;
}

static wc_status check_fbo(const char* what, int width, int height, int samples, char* err,
                             size_t err_len) {
    GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    GLenum gl_err = glGetError();
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        wg_errorf(err, err_len, "%s framebuffer %d x %d (%d samples) is incomplete: %s (0x%04x)",
                  what, width, height, samples, wg_fbo_status_name(status), (unsigned)status);
        return WC_ERROR_GPU;
    }
    if (gl_err != GL_NO_ERROR) {
        wg_errorf(err, err_len, "%s framebuffer %d x %d (%d samples): %s (0x%04x)", what, width,
                  height, samples, wg_gl_error_name(gl_err), (unsigned)gl_err);
        return WC_ERROR_GPU;
    }
    return WC_OK;
}

wc_status wg_target_ensure(wg_target* t, int width, int height, int samples, char* err,
                             size_t err_len) {
    if (t->fbo && t->width == width && t->height == height && t->samples == samples) return WC_OK;
    wg_target_destroy(t);
    t->width = width;
    t->height = height;
    t->samples = samples;
    wc_status st = WC_OK;
    if (samples > 1) {
        t->ms_color = make_rbo(GL_RGBA8, width, height, samples);
        t->ms_depth = make_rbo(GL_DEPTH_COMPONENT24, width, height, samples);
        glGenFramebuffers(1, &t->ms_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, t->ms_fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                  t->ms_color);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                  t->ms_depth);
        st = check_fbo("multisampled", width, height, samples, err, err_len);
    }
    if (st == WC_OK) {
        t->color = make_rbo(GL_RGBA8, width, height, 1);
        if (samples <= 1) t->depth = make_rbo(GL_DEPTH_COMPONENT24, width, height, 1);
        glGenFramebuffers(1, &t->fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->color);
        if (t->depth)
            glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                                      t->depth);
        st = check_fbo(samples > 1 ? "resolve" : "colour + depth", width, height, 1, err, err_len);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (st != WC_OK) wg_target_destroy(t);
    return st;
}

GLuint wg_target_draw_fbo(const wg_target* t) {
    return t->samples > 1 ? t->ms_fbo : t->fbo;
}

void wg_target_resolve(const wg_target* t) {
    if (t->samples > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, t->ms_fbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->fbo);
        glBlitFramebuffer(0, 0, t->width, t->height, 0, 0, t->width, t->height,
                          GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->fbo);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
}
