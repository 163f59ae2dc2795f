/* A cloth's arrays as textures in its layout (see wg_layout.h). */
#include "wg_layout.h"

#include <stdint.h>
#include <string.h>

#include "gpu_error.h"

int wg_layout_init(wg_layout* L, int shift, int max_size, wc_allocator alloc, char* err, size_t err_len) {
    memset(L, 0, sizeof *L);
    L->shift = shift;
    L->max_size = max_size;
    L->alloc = alloc;
    glGenFramebuffers(1, &L->read_fbo);
    if (!L->read_fbo) {
        wg_errorf(err, err_len, "glGenFramebuffers: %s", wg_gl_error_name(glGetError()));
        return 0;
    }
    return 1;
}

void wg_layout_destroy(wg_layout* L) {
    if (L->read_fbo) glDeleteFramebuffers(1, &L->read_fbo);
    L->read_fbo = 0;
}

void wg_layout_size(const wg_layout* L, int count, int* w, int* h) {
    int W = 1 << L->shift;
    if (count < 1) count = 1;
    *w = count < W ? count : W;
    *h = (int)(((long long)count + W - 1) >> L->shift);
}

int wg_array_create(const wg_layout* L, wg_tex* t, GLenum internal, int count, const void* data, char* err,
                    size_t err_len) {
    int w, h;
    wg_layout_size(L, count, &w, &h);
    if (h > L->max_size) {
        wg_errorf(err, err_len, "an array of %d items needs a %d x %d texture, above the device's limit %d", count, w, h,
                  L->max_size);
        return 0;
    }
    if (!data) return wg_tex_create(t, internal, w, h, NULL, err, err_len);
    /* data covers `count` items; the texture's last row is padded with zeros */
    int is_int = 0, comp = wg_tex_components(internal, &is_int);
    size_t item = (size_t)comp * 4u, total = (size_t)w * h * item;
    if ((size_t)count * item == total) return wg_tex_create(t, internal, w, h, data, err, err_len);
    unsigned char* pad = wc_calloc(&L->alloc, total, 1);
    if (!pad) {
        wg_errorf(err, err_len, "out of memory");
        return 0;
    }
    memcpy(pad, data, (size_t)count * item);
    int ok = wg_tex_create(t, internal, w, h, pad, err, err_len);
    wc_free(&L->alloc, pad);
    return ok;
}

void wg_array_upload(const wg_layout* L, const wg_tex* t, int count, const void* data) {
    wg_array_upload_range(L, t, 0, count, data);
}

void wg_array_upload_range(const wg_layout* L, const wg_tex* t, int first, int count, const void* data) {
    const int W = 1 << L->shift;
    const size_t item = (size_t)wg_tex_components(t->internal, NULL) * 4u;
    const unsigned char* p = (const unsigned char*)data;
    for (int i = first, end = first + count; i < end;) {
        int row = i >> L->shift, col = i & (W - 1), len = end - i < W - col ? end - i : W - col;
        int rows = col == 0 ? (end - i) >> L->shift : 0;
        if (rows > 0) len = (end - i < W ? end - i : W);   /* whole rows in one upload */
        else rows = 1;
        wg_tex_upload(t, col, row, len, rows, p);
        i += len * rows;
        p += (size_t)len * rows * item;
    }
}

/* t as the read framebuffer's colour attachment 0 */
static void bind_read(const wg_layout* L, const wg_tex* t) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, L->read_fbo);
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->id, 0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
}

/* count items of t, channels (2, 3 or 4) floats each, read row by row to at: client memory, or
 * an offset into the bound GL_PIXEL_PACK_BUFFER */
static void read_items(const wg_layout* L, const wg_tex* t, int count, int channels, uintptr_t at) {
    GLenum format = channels == 4 ? GL_RGBA : channels == 3 ? GL_RGB : GL_RG;
    int W = 1 << L->shift;
    int full = count >> L->shift, rest = count - (full << L->shift);
    bind_read(L, t);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (full > 0) glReadPixels(0, 0, count < W ? count : W, full, format, GL_FLOAT, (void*)at);
    if (rest > 0)
        glReadPixels(0, full, rest, 1, format, GL_FLOAT,
                     (void*)(at + (size_t)full * (size_t)W * (size_t)channels * sizeof(float)));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void wg_array_read(const wg_layout* L, const wg_tex* t, int count, float* out) {
    if (count <= 0) return;
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    read_items(L, t, count, 4, (uintptr_t)out);
}

void wg_array_read_rg(const wg_layout* L, const wg_tex* t, int count, float* out) {
    if (count <= 0) return;
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    read_items(L, t, count, 2, (uintptr_t)out);
}

void wg_array_read_rgb(const wg_layout* L, const wg_tex* t, int count, size_t offset) {
    read_items(L, t, count, 3, (uintptr_t)offset);
}

void wg_read_texels(const wg_layout* L, const wg_tex* t, int x0, int n, float* out) {
    bind_read(L, t);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glReadPixels(x0, 0, n, 1, GL_RGBA, GL_FLOAT, out);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

void wg_read1(const wg_layout* L, const wg_tex* t, float out[4]) { wg_read_texels(L, t, 0, 1, out); }

void wg_array_read_items(const wg_layout* L, const wg_tex* t, const int* ids, int k, float* out) {
    if (k <= 0) return;
    const int W = 1 << L->shift;
    bind_read(L, t);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    for (int u = 0; u < k; ++u)
        glReadPixels(ids[u] & (W - 1), ids[u] >> L->shift, 1, 1, GL_RGBA, GL_FLOAT, out + 4 * (size_t)u);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}
