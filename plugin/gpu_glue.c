/* The GPU backend behind the facade: the context's GL context and solver device, each cloth's
 * wg_sim (gpu/solver/wg_sim.h), and weft_cloth_write_gl_buffers. Every GL call happens between
 * wa_gl_begin and wa_gl_end of the context's one wg_gl_context (shared with weft_render).
 *
 * A GPU cloth's positions, velocities, warm start and contacts live in textures; the wc_state
 * keeps the book-keeping (pins, colliders, time, sleep) and a mirror of those arrays that is
 * filled only when something on the CPU needs it (snapshots, attachment binding, the step's
 * range check when the GPU's bound is not enough). Built without WEFT_GPU every entry fails with
 * WEFT_ERROR_UNSUPPORTED. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "api_internal.h"

#ifdef WEFT_HAVE_GPU
#include <GL/glew.h>

#include "egl_context.h"
#include "gl_state.h"
#include "wg_device.h"
#include "wg_sim.h"

#define GL_OF(ctx) ((wg_gl_context*)(ctx)->gl)
#define SIM_OF(c) ((wg_sim*)(c)->gpu)

static weft_status gl_begin(weft_context* ctx, char* err, size_t err_len) { return wa_status(wg_gl_begin(GL_OF(ctx), err, err_len)); }

static void gl_end(weft_context* ctx) { wg_gl_end(GL_OF(ctx)); }

weft_status wa_gl_begin(weft_context* ctx, const char* fn) {
    char err[512] = "";
    weft_status st = gl_begin(ctx, err, sizeof err);
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: GPU backend: %s", fn, err);
    return WEFT_OK;
}

void wa_gl_end(weft_context* ctx) { gl_end(ctx); }

weft_status wa_gl_context_new(weft_context* ctx, void** out, char* err, size_t err_len) {
    wg_gl_context_desc gd;
    memset(&gd, 0, sizeof gd);
    gd.host_current = ctx->def.gl_mode == WEFT_GL_HOST_CURRENT;
    gd.log = wa_core_log;   /* gpu/ speaks core's types: levels mapped, filtered by def.log_level */
    gd.log_user = ctx;
    gd.allocator = ctx->alloc;
    wg_gl_context* gl = NULL;
    weft_status st = wa_status(wg_gl_context_create(&gd, &gl, err, err_len));
    *out = gl;
    return st;
}

weft_status wa_gpu_context_init(weft_context* ctx, int only_hardware, int* software, char* err, size_t err_len) {
    *software = 0;
    void* glv = NULL;
    weft_status st = wa_gl_context_new(ctx, &glv, err, err_len);
    if (st != WEFT_OK) return st;
    wg_gl_context* gl = glv;
    /* AUTO: a software rasteriser is known from the renderer string already; the programs are
     * not compiled for nothing */
    if (only_hardware && wg_renderer_is_software(wg_gl_context_description(gl))) {
        *software = 1;
        snprintf(err, err_len, "%s", wg_gl_context_description(gl));
        wg_gl_context_destroy(gl);
        return WEFT_OK;
    }
    ctx->gl = gl;
    st = gl_begin(ctx, err, err_len);
    if (st != WEFT_OK) {
        ctx->gl = NULL;
        wg_gl_context_destroy(gl);
        return st;
    }
    wg_device* dev = NULL;
    st = wa_status(wg_device_create(gl, &dev, err, err_len));
    if (st == WEFT_OK && only_hardware && dev->software) {
        *software = 1;
        snprintf(err, err_len, "%s", dev->renderer);
        wg_device_destroy(dev);
        dev = NULL;
    }
    gl_end(ctx);
    if (st != WEFT_OK || !dev) {
        ctx->gl = NULL;
        wg_gl_context_destroy(gl);
        return st;
    }
    ctx->device = dev;
    snprintf(err, err_len, "%s%s", dev->renderer, dev->compute ? " (compute-shader passes)" : " (fragment-shader passes)");
    return WEFT_OK;
}

int wa_gpu_has_multigrid(const weft_context* ctx) {
    return ctx->device && ((const wg_device*)ctx->device)->compute;
}

void wa_gpu_context_release(weft_context* ctx) {
    if (!ctx->device) return;
    char err[512] = "";
    if (gl_begin(ctx, err, sizeof err) == WEFT_OK) {
        wg_device_destroy((wg_device*)ctx->device);
        gl_end(ctx);
    } else {
        /* host-current mode without the host's context: its GL objects die with that context */
        wa_log(ctx, WEFT_LOG_WARN, "weft_context_destroy: GPU device's GL objects left to the host's context (%s)", err);
        wg_device_forget((wg_device*)ctx->device);
    }
    ctx->device = NULL;
}

