/* The texture layout of one cloth's arrays, and the arrays' creation, uploads and read-backs.
 *
 * Item i of every array is texel (i & (W-1), i >> shift), W = 2^shift the same for all of a
 * cloth's arrays (1024, or wider where an array would be taller than the device allows); an
 * array of n < W items is an n x 1 texture. Texels past an array's end are zeros, so that a
 * reduction over a whole texture needs no bounds. Vectors are RGBA32F (xyz, w free for a
 * partial product), symmetric 3x3 blocks two textures (a00 a01 a02 a11 | a12 a22), indices
 * RGBA32I or R32I. Calls are made with the cloth's GL context current. */
#ifndef WEFT_GPU_SOLVER_LAYOUT_H
#define WEFT_GPU_SOLVER_LAYOUT_H

#include "alloc.h"
#include "gl_texture.h"

typedef struct wg_layout {
    int shift;                  /* W = 1 << shift */
    int max_size;               /* the device's largest texture side */
    wc_allocator alloc;         /* staging of padded uploads */
    GLuint read_fbo;            /* the framebuffer that read-backs attach an array to */
} wg_layout;

/* A layout of width 2^shift on a device whose textures are at most max_size texels a side; 0
 * with err when GL fails. */
int wg_layout_init(wg_layout* L, int shift, int max_size, wc_allocator alloc, char* err, size_t err_len);
void wg_layout_destroy(wg_layout* L);

/* The texture size of an array of `count` items (at least one texel). */
void wg_layout_size(const wg_layout* L, int count, int* w, int* h);
/* Create a texture for `count` items from data (item after item, the format's client layout; the
 * last row padded with zeros) or zeros (data NULL); 0 with err when it does not fit the device
 * or GL fails. */
int wg_array_create(const wg_layout* L, wg_tex* t, GLenum internal, int count, const void* data, char* err,
                    size_t err_len);
/* Replace items [0, count) from a client buffer laid out item after item. */
void wg_array_upload(const wg_layout* L, const wg_tex* t, int count, const void* data);
/* Replace items [first, first + count) from a client buffer holding those items one after the
 * other (a partial first row, whole rows, a partial last row: at most three uploads). */
void wg_array_upload_range(const wg_layout* L, const wg_tex* t, int first, int count, const void* data);
/* Read items [0, count) of an RGBA32F array into out (count x 4 floats). */
void wg_array_read(const wg_layout* L, const wg_tex* t, int count, float* out);
/* Read items [0, count) of an RGBA32F array's first two components into out (count x 2 floats). */
void wg_array_read_rg(const wg_layout* L, const wg_tex* t, int count, float* out);
/* Read items [0, count) of an RGBA32F array as RGB floats into the bound pixel-pack buffer at
 * `offset` bytes, or, with none bound, to host memory at address `offset`. */
void wg_array_read_rgb(const wg_layout* L, const wg_tex* t, int count, size_t offset);
/* Read items ids[0, k) of an RGBA32F array into out (k x 4 floats): one texel each (the first a
 * synchronisation with the GPU). */
void wg_array_read_items(const wg_layout* L, const wg_tex* t, const int* ids, int k, float* out);
/* Read texels (x0, 0) .. (x0 + n - 1, 0) of an RGBA32F texture into out (n x 4 floats): a
 * synchronisation with the GPU. */
void wg_read_texels(const wg_layout* L, const wg_tex* t, int x0, int n, float* out);
/* Texel (0, 0): a reduction's result, a solver's scalars. */
void wg_read1(const wg_layout* L, const wg_tex* t, float out[4]);
/* a and b trade textures (a pass that changes an array writes a scratch one of the same format,
 * which then takes the array's place). */
static inline void wg_tex_swap(wg_tex* a, wg_tex* b) {
    wg_tex t = *a;
    *a = *b;
    *b = t;
}

#endif
