/* The host's GL buffers (wg_host_buffer.h): a body's vertices unpacked from one into a texture
 * on the GPU (wg_mesh_body_take), or read from one (wg_sim.h; where the body is moved on the
 * host). The read copies the vertices' byte range on the GPU into the cloth's read-back buffer (the one the
 * outputs' read-backs use), maps it and gathers the 3 floats of each vertex: the map waits for
 * the GPU to finish the host's commands that write the buffer. */
#include <GL/glew.h>
#include <stdint.h>
#include <string.h>

#include "gpu_error.h"
#include "wg_host_buffer.h"
#include "wg_sim_impl.h"

wc_status wg_host_buffer_check(unsigned name, size_t offset, size_t need, const char* what, const char* layout,
                               wc_diag* d) {
    if (!glIsBuffer(name))
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "%s %u is not a buffer object of the current GL context", what, name);
    GLint prev = 0;
    glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &prev);
    glBindBuffer(GL_COPY_WRITE_BUFFER, name);
    GLint64 size = -1;
    glGetBufferParameteri64v(GL_COPY_WRITE_BUFFER, GL_BUFFER_SIZE, &size);
    glBindBuffer(GL_COPY_WRITE_BUFFER, (GLuint)prev);
    if (size < 0 || offset > (size_t)size || (size_t)size - offset < need)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "%s %u holds %lld bytes; %zu are needed from offset %zu (%s)",
                       what, name, (long long)size, need, offset, layout);
    return WC_OK;
}

/* 1 when the buffer bound at target is mapped by the host, not persistently (it cannot be read
   by a copy then) */
static int mapped_by_host(GLenum target) {
    GLint mapped = GL_FALSE, access = 0;
    glGetBufferParameteriv(target, GL_BUFFER_MAPPED, &mapped);
    glGetBufferParameteriv(target, GL_BUFFER_ACCESS_FLAGS, &access);
    return mapped && !(access & GL_MAP_PERSISTENT_BIT);
}

wc_status wg_host_buffer_unpack(unsigned buffer, size_t offset, size_t floats, wg_tex* raw, int w, int h,
                                wc_diag* d) {
    if (raw->id == 0 || raw->w != w || raw->h < h) {
        char err[160];
        wg_tex_destroy(raw);
        if (!wg_tex_create(raw, GL_R32F, w, h, NULL, err, sizeof err)) return wc_fail(d, WC_ERROR_GPU, "%s", err);
    }
    GLint prev_unpack = 0, prev_tex = 0, align = 4, row = 0, skip_rows = 0, skip_pixels = 0;
    glGetIntegerv(GL_PIXEL_UNPACK_BUFFER_BINDING, &prev_unpack);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev_tex);
    glGetIntegerv(GL_UNPACK_ALIGNMENT, &align);
    glGetIntegerv(GL_UNPACK_ROW_LENGTH, &row);
    glGetIntegerv(GL_UNPACK_SKIP_ROWS, &skip_rows);
    glGetIntegerv(GL_UNPACK_SKIP_PIXELS, &skip_pixels);
    glGetError();
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, buffer);
    wc_status st = WC_OK;
    if (mapped_by_host(GL_PIXEL_UNPACK_BUFFER)) {
        st = wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "buffer %u is mapped by the host (unmap it before the call)", buffer);
    } else {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        glPixelStorei(GL_UNPACK_SKIP_ROWS, 0);
        glPixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
        glBindTexture(GL_TEXTURE_2D, raw->id);
        const size_t full = floats / (size_t)w, rest = floats % (size_t)w;
        if (full)
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, (GLsizei)full, GL_RED, GL_FLOAT, (const void*)(uintptr_t)offset);
        if (rest)
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, (GLint)full, (GLsizei)rest, 1, GL_RED, GL_FLOAT,
                            (const void*)(uintptr_t)(offset + full * (size_t)w * sizeof(float)));
        GLenum e = glGetError();
        if (e != GL_NO_ERROR) st = wc_fail(d, WC_ERROR_GPU, "reading buffer %u: %s", buffer, wg_gl_error_name(e));
    }
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev_tex);
    glBindBuffer(GL_PIXEL_UNPACK_BUFFER, (GLuint)prev_unpack);
    glPixelStorei(GL_UNPACK_ALIGNMENT, align);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, row);
    glPixelStorei(GL_UNPACK_SKIP_ROWS, skip_rows);
    glPixelStorei(GL_UNPACK_SKIP_PIXELS, skip_pixels);
    return st;
}

wc_status wg_sim_read_host_vertices(wg_sim* g, unsigned buffer, size_t offset, size_t stride, int n, float* out,
                                    wc_diag* d) {
    const size_t need = (size_t)(n - 1) * stride + 3 * sizeof(float);
    GLint prev_read = 0, prev_write = 0;
    glGetIntegerv(GL_COPY_READ_BUFFER_BINDING, &prev_read);
    glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &prev_write);
    glGetError();
    glBindBuffer(GL_COPY_READ_BUFFER, buffer);
    wc_status st = WC_OK;
    if (mapped_by_host(GL_COPY_READ_BUFFER)) {
        st = wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "buffer %u is mapped by the host (unmap it before the call)", buffer);
    } else {
        glBindBuffer(GL_COPY_WRITE_BUFFER, g->pbo);
        GLint64 have = 0;
        glGetBufferParameteri64v(GL_COPY_WRITE_BUFFER, GL_BUFFER_SIZE, &have);
        if ((size_t)have < need) glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)need, NULL, GL_STREAM_READ);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, (GLintptr)offset, 0, (GLsizeiptr)need);
        const unsigned char* p = glMapBufferRange(GL_COPY_WRITE_BUFFER, 0, (GLsizeiptr)need, GL_MAP_READ_BIT);
        if (p) {
            for (int i = 0; i < n; ++i) memcpy(out + 3 * (size_t)i, p + (size_t)i * stride, 3 * sizeof(float));
            glUnmapBuffer(GL_COPY_WRITE_BUFFER);
        }
        GLenum e = glGetError();
        if (e != GL_NO_ERROR || !p)
            st = wc_fail(d, WC_ERROR_GPU, "reading buffer %u: %s", buffer,
                         e != GL_NO_ERROR ? wg_gl_error_name(e) : "the copy could not be mapped");
    }
    glBindBuffer(GL_COPY_READ_BUFFER, (GLuint)prev_read);
    glBindBuffer(GL_COPY_WRITE_BUFFER, (GLuint)prev_write);
    return st;
}