weft_status wa_gpu_cloth_create(weft_context* ctx, wa_cloth* c, const char* fn) {
    weft_status st = wa_gl_begin(ctx, fn);
    if (st != WEFT_OK) return st;
    wc_diag d = wa_core_diag(ctx);
    wg_sim* g = NULL;
    st = wa_status(wg_sim_create((wg_device*)ctx->device, c->state, c->host_rest, &g, &d));
    wa_gl_end(ctx);
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: GPU backend: %s", fn, d.message);
    c->gpu = g;
    return WEFT_OK;
}

void wa_gpu_cloth_destroy(wa_cloth* c) {
    if (!c->gpu) return;
    weft_context* ctx = c->ctx;
    char err[512] = "";
    if (gl_begin(ctx, err, sizeof err) == WEFT_OK) {
        wg_sim_destroy(SIM_OF(c));
        gl_end(ctx);
    } else {
        /* host-current mode without the host's context: its GL objects go with that context */
        wa_log(ctx, WEFT_LOG_WARN, "weft_cloth_destroy: GPU cloth's GL objects left to the host's context (%s)", err);
        wg_sim_forget(SIM_OF(c));
    }
    c->gpu = NULL;
}

weft_status wa_gpu_download_raw(weft_context* ctx, wa_cloth* c, const char* fn) {
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wg_sim_download(SIM_OF(c), c->state, &d));
    return st == WEFT_OK ? st : wa_fail(ctx, st, "%s: %s", fn, d.message);
}

weft_status wa_gpu_upload_raw(weft_context* ctx, wa_cloth* c, const char* fn) {
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wg_sim_upload(SIM_OF(c), c->state, &d));
    return st == WEFT_OK ? st : wa_fail(ctx, st, "%s: %s", fn, d.message);
}

weft_status wa_gpu_download(weft_context* ctx, wa_cloth* c, const char* fn) {
    weft_status st = wa_gl_begin(ctx, fn);
    if (st != WEFT_OK) return st;
    st = wa_gpu_download_raw(ctx, c, fn);
    wa_gl_end(ctx);
    return st;
}

weft_status wa_gpu_upload(weft_context* ctx, wa_cloth* c, const char* fn) {
    weft_status st = wa_gl_begin(ctx, fn);
    if (st != WEFT_OK) return st;
    st = wa_gpu_upload_raw(ctx, c, fn);
    wa_gl_end(ctx);
    return st;
}

weft_status wa_gpu_transfer(wa_cloth* c, int upload, wc_diag* d) {
    return wa_status(upload ? wg_sim_upload(SIM_OF(c), c->state, d) : wg_sim_download(SIM_OF(c), c->state, d));
}

void wa_gpu_backup(wa_cloth* c) { wg_sim_backup(SIM_OF(c)); }
void wa_gpu_restore_backup(wa_cloth* c) { wg_sim_restore_backup(SIM_OF(c)); }

void wa_gpu_transform(wa_cloth* c, const double* Rx, const double* tx, const double* Rv, const double* dv) {
    wg_sim_transform(SIM_OF(c), Rx, tx, Rv, dv);
}

weft_status wa_gpu_step_frame(wa_cloth* c, double dt, wc_step_stats* ss, wc_diag* d) {
    return wa_status(wg_sim_step_frame(SIM_OF(c), c->state, dt, ss, d));
}

int wa_gpu_outputs_in_range(wa_cloth* c, const wa_xform* T, int* vertex, double* value, weft_status* st,
                            wc_diag* d) {
    *st = WEFT_OK;
    /* |world coordinate| <= M; |object coordinate| <= (sum_j |inv.R_ij| M + |inv.t_i|) / scale */
    double M = wg_sim_max_abs(SIM_OF(c));
    if (isfinite(M)) {
        wa_xform inv;
        wa_xform_inverse(T, &inv);
        double bound = M;
        for (int i = 0; i < 3; ++i) {
            double b = fabs(inv.t[i]);
            for (int j = 0; j < 3; ++j) b += fabs(inv.R[3 * i + j]) * M;
            b /= c->unit_scale;
            if (!(b <= bound)) bound = b;
        }
        int unused_ok = 1;   /* host vertices without a particle: rest moved with the object */
        for (int v = 0; v < c->n_host && unused_ok; ++v) {
            if (c->model.host_to_particle[v] >= 0) continue;
            double w[3];
            wa_xform_point(T, c->host_rest + 3 * v, w);
            for (int k = 0; k < 3; ++k) {
                double o = c->host_rest[3 * v + k] / c->unit_scale;
                if (!(fabs(w[k]) <= WA_MAX_OUTPUT_COORD) || !(fabs(o) <= WA_MAX_OUTPUT_COORD)) unused_ok = 0;
            }
        }
        if (bound <= WA_MAX_OUTPUT_COORD && unused_ok) return 1;
    }
    /* the bound could exceed the limit: the exact check on the downloaded positions */
    *st = wa_status(wg_sim_download(SIM_OF(c), c->state, d));
    if (*st != WEFT_OK) return 0;
    return wa_outputs_in_range(c, T, vertex, value);
}

