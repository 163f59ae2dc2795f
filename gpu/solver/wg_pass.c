/* Running passes: programs, inputs, uniforms, framebuffers, reductions, read-backs (see
 * wg_sim_impl.h). */
#include <string.h>

#include "gpu_error.h"
#include "wg_compute.h"
#include "wg_sim_impl.h"

void wg_layout_size(const wg_sim* g, int count, int* w, int* h) {
    int W = 1 << g->shift;
    if (count < 1) count = 1;
    *w = count < W ? count : W;
    *h = (int)(((long long)count + W - 1) >> g->shift);
}

int wg_array_create(wg_sim* g, wg_tex* t, GLenum internal, int count, const void* data, char* err, size_t err_len) {
    int w, h;
    wg_layout_size(g, count, &w, &h);
    if (h > g->dev->max_texture_size) {
        wg_errorf(err, err_len, "an array of %d items needs a %d x %d texture, above the device's limit %d", count, w, h,
                  g->dev->max_texture_size);
        return 0;
    }
    if (!data) return wg_tex_create(t, internal, w, h, NULL, err, err_len);
    /* data covers `count` items; the texture's last row is padded with zeros */
    int is_int = 0, comp = wg_tex_components(internal, &is_int);
    size_t item = (size_t)comp * 4u, total = (size_t)w * h * item;
    if ((size_t)count * item == total) return wg_tex_create(t, internal, w, h, data, err, err_len);
    unsigned char* pad = wc_calloc(&g->alloc, total, 1);
    if (!pad) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    memcpy(pad, data, (size_t)count * item);
    int ok = wg_tex_create(t, internal, w, h, pad, err, err_len);
    wc_free(&g->alloc, pad);
    return ok;
}

void wg_array_upload(wg_sim* g, const wg_tex* t, int count, const void* data) {
    if (count <= 0) return;
    int W = 1 << g->shift, comp = wg_tex_components(t->internal, NULL);
    int full = count >> g->shift, rest = count - (full << g->shift);
    if (full > 0) wg_tex_upload(t, 0, 0, count < W ? count : W, full, data);
    if (rest > 0) {
        const unsigned char* p = (const unsigned char*)data + (size_t)full * W * comp * 4u;
        wg_tex_upload(t, 0, full, rest, 1, p);
    }
}

static void bind_read(wg_sim* g, const wg_tex* t) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, g->scratch_fbo);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->id, 0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
}

