/* The cached framebuffers of a cloth's fragment passes (see wg_fbo_cache.h). */
#include "wg_fbo_cache.h"

/* A framebuffer with exactly these colour attachments: a cached one, or a new entry attached
 * here, or the spare re-attached when the cache is full. */
static GLuint lookup(wg_fbo_cache* c, const wg_tex* const* out, int n_out) {
    for (int k = 0; k < c->n; ++k) {
        wg_fbo_entry* e = &c->e[k];
        if (e->n != n_out) continue;
        int same = 1;
        for (int j = 0; j < n_out && same; ++j) same = e->tex[j] == out[j]->id;
        if (same) return e->fbo;
    }
    GLuint fbo = 0;
    if (c->n < WG_FBO_CACHE) {
        wg_fbo_entry* e = &c->e[c->n++];
        glGenFramebuffers(1, &e->fbo);
        e->n = n_out;
        for (int j = 0; j < n_out; ++j) e->tex[j] = out[j]->id;
        fbo = e->fbo;
    } else {
        if (!c->spare) glGenFramebuffers(1, &c->spare);
        fbo = c->spare;
    }
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    static const GLenum bufs[WG_MAX_OUT] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                            GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5,
                                            GL_COLOR_ATTACHMENT6, GL_COLOR_ATTACHMENT7};
    for (int j = 0; j < WG_MAX_OUT; ++j)
        glFramebufferTexture2D(GL_DRAW_FRAMEBUFFER, bufs[j], GL_TEXTURE_2D, j < n_out ? out[j]->id : 0, 0);
    glDrawBuffers(n_out, bufs);
    return fbo;
}

void wg_fbo_bind(wg_fbo_cache* c, const wg_tex* const* out, int n_out) {
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, lookup(c, out, n_out));
}

void wg_fbo_cache_destroy(wg_fbo_cache* c) {
    for (int k = 0; k < c->n; ++k) glDeleteFramebuffers(1, &c->e[k].fbo);
    if (c->spare) glDeleteFramebuffers(1, &c->spare);
    c->n = 0;
    c->spare = 0;
}