weft_status wa_gpu_vertices(weft_context* ctx, wa_cloth* c, int object, float* positions, float* normals,
                            unsigned position_buffer, size_t position_offset, unsigned normal_buffer,
                            size_t normal_offset, const char* fn) {
    wg_output_request r;
    memset(&r, 0, sizeof r);
    r.to_object = object;
    memcpy(r.R, c->object.R, sizeof r.R);
    memcpy(r.t, c->object.t, sizeof r.t);
    r.unit_scale = c->unit_scale;
    r.positions = positions;
    r.normals = normals;
    r.position_buffer = position_buffer;
    r.normal_buffer = normal_buffer;
    r.position_offset = position_offset;
    r.normal_offset = normal_offset;
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wg_sim_output(SIM_OF(c), &r, &d));
    return st == WEFT_OK ? st : wa_fail(ctx, st, "%s: %s", fn, d.message);
}

/* A host buffer name: exists and holds `need` bytes from offset. Inside wa_gl_begin. */
static weft_status check_buffer(weft_context* ctx, unsigned name, size_t offset, size_t need, const char* what,
                                const char* fn) {
    if (!glIsBuffer(name))
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: %s %u is not a buffer object of the current GL context",
                       fn, what, name);
    GLint prev = 0;
    glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &prev);
    glBindBuffer(GL_COPY_WRITE_BUFFER, name);
    GLint64 size = -1;
    glGetBufferParameteri64v(GL_COPY_WRITE_BUFFER, GL_BUFFER_SIZE, &size);
    glBindBuffer(GL_COPY_WRITE_BUFFER, (GLuint)prev);
    if (size < 0 || offset > (size_t)size || (size_t)size - offset < need)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT,
                       "%s: %s %u holds %lld bytes; %zu are needed from offset %zu (3 floats per host vertex)", fn, what,
                       name, (long long)size, need, offset);
    return WEFT_OK;
}

weft_status weft_cloth_write_gl_buffers(weft_context* ctx, weft_cloth cloth, weft_space space, unsigned position_buffer,
                                        size_t position_offset, unsigned normal_buffer, size_t normal_offset) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_write_gl_buffers";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (space != WEFT_SPACE_WORLD && space != WEFT_SPACE_OBJECT)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: space = %d is not a weft_space", fn, (int)space);
    if (!c->gpu)
        return wa_fail(ctx, WEFT_ERROR_UNSUPPORTED,
                       "%s: the cloth runs on the CPU backend (only GPU cloths write GL buffers; use "
                       "weft_cloth_get_vertices)", fn);
    if (ctx->def.gl_mode != WEFT_GL_HOST_CURRENT)
        return wa_fail(ctx, WEFT_ERROR_UNSUPPORTED,
                       "%s: the context is WEFT_GL_HEADLESS: its GL context is Weft's own, so the host's buffer "
                       "names mean nothing there (create the context with WEFT_GL_HOST_CURRENT)", fn);
    if (position_offset % 4 || normal_offset % 4)
        return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: offsets %zu and %zu must be multiples of 4 bytes", fn,
                       position_offset, normal_offset);
    if (position_buffer && position_buffer == normal_buffer) {
        size_t bytes = 3 * sizeof(float) * (size_t)c->n_host;
        size_t lo = position_offset < normal_offset ? position_offset : normal_offset;
        size_t hi = position_offset < normal_offset ? normal_offset : position_offset;
        if (hi - lo < bytes)
            return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT,
                           "%s: the position and normal ranges of buffer %u overlap (offsets %zu and %zu, %zu bytes "
                           "each)", fn, position_buffer, position_offset, normal_offset, bytes);
    }
    if (!position_buffer && !normal_buffer) return wa_ok(ctx);
    weft_status st = wa_gl_begin(ctx, fn);
    if (st != WEFT_OK) return st;
    size_t need = 3 * sizeof(float) * (size_t)c->n_host;
    if (position_buffer) st = check_buffer(ctx, position_buffer, position_offset, need, "position_buffer", fn);
    if (st == WEFT_OK && normal_buffer) st = check_buffer(ctx, normal_buffer, normal_offset, need, "normal_buffer", fn);
    if (st == WEFT_OK)
        st = wa_gpu_vertices(ctx, c, space == WEFT_SPACE_OBJECT, NULL, NULL, position_buffer, position_offset,
                             normal_buffer, normal_offset, fn);
    wa_gl_end(ctx);
    return st == WEFT_OK ? wa_ok(ctx) : st;
}

