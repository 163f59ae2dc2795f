/* Helpers shared by the gpu/ renderer tests: pictures, the documented sky, an independent pinhole
 * camera model, and small scenes. */
#ifndef WEFT_TESTS_RENDER_SUPPORT_H
#define WEFT_TESTS_RENDER_SUPPORT_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "egl_context.h"
#include "render.h"

#define RS_PI 3.14159265358979323846

static inline unsigned char* image_alloc(int w, int h) {
    unsigned char* p = (unsigned char*)malloc(4 * (size_t)w * (size_t)h);
    memset(p, 0xAB, 4 * (size_t)w * (size_t)h);
    return p;
}

static inline const unsigned char* px(const unsigned char* img, int w, int x, int y) {
    return img + 4 * ((size_t)y * (size_t)w + (size_t)x);
}

/* Expected sky at row y (top first), from the documented gradient. */
static inline void sky_at(int y, int h, int out[3]) {
    const float top[3] = WG_SKY_TOP_RGB, bottom[3] = WG_SKY_BOTTOM_RGB;
    double t = (h - y - 0.5) / h;
    for (int i = 0; i < 3; ++i)
        out[i] = (int)lround((bottom[i] + t * (top[i] - bottom[i])) * 255.0);
}

static inline int is_sky(const unsigned char* img, int w, int h, int x, int y, int tol) {
    int s[3];
    sky_at(y, h, s);
    const unsigned char* p = px(img, w, x, y);
    for (int i = 0; i < 3; ++i)
        if (abs((int)p[i] - s[i]) > tol) return 0;
    return p[3] == 255;
}

static inline int luma(const unsigned char* p) {
    return (int)p[0] + (int)p[1] + (int)p[2];
}

/* Independent pinhole camera: basis, focal length in pixels, projection and pixel rays. */
typedef struct pinhole {
    double eye[3], f[3], s[3], u[3], focal;
    int w, h;
} pinhole;

static inline void unit(double v[3]) {
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; ++i) v[i] /= n;
}

static inline void pinhole_of(const wg_camera* c, pinhole* p) {
    for (int i = 0; i < 3; ++i) {
        p->eye[i] = c->eye[i];
        p->f[i] = (double)c->target[i] - c->eye[i];
    }
    unit(p->f);
    double up[3] = {c->up[0], c->up[1], c->up[2]};
    p->s[0] = p->f[1] * up[2] - p->f[2] * up[1];
    p->s[1] = p->f[2] * up[0] - p->f[0] * up[2];
    p->s[2] = p->f[0] * up[1] - p->f[1] * up[0];
    unit(p->s);
    p->u[0] = p->s[1] * p->f[2] - p->s[2] * p->f[1];
    p->u[1] = p->s[2] * p->f[0] - p->s[0] * p->f[2];
    p->u[2] = p->s[0] * p->f[1] - p->s[1] * p->f[0];
    p->focal = 0.5 * c->height / tan(0.5 * c->fov_y_deg * RS_PI / 180.0);
    p->w = c->width;
    p->h = c->height;
}

/* Image position (x right, y down, in pixels; pixel (i, j) covers [i, i+1) x [j, j+1)). */
static inline void project(const pinhole* p, const double q[3], double* x, double* y) {
    double d[3] = {q[0] - p->eye[0], q[1] - p->eye[1], q[2] - p->eye[2]};
    double xc = d[0] * p->s[0] + d[1] * p->s[1] + d[2] * p->s[2];
    double yc = d[0] * p->u[0] + d[1] * p->u[1] + d[2] * p->u[2];
    double zc = d[0] * p->f[0] + d[1] * p->f[1] + d[2] * p->f[2];
    *x = 0.5 * p->w + p->focal * xc / zc;
    *y = 0.5 * p->h - p->focal * yc / zc;
}

/* Direction of the ray through the centre of pixel (i, j). */
static inline void pixel_ray(const pinhole* p, int i, int j, double dir[3]) {
    double a = (i + 0.5 - 0.5 * p->w) / p->focal, b = (j + 0.5 - 0.5 * p->h) / p->focal;
    for (int k = 0; k < 3; ++k) dir[k] = p->f[k] + a * p->s[k] - b * p->u[k];
}

static inline wg_camera front_camera(int w, int h) {
    wg_camera c = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 40.0f, w, h};
    return c;
}

static inline wg_shape shape_at(wg_shape_type type, float x, float y, float z, float radius,
                                float hh) {
    wg_shape s;
    memset(&s, 0, sizeof s);
    s.type = type;
    s.transform[0] = s.transform[5] = s.transform[10] = s.transform[15] = 1.0f;
    s.transform[12] = x;
    s.transform[13] = y;
    s.transform[14] = z;
    s.radius = radius;
    s.half_height = hh;
    return s;
}

/* A quad [x0, x1] x [y0, y1] at z = 0, counter-clockwise seen from +z unless flipped; its arrays
 * live in a quad_store the caller keeps (tests damage them on purpose). */
#define QUAD_X0 1.5f
#define QUAD_X1 2.1f
#define QUAD_Y0 (-0.3f)
#define QUAD_Y1 0.3f

typedef struct quad_store {
    float pos[12], nrm[12];
    int tris[6];
} quad_store;

static inline wg_mesh quad_mesh(quad_store* q, int flipped, int with_normals) {
    const float p[12] = {QUAD_X0, QUAD_Y0, 0, QUAD_X1, QUAD_Y0, 0, QUAD_X1, QUAD_Y1, 0,
                         QUAD_X0, QUAD_Y1, 0};
    const int ccw[6] = {0, 1, 2, 0, 2, 3}, cw[6] = {0, 2, 1, 0, 3, 2};
    memcpy(q->pos, p, sizeof p);
    memcpy(q->tris, flipped ? cw : ccw, sizeof ccw);
    for (int v = 0; v < 4; ++v) {
        q->nrm[3 * v + 0] = 0;
        q->nrm[3 * v + 1] = 0;
        q->nrm[3 * v + 2] = flipped ? -1.0f : 1.0f;
    }
    wg_mesh m = {q->pos, with_normals ? q->nrm : NULL, 4, q->tris, 2,
                 {0.8f, 0.4f, 0.2f}, {0.2f, 0.4f, 0.8f}};
    return m;
}

/* A headless context (logging into log) and a renderer with default samples; 0 on failure
 * (printed). This machine has EGL + Mesa by .ci/deps.sh, so no context is a failure, not a
 * skip. */
static inline int rs_open(wc_log_fn log, wg_gl_context** ctx, wg_renderer** r) {
    wg_gl_context_desc desc;
    memset(&desc, 0, sizeof desc);
    desc.log = log;
    char err[1024];
    if (wg_gl_context_create(&desc, ctx, err, sizeof err) != WC_OK) {
        fprintf(stderr, "no headless GL context: %s\n", err);
        return 0;
    }
    if (wg_renderer_create(*ctx, NULL, r, err, sizeof err) != WC_OK) {
        fprintf(stderr, "renderer: %s\n", err);
        wg_gl_context_destroy(*ctx);
        return 0;
    }
    return 1;
}

#endif
