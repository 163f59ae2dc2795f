/* weft_render: a preview picture of one cloth and its colliders, drawn by gpu/'s off-screen
 * renderer. The renderer is created by the first call and kept by the weft_context, in the GL
 * context of the backend's device (the GPU backend's) or, without one, in a GL context of its
 * own (headless EGL, or the host's current one in WEFT_GL_HOST_CURRENT mode), so a CPU context
 * that never renders never touches EGL. Buffers of a call are allocated per call through the
 * context's allocator (rendering is not part of a step). Built without WEFT_GPU, weft_render
 * reports WEFT_ERROR_UNSUPPORTED. */
#include <math.h>
#include <string.h>

#include "api_internal.h"
#include "call_guard.h"

#ifdef WEFT_HAVE_GPU
#include "egl_context.h"
#include "png_write.h"
#include "render.h"
#endif

weft_render_def weft_default_render_def(void) {
    weft_render_def d;
    memset(&d, 0, sizeof d);
    d.width = 640;
    d.height = 480;
    d.up[1] = 1.0f;
    d.fov_y_deg = 40.0f;
    d.draw_colliders = 1;
    d.internal_cookie = WA_COOKIE_RENDER;
    return d;
}

static int finite3(const float* v) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

/* Everything checkable without the cloth or GL. */
static weft_status check_def(weft_context* ctx, const weft_render_def* d) {
    if (!d) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "weft_render: def is NULL");
    if (d->internal_cookie != WA_COOKIE_RENDER)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT,
                       "weft_render: def was not initialised with weft_default_render_def()");
    if (d->width < 1 || d->width > 8192 || d->height < 1 || d->height > 8192)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "weft_render: def->width x height %d x %d is outside 1..8192",
                       d->width, d->height);
    if (!finite3(d->eye) || !finite3(d->target) || !finite3(d->up) || !isfinite(d->fov_y_deg))
        return wa_fail(ctx, WEFT_ERROR_NONFINITE, "weft_render: def->eye/target/up/fov_y_deg has a NaN or Inf");
    if (!(d->fov_y_deg > 0.0f && d->fov_y_deg < 180.0f))
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "weft_render: def->fov_y_deg %g is outside (0, 180)",
                       (double)d->fov_y_deg);
    if (d->draw_colliders != 0 && d->draw_colliders != 1)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "weft_render: def->draw_colliders must be 0 or 1, not %d",
                       d->draw_colliders);
    if (!d->png_path && !d->rgba)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT,
                       "weft_render: def->png_path and def->rgba are both NULL: nothing to write");
    if (d->png_path && !d->png_path[0])
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "weft_render: def->png_path is empty");
    return WEFT_OK;
}

#ifdef WEFT_HAVE_GPU

/* gpu/ speaks core's types: its logger is the context's core bridge (wa_core_log: levels mapped,
 * filtered by def.log_level) and its allocator the context's wc_allocator bridge. */

/* An ABI collider type as gpu/'s shape kind (validated when the cloth was made; anything else is
 * passed on for wg_render to refuse). */
static wg_shape_type shape_type(int collider_type) {
    switch ((weft_collider_type)collider_type) {
    case WEFT_COLLIDER_PLANE: return WG_SHAPE_PLANE;
    case WEFT_COLLIDER_SPHERE: return WG_SHAPE_SPHERE;
    case WEFT_COLLIDER_CAPSULE: return WG_SHAPE_CAPSULE;
    }
    return (wg_shape_type)collider_type;
}

/* The renderer, created on first use in the backend's GL context, or (a backend without one)
 * in a GL context of its own made now: headless or the host's, per def.gl_mode. */
static weft_status ensure_renderer(weft_context* ctx) {
    if (ctx->renderer) return WEFT_OK;
    char err[512] = "";
    wg_gl_context* shared = wa_backend_gl_context(ctx);
    wg_gl_context* gl = shared;
    if (!gl) {
        wg_gl_context_desc gd;
        memset(&gd, 0, sizeof gd);
        gd.host_current = ctx->def.gl_mode == WEFT_GL_HOST_CURRENT;
        gd.log = wa_core_log;
        gd.log_user = ctx;
        gd.allocator = ctx->alloc;
        weft_status st = wa_status(wg_gl_context_create(&gd, &gl, err, sizeof err));
        if (st != WEFT_OK) return wa_fail(ctx, st, "weft_render: %s", err);
    }
    wg_renderer* r = NULL;   /* the renderer makes its context current around its GL calls */
    weft_status st = wa_status(wg_renderer_create(gl, NULL, &r, err, sizeof err));
    if (st != WEFT_OK) {
        if (!shared) wg_gl_context_destroy(gl);
        return wa_fail(ctx, st, "weft_render: %s", err);
    }
    ctx->renderer = r;
    if (!shared) {
        ctx->render_gl = gl;
        wa_log(ctx, WEFT_LOG_INFO, "weft_render: %s", wg_gl_context_description(gl));
    }
    return WEFT_OK;
}