#else /* !WEFT_HAVE_GPU */

weft_status wa_gl_context_new(weft_context* ctx, void** out, char* err, size_t err_len) {
    (void)ctx;
    *out = NULL;
    snprintf(err, err_len, "this libweft.so was built without WEFT_GPU");
    return WEFT_ERROR_UNSUPPORTED;
}

weft_status wa_gl_begin(weft_context* ctx, const char* fn) {
    return wa_fail(ctx, WEFT_ERROR_UNSUPPORTED, "%s: this libweft.so was built without WEFT_GPU", fn);
}
void wa_gl_end(weft_context* ctx) { (void)ctx; }
weft_status wa_gpu_context_init(weft_context* ctx, int only_hardware, int* software, char* err, size_t err_len) {
    (void)ctx, (void)only_hardware;
    *software = 0;
    snprintf(err, err_len, "this libweft.so was built without WEFT_GPU");
    return WEFT_ERROR_UNSUPPORTED;
}
void wa_gpu_context_release(weft_context* ctx) { (void)ctx; }
int wa_gpu_has_multigrid(const weft_context* ctx) {
    (void)ctx;
    return 0;
}
weft_status wa_gpu_cloth_create(weft_context* ctx, wa_cloth* c, const char* fn) {
    (void)c;
    return wa_gl_begin(ctx, fn);
}
void wa_gpu_cloth_destroy(wa_cloth* c) { (void)c; }
weft_status wa_gpu_download_raw(weft_context* ctx, wa_cloth* c, const char* fn) { return wa_gpu_cloth_create(ctx, c, fn); }
weft_status wa_gpu_upload_raw(weft_context* ctx, wa_cloth* c, const char* fn) { return wa_gpu_cloth_create(ctx, c, fn); }
weft_status wa_gpu_download(weft_context* ctx, wa_cloth* c, const char* fn) { return wa_gpu_cloth_create(ctx, c, fn); }
weft_status wa_gpu_upload(weft_context* ctx, wa_cloth* c, const char* fn) { return wa_gpu_cloth_create(ctx, c, fn); }
weft_status wa_gpu_transfer(wa_cloth* c, int upload, wc_diag* d) {
    (void)c, (void)upload;
    return wa_status(wc_fail(d, WC_ERROR_UNSUPPORTED, "this libweft.so was built without WEFT_GPU"));
}
void wa_gpu_backup(wa_cloth* c) { (void)c; }
void wa_gpu_restore_backup(wa_cloth* c) { (void)c; }
void wa_gpu_transform(wa_cloth* c, const double* Rx, const double* tx, const double* Rv, const double* dv) {
    (void)c, (void)Rx, (void)tx, (void)Rv, (void)dv;
}
weft_status wa_gpu_step_frame(wa_cloth* c, double dt, wc_step_stats* ss, wc_diag* d) {
    (void)c, (void)dt, (void)ss;
    return wa_status(wc_fail(d, WC_ERROR_UNSUPPORTED, "this libweft.so was built without WEFT_GPU"));
}
int wa_gpu_outputs_in_range(wa_cloth* c, const wa_xform* T, int* vertex, double* value, weft_status* st,
                            wc_diag* d) {
    *st = WEFT_OK;
    (void)d;
    return wa_outputs_in_range(c, T, vertex, value);
}
weft_status wa_gpu_vertices(weft_context* ctx, wa_cloth* c, int object, float* positions, float* normals,
                            unsigned position_buffer, size_t position_offset, unsigned normal_buffer,
                            size_t normal_offset, const char* fn) {
    (void)object, (void)positions, (void)normals, (void)position_buffer, (void)position_offset, (void)normal_buffer,
        (void)normal_offset;
    return wa_gpu_cloth_create(ctx, c, fn);
}
weft_status weft_cloth_write_gl_buffers(weft_context* ctx, weft_cloth cloth, weft_space space, unsigned position_buffer,
                                        size_t position_offset, unsigned normal_buffer, size_t normal_offset) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    (void)space, (void)position_buffer, (void)position_offset, (void)normal_buffer, (void)normal_offset;
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    if (!wa_lookup(ctx, cloth, "weft_cloth_write_gl_buffers")) return WEFT_ERROR_INVALID_HANDLE;
    return wa_fail(ctx, WEFT_ERROR_UNSUPPORTED, "weft_cloth_write_gl_buffers: this libweft.so was built without WEFT_GPU");
}

#endif
