/* Results in the host's vertex order (see wg_sim.h): a normals pass over particles, a pass over
 * host vertices (world or object space), then either a read-back through the pixel-pack buffer
 * into the caller's float arrays, or glReadPixels straight into the caller's GL buffer objects
 * (a pixel-pack target at the caller's offset: the data never leaves the GPU). Texels are RGBA;
 * reading GL_RGB packs 3 floats per vertex. */
#include <string.h>

#include "gpu_error.h"
#include "wg_sim_impl.h"

static void to_host_memory(wg_sim* g, const wg_tex* t, float* out) {
    size_t bytes = (size_t)g->nh * 12u;
    glBindBuffer(GL_PIXEL_PACK_BUFFER, g->pbo);
    GLint64 have = 0;
    glGetBufferParameteri64v(GL_PIXEL_PACK_BUFFER, GL_BUFFER_SIZE, &have);
    if ((size_t)have < bytes) glBufferData(GL_PIXEL_PACK_BUFFER, (GLsizeiptr)bytes, NULL, GL_STREAM_READ);
    wg_array_read_rgb(&g->layout, t, g->nh, 0);
    void* p = glMapBufferRange(GL_PIXEL_PACK_BUFFER, 0, (GLsizeiptr)bytes, GL_MAP_READ_BIT);
    if (p) {
        memcpy(out, p, bytes);
        glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

wc_status wg_sim_output(wg_sim* g, const wg_output_request* q, wc_diag* diag) {
    wg_runner* run = &g->run;
    glGetError();
    int want_n = q->normals || q->normal_buffer;
    if (want_n) {
        WG_USE(run, WGP_NORMALS, &(wg_normals_in){.x = wg_ring_cur(&g->x), .rows = &g->rows, .row_tri = &g->row_tri,
            .tri = &g->tri});
        WG_RUN(run, g->n, &g->nrm);
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
    WG_USE(run, WGP_HOST_OUTPUT, &(wg_host_output_in){.x = wg_ring_cur(&g->x), .normal = &g->nrm,
        .host_map = &g->host_map, .host_rest = &g->host_rest});
    wg_u1i(run, "u_to_object", q->to_object);
    wg_umat3(run, "u_R", R);
    wg_u3f(run, "u_t", q->t);
    wg_umat3(run, "u_inv", inv);
    wg_umat3(run, "u_rinv", Rinv);
    wg_u1f(run, "u_inv_scale", 1.0 / s);
    WG_RUN(run, g->nh, &g->host_pos, &g->host_nrm);
    if (q->positions) to_host_memory(g, &g->host_pos, q->positions);
    if (q->normals) to_host_memory(g, &g->host_nrm, q->normals);
    if (q->position_buffer) {
        glBindBuffer(GL_PIXEL_PACK_BUFFER, q->position_buffer);
        wg_array_read_rgb(&g->layout, &g->host_pos, g->nh, q->position_offset);
    }
    if (q->normal_buffer) {
        glBindBuffer(GL_PIXEL_PACK_BUFFER, q->normal_buffer);
        wg_array_read_rgb(&g->layout, &g->host_nrm, g->nh, q->normal_offset);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return wc_fail(diag, WC_ERROR_GPU, "GPU output: %s", wg_gl_error_name(e));
    return WC_OK;
}