void wg_array_read(wg_sim* g, const wg_tex* t, int count, float* out) {
    if (count <= 0) return;
    int W = 1 << g->shift;
    int full = count >> g->shift, rest = count - (full << g->shift);
    bind_read(g, t);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (full > 0) glReadPixels(0, 0, count < W ? count : W, full, GL_RGBA, GL_FLOAT, out);
    if (rest > 0) glReadPixels(0, full, rest, 1, GL_RGBA, GL_FLOAT, out + (size_t)full * W * 4u);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void wg_read1(wg_sim* g, const wg_tex* t, float out[4]) {
    bind_read(g, t);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glReadPixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, out);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void wg_use(wg_sim* g, wg_pass_id p) {
    g->prog = &g->dev->prog[p];
    glUseProgram(g->prog->id);
}

void wg_in(wg_sim* g, int unit, const wg_tex* t) {
    (void)g;
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(GL_TEXTURE_2D, t->id);
}

void wg_u1i(wg_sim* g, const char* name, int v) { glUniform1i(wg_program_loc(g->prog, name), v); }
void wg_u1f(wg_sim* g, const char* name, double v) { glUniform1f(wg_program_loc(g->prog, name), (float)v); }
void wg_u2f(wg_sim* g, const char* name, double a, double b) {
    glUniform2f(wg_program_loc(g->prog, name), (float)a, (float)b);
}
void wg_u3f(wg_sim* g, const char* name, const double* v) {
    glUniform3f(wg_program_loc(g->prog, name), (float)v[0], (float)v[1], (float)v[2]);
}
void wg_u2i(wg_sim* g, const char* name, int a, int b) { glUniform2i(wg_program_loc(g->prog, name), a, b); }
void wg_u4i(wg_sim* g, const char* name, int a, int b, int c, int d) {
    glUniform4i(wg_program_loc(g->prog, name), a, b, c, d);
}
void wg_umat3(wg_sim* g, const char* name, const double* rm) {
    float m[9];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m[3 * c + r] = (float)rm[3 * r + c];   /* column-major */
    glUniformMatrix3fv(wg_program_loc(g->prog, name), 1, GL_FALSE, m);
}

/* A framebuffer with exactly these colour attachments (cached per cloth; the textures are the
 * cloth's own, so no entry outlives them). */
static GLuint fbo_for(wg_sim* g, const wg_tex* const* out, int n_out) {
    for (int k = 0; k < g->n_fbo; ++k) {
        wg_fbo_entry* e = &g->fbo[k];
        if (e->n != n_out) continue;
        int same = 1;
        for (int j = 0; j < n_out && same; ++j) same = e->tex[j] == out[j]->id;
        if (same) return e->fbo;
    }
    GLuint fbo = 0;
    wg_fbo_entry* e = NULL;
    if (g->n_fbo < WG_FBO_CACHE) {
        e = &g->fbo[g->n_fbo++];
        glGenFramebuffers(1, &e->fbo);
        e->n = n_out;
        for (int j = 0; j < n_out; ++j) e->tex[j] = out[j]->id;
        fbo = e->fbo;
    } else {
        fbo = g->scratch_fbo;   /* full cache: re-attach every time */
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

/* A compute pass (wg_compute.h) over the w x h texels at (x0, 0). */
static void dispatch(wg_sim* g, int count, const wg_tex* const* out, int n_out, int x0, int w, int h) {
    glUniform1i(wg_program_loc(g->prog, "u_n"), count);
    glUniform1i(wg_program_loc(g->prog, "u_shift"), g->shift);
    wg_compute_dispatch(g->prog, out, n_out, x0, w, h);
    ++g->passes;
}

void wg_run(wg_sim* g, int count, const wg_tex* const* out, int n_out) {
    if (g->dev->compute) {
        dispatch(g, count, out, n_out, 0, out[0]->w, out[0]->h);
        return;
    }
    GLuint fbo = fbo_for(g, out, n_out);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glViewport(0, 0, out[0]->w, out[0]->h);
    glUniform1i(wg_program_loc(g->prog, "u_n"), count);
    glUniform1i(wg_program_loc(g->prog, "u_shift"), g->shift);
    glBindVertexArray(g->dev->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++g->passes;
}

void wg_run_groups(wg_sim* g, int count, const wg_tex* out, int groups) {
    glUniform1i(wg_program_loc(g->prog, "u_n"), count);
    glUniform1i(wg_program_loc(g->prog, "u_shift"), g->shift);
    wg_compute_dispatch_groups(out, groups, g->dev->max_groups_x);
    ++g->passes;
}

void wg_run_texel(wg_sim* g, const wg_tex* out, int x) {
    const wg_tex* const o[1] = {out};
    if (g->dev->compute) {
        dispatch(g, 1, o, 1, x, 1, 1);
        return;
    }
    GLuint fbo = fbo_for(g, o, 1);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glViewport(x, 0, 1, 1);
    glUniform1i(wg_program_loc(g->prog, "u_n"), 1);
    glUniform1i(wg_program_loc(g->prog, "u_shift"), g->shift);
    glBindVertexArray(g->dev->vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++g->passes;
}

/* Work groups of reduce_groups.glsl's first dispatch over `texels`: ~1024 texels a group (4 per
   invocation), at most 1024 groups, so that the second dispatch (one group) has at most 1024. */
static int reduce_groups(long long texels) {
    long long k = (texels + 1023) / 1024;
    return k < 1 ? 1 : k > 1024 ? 1024 : (int)k;
}

int wg_chain_create(wg_sim* g, wg_chain* ch, int w, int h, char* err, size_t err_len) {
    memset(ch, 0, sizeof *ch);
    if (g->dev->compute) {   /* one or two dispatches: each level is as wide as its dispatch's groups */
        int k = reduce_groups((long long)w * h);
        if (k > 1) {
            if (!wg_tex_create(&ch->level[0], GL_RGBA32F, k, 1, NULL, err, err_len)) return 0;
            ++ch->n_levels;
        }
        if (!wg_tex_create(&ch->level[ch->n_levels], GL_RGBA32F, 1, 1, NULL, err, err_len)) return 0;
        ++ch->n_levels;
        return 1;
    }
    do {
        w = (w + 7) / 8;
        h = (h + 7) / 8;
        if (ch->n_levels == WG_REDUCE_LEVELS) {
            wg_errorf(err, err_len, "reduction deeper than %d levels", WG_REDUCE_LEVELS);
            return 0;
        }
        if (!wg_tex_create(&ch->level[ch->n_levels], GL_RGBA32F, w, h, NULL, err, err_len)) return 0;
        ++ch->n_levels;
    } while (w > 1 || h > 1);
    return 1;
}

void wg_chain_destroy(wg_chain* ch) {
    for (int k = 0; k < ch->n_levels; ++k) wg_tex_destroy(&ch->level[k]);
    ch->n_levels = 0;
}

const wg_tex* wg_reduce(wg_sim* g, wg_chain* ch, const wg_tex* src, int m0, int m1, int m2, int m3) {
    const int groups = g->dev->compute;   /* reduce_groups.glsl: a level as wide as its work groups */
    wg_use(g, groups ? WGP_REDUCE_GROUPS : WGP_REDUCE);
    wg_u4i(g, "u_mode", m0, m1, m2, m3);
    const wg_tex* in = src;
    for (int k = 0; k < ch->n_levels; ++k) {
        const wg_tex* out = &ch->level[k];
        wg_in(g, 0, in);
        wg_u2i(g, "u_in", in->w, in->h);
        if (groups) {
            wg_u1i(g, "u_groups", out->w);
            wg_run_groups(g, 1, out, out->w);
        } else {
            WG_RUN(g, out->w * out->h, out);
        }
        in = out;
    }
    return in;
}

void wg_copy(wg_sim* g, const wg_tex* dst, const wg_tex* src) {
    wg_use(g, WGP_COPY);
    wg_in(g, 0, src);
    WG_RUN(g, dst->w * dst->h, dst);
}

void wg_stamp(wg_sim* g, wg_stage stage) {
    if (!g->dev->has_timer || g->n_stamps >= WG_MAX_STAMPS) return;
    glQueryCounter(g->stamps[g->n_stamps], GL_TIMESTAMP);
    g->stamp_stage[g->n_stamps++] = (int)stage;
}
