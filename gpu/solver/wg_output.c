/* Results in the host's vertex order (see wg_sim.h): a normals pass over particles, a pass over
 * host vertices (world or object space), then either a read-back through the pixel-pack buffer
 * into the caller's float arrays, or glReadPixels straight into the caller's GL buffer objects
 * (a pixel-pack target at the caller's offset: the data never leaves the GPU). Texels are RGBA;
 * reading GL_RGB packs 3 floats per vertex. */
#include <string.h>

#include "gpu_error.h"
#include "wg_sim_impl.h"

/* Read items [0, count) of an RGBA32F array as RGB floats into the bound pixel-pack buffer at
 * `offset` bytes, or into host memory when no buffer is bound (offset is then a pointer). */
static void read_rgb(wg_sim* g, const wg_tex* t, int count, size_t offset) {
    int W = 1 << g->shift;
    int full = count >> g->shift, rest = count - (full << g->shift);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, g->scratch_fbo);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->id, 0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (full > 0) glReadPixels(0, 0, count < W ? count : W, full, GL_RGB, GL_FLOAT, (void*)offset);
    if (rest > 0)
        glReadPixels(0, full, rest, 1, GL_RGB, GL_FLOAT, (void*)(offset + (size_t)full * (size_t)W * 12u));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

static void to_host_memory(wg_sim* g, const wg_tex* t, float* out) {
    size_t bytes = (size_t)g->nh * 12u;
    glBindBuffer(GL_PIXEL_PACK_BUFFER, g->pbo);
    GLint64 have = 0;
    glGetBufferParameteri64v(GL_PIXEL_PACK_BUFFER, GL_BUFFER_SIZE, &have);
    if ((size_t)have < bytes) glBufferData(GL_PIXEL_PACK_BUFFER, (GLsizeiptr)bytes, NULL, GL_STREAM_READ);
    read_rgb(g, t, g->nh, 0);
    void* p = glMapBufferRange(GL_PIXEL_PACK_BUFFER, 0, (GLsizeiptr)bytes, GL_MAP_READ_BIT);
    if (p) {
        memcpy(out, p, bytes);
        glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

wc_status wg_sim_output(wg_sim* g, const wg_output_request* q, wc_diag* diag) {
    glGetError();
    int want_n = q->normals || q->normal_buffer;
    if (want_n) {
        wg_use(g, WGP_NORMALS);
        wg_in(g, 0, wg_ring_cur(&g->x));
        wg_in(g, 1, &g->rows);
        wg_in(g, 2, &g->row_tri);
        wg_in(g, 3, &g->tri);
        WG_RUN(g, g->n, &g->nrm);
    }
    double Rinv[9], inv[9], s = q->unit_scale > 0 ? q->unit_scale : 1.0;
    /* R is rigid within 1e-3 (checked by the plugin); the exact inverse as plugin/transform.c */
    const double* R = q->R;
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) + R[2] * (R[3] * R[7] - R[4] * R[6]);
    double id = det != 0.0 ? 1.0 / det : 0.0;
    Rinv[0] = (R[4] * R[8] - R[5] * R[7]) * id;
    Rinv[1] = (R[2] * R[7] - R[1] * R[8]) * id;
    Rinv[2] = (R[1] * R[5] - R[2] * R[4]) * id;
    Rinv[3] = (R[5] * R[6] - R[3] * R[8]) * id;
    Rinv[4] = (R[0] * R[8] - R[2] * R[6]) * id;
    Rinv[5] = (R[2] * R[3] - R[0] * R[5]) * id;
    Rinv[6] = (R[3] * R[7] - R[4] * R[6]) * id;
    Rinv[7] = (R[1] * R[6] - R[0] * R[7]) * id;
    Rinv[8] = (R[0] * R[4] - R[1] * R[3]) * id;
    for (int k = 0; k < 9; ++k) inv[k] = Rinv[k] / s;
    wg_use(g, WGP_HOST_OUTPUT);
    wg_in(g, 0, wg_ring_cur(&g->x));
    wg_in(g, 1, &g->nrm);
    wg_in(g, 2, &g->host_map);
    wg_in(g, 3, &g->host_rest);
    wg_u1i(g, "u_to_object", q->to_object);
    wg_umat3(g, "u_R", R);
    wg_u3f(g, "u_t", q->t);
    wg_umat3(g, "u_inv", inv);
    wg_umat3(g, "u_rinv", Rinv);
    wg_u1f(g, "u_inv_scale", 1.0 / s);
    WG_RUN(g, g->nh, &g->host_pos, &g->host_nrm);
    if (q->positions) to_host_memory(g, &g->host_pos, q->positions);
    if (q->normals) to_host_memory(g, &g->host_nrm, q->normals);
    if (q->position_buffer) {
        glBindBuffer(GL_PIXEL_PACK_BUFFER, q->position_buffer);
        read_rgb(g, &g->host_pos, g->nh, q->position_offset);
    }
    if (q->normal_buffer) {
        glBindBuffer(GL_PIXEL_PACK_BUFFER, q->normal_buffer);
        read_rgb(g, &g->host_nrm, g->nh, q->normal_offset);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "GPU output: %s", wg_gl_error_name(e));
    return WC_OK;
}