void wa_render_release(weft_context* ctx) {
    /* In WEFT_GL_HOST_CURRENT mode the host's context must be current here to delete the GL
     * objects; without one they die with the host's context (the memory is freed either way). */
    wg_renderer_destroy((wg_renderer*)ctx->renderer);
    wg_gl_context_destroy((wg_gl_context*)ctx->render_gl);
    ctx->renderer = NULL;
    ctx->render_gl = NULL;
}

/* Column-major float 4x4 of an affine transform (R row-major). */
static void xform_to_floats(const wc_xform* x, float* m) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m[4 * c + r] = (float)x->R[3 * r + c];
    m[3] = m[7] = m[11] = 0.0f;
    m[12] = (float)x->t[0];
    m[13] = (float)x->t[1];
    m[14] = (float)x->t[2];
    m[15] = 1.0f;
}

weft_status weft_render(weft_context* ctx, weft_cloth cloth, const weft_render_def* def) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, "weft_render");
    if (!c) return ctx->last_status;
    weft_status st = check_def(ctx, def);
    if (st != WEFT_OK) return st;

    int nv = c->n_host, nt = c->model.n_tris;
    int nc = def->draw_colliders ? c->n_colliders : 0;
    size_t w = (size_t)def->width, h = (size_t)def->height;
    float* pos = WC_NEW(&ctx->alloc, float, (size_t)nv * 6);
    int* tris = WC_NEW(&ctx->alloc, int, (size_t)nt * 3);
    wg_shape* shapes = nc ? WC_NEW(&ctx->alloc, wg_shape, nc) : NULL;
    unsigned char* rgba = def->rgba ? def->rgba : WC_NEW(&ctx->alloc, unsigned char, w * h * 4);
    unsigned char* own_rgba = def->rgba ? NULL : rgba;
    if (!pos || !tris || (nc && !shapes) || !rgba) {
        st = wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "weft_render: out of memory for %d vertices, %zu x %zu pixels", nv,
                     w, h);
        goto done;
    }
    int count = 0;
    st = weft_cloth_get_vertices(ctx, cloth, WEFT_SPACE_WORLD, pos, pos + (size_t)nv * 3, nv, &count);
    if (st == WEFT_OK) st = weft_cloth_get_triangles(ctx, cloth, tris, nt, &count);
    if (st != WEFT_OK) goto done;
    for (int i = 0; i < nc; ++i) {
        const wc_cloth_collider* k = &c->colliders[i];
        memset(&shapes[i], 0, sizeof shapes[i]);
        shapes[i].type = shape_type(k->type);
        xform_to_floats(&c->collider_xf[i], shapes[i].transform);
        shapes[i].radius = (float)k->radius;
        shapes[i].half_height = (float)k->half_height;
    }

    st = ensure_renderer(ctx);
    if (st != WEFT_OK) goto done;

    wg_mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    mesh.positions = pos;
    mesh.normals = NULL; /* area-weighted per host vertex: a seam shades smoothly either side */
    mesh.n_vertices = nv;
    mesh.triangles = tris;
    mesh.n_triangles = nt;
    const float front[3] = {0.80f, 0.28f, 0.22f}, back[3] = {0.95f, 0.78f, 0.45f};
    memcpy(mesh.front_rgb, front, sizeof front);
    memcpy(mesh.back_rgb, back, sizeof back);
    wg_camera cam;
    memcpy(cam.eye, def->eye, sizeof cam.eye);
    memcpy(cam.target, def->target, sizeof cam.target);
    memcpy(cam.up, def->up, sizeof cam.up);
    cam.fov_y_deg = def->fov_y_deg;
    cam.width = def->width;
    cam.height = def->height;

    char err[512] = "";
    st = wa_status(wg_render((wg_renderer*)ctx->renderer, &cam, &mesh, 1, shapes, nc, rgba, err, sizeof err));
    if (st != WEFT_OK) {
        st = wa_fail(ctx, st, "weft_render: %s", err);
        goto done;
    }
    if (def->png_path) {
        st = wa_status(wg_png_write(def->png_path, rgba, def->width, def->height, err, sizeof err));
        if (st != WEFT_OK) {
            st = wa_fail(ctx, st, "weft_render: %s", err);
            goto done;
        }
    }
    st = wa_ok(ctx);
done:
    wc_free(&ctx->alloc, pos);
    wc_free(&ctx->alloc, tris);
    wc_free(&ctx->alloc, shapes);
    wc_free(&ctx->alloc, own_rgba);
    return st;
}

#else /* !WEFT_HAVE_GPU */

void wa_render_release(weft_context* ctx) { (void)ctx; }

weft_status weft_render(weft_context* ctx, weft_cloth cloth, const weft_render_def* def) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    if (!wa_lookup(ctx, cloth, "weft_render")) return ctx->last_status;
    weft_status st = check_def(ctx, def);
    if (st != WEFT_OK) return st;
    return wa_fail(ctx, WEFT_ERROR_UNSUPPORTED, "weft_render: this libweft.so was built without WEFT_GPU");
}

#endif
