/* The GPU backend's table (wg_backend.h): every operation is a wg_sim call inside the device's
 * wg_gl_begin/end. The rigid carry is one wg_sim_transform pass (x' = Rx x + tx, v' = Rv v + dv,
 * the warm start turning with v), composed here from core's wc_carry; the range bound is the
 * GPU's max |coordinate| (one small read-back). */
#include <GL/glew.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cloth.h"
#include "gpu_error.h"
#include "vec3.h"
#include "wg_backend.h"
#include "wg_device.h"
#include "wg_host_buffer.h"
#include "wg_mesh.h"
#include "wg_sim.h"

typedef struct wg_backend_device {
    wg_gl_context* gl;
    wg_device* dev;
    int host_gl;                /* the host's GL context: its buffer names mean something here */
    wc_allocator alloc;
} wg_backend_device;

#define DEV(device) ((wg_backend_device*)(device))
#define SIM(c) ((wg_sim*)(c)->sim)

wg_gl_context* wg_backend_gl_context(void* device) { return device ? DEV(device)->gl : NULL; }

const char* wg_backend_renderer(const void* device, int* software) {
    const wg_backend_device* bd = device;
    *software = bd->dev->software;
    return bd->dev->renderer;
}

/* ---- the device ------------------------------------------------------------------------------ */

static wc_status device_create(const wc_device_desc* desc, void** out, int* software, char* info, size_t info_len) {
    *out = NULL;
    *software = 0;
    wg_gl_context_desc gd;
    memset(&gd, 0, sizeof gd);
    gd.host_current = desc->host_gl;
    gd.log = desc->log;
    gd.log_user = desc->log_user;
    gd.allocator = desc->allocator;
    wg_gl_context* gl = NULL;
    wc_status st = wg_gl_context_create(&gd, &gl, info, info_len);
    if (st != WC_OK) return st;
    /* only hardware: a software rasteriser is known from the renderer string already; the
     * programs are not compiled for nothing */
    if (desc->only_hardware && wg_renderer_is_software(wg_gl_context_description(gl))) {
        *software = 1;
        snprintf(info, info_len, "%s", wg_gl_context_renderer(gl));
        wg_gl_context_destroy(gl);
        return WC_OK;
    }
    wg_backend_device* bd = wc_calloc(&desc->allocator, 1, sizeof *bd);
    if (!bd) {
        snprintf(info, info_len, "out of memory");
        wg_gl_context_destroy(gl);
        return WC_ERROR_OUT_OF_MEMORY;
    }
    st = wg_gl_begin(gl, info, info_len);
    wg_device* dev = NULL;
    if (st == WC_OK) {
        st = wg_device_create(gl, &dev, info, info_len);
        if (st == WC_OK && desc->only_hardware && dev->software) {
            *software = 1;
            snprintf(info, info_len, "%s", dev->renderer);
            wg_device_destroy(dev);
            dev = NULL;
        }
        wg_gl_end(gl);
    }
    if (st != WC_OK || !dev) {
        wc_free(&desc->allocator, bd);
        wg_gl_context_destroy(gl);
        return st;
    }
    bd->gl = gl;
    bd->dev = dev;
    bd->host_gl = desc->host_gl;
    bd->alloc = desc->allocator;
    *out = bd;
    snprintf(info, info_len, "%s%s", dev->renderer, dev->compute ? " (compute-shader passes)" : " (fragment-shader passes)");
    return WC_OK;
}

static wc_status device_destroy(void* device, wc_diag* d) {
    if (!device) return WC_OK;
    wg_backend_device* bd = DEV(device);
    char err[512] = "";
    wc_status st = WC_OK;
    if (wg_gl_begin(bd->gl, err, sizeof err) == WC_OK) {
        wg_device_destroy(bd->dev);
        wg_gl_end(bd->gl);
    } else {
        /* the host's context is not current: its GL objects die with that context */
        st = wc_fail(d, WC_ERROR_GPU, "GPU device's GL objects left to the host's context (%s)", err);
        wg_device_forget(bd->dev);
    }
    wg_gl_context_destroy(bd->gl);
    wc_allocator a = bd->alloc;
    wc_free(&a, bd);
    return st;
}

/* The multigrid preconditioner where the passes are compute shaders (block Jacobi on fragment
 * passes); the CPU's method: two Newton iterations with the line search (a few read-backs a
 * substep; one linearised step rolls back where the CPU's method does not: docs/design/gpu.md);
 * self-collision on for a garment, as on the CPU (core's stage on the host, wg_self.h). */
static void defaults(const void* device, const wc_defaults_query* q, wc_backend_defaults* out) {
    const wg_backend_device* bd = device;
    (void)q;   /* the same at every size */
    out->preconditioner = bd && bd->dev->compute ? WC_PRECOND_AMG : WC_PRECOND_BLOCK_JACOBI;
    out->newton_forcing = 1e-2;
    out->tolerance = 1e-4;
    out->newton_iterations = 2;
    out->line_search = 1;
    out->garment_self_collision = 1;
}

static wc_status begin(void* device, wc_diag* d) {
    char err[512] = "";
    wc_status st = wg_gl_begin(DEV(device)->gl, err, sizeof err);
    return st == WC_OK ? st : wc_fail(d, st, "GPU backend: %s", err);
}

static void end(void* device) { wg_gl_end(DEV(device)->gl); }

/* ---- one cloth ------------------------------------------------------------------------------- */

static wc_status supports(const void* device, const wc_backend_query* q, wc_diag* d) {
    const wg_backend_device* bd = device;
    wc_status st = wg_sim_supports(bd->dev, q->model, q->sim, q->n_mesh_colliders, d);
    return st == WC_OK ? st : wc_diag_prefix(d, st, "GPU backend: ");
}

static wc_status create(wc_cloth* c, wc_diag* d) {
    wc_status st = begin(c->device, d);
    if (st != WC_OK) return st;
    wg_sim* g = NULL;
    st = wg_sim_create(DEV(c->device)->dev, c->state, c->host_rest, &g, d);
    end(c->device);
    if (st != WC_OK) return wc_diag_prefix(d, st, "GPU backend: ");
    c->sim = g;
    return WC_OK;
}

static wc_status destroy(wc_cloth* c, wc_diag* d) {
    if (!c->sim) return WC_OK;
    wg_gl_context* gl = DEV(c->device)->gl;
    char err[512] = "";
    wc_status st = WC_OK;
    if (wg_gl_begin(gl, err, sizeof err) == WC_OK) {
        wg_sim_destroy(SIM(c));
        wg_gl_end(gl);
    } else {
        /* the host's context is not current: its GL objects go with that context */
        st = wc_fail(d, WC_ERROR_GPU, "GPU cloth's GL objects left to the host's context (%s)", err);
        wg_sim_forget(SIM(c));
    }
    c->sim = NULL;
    return st;
}

static wc_status step_frame(wc_cloth* c, double dt, wc_step_stats* st, wc_diag* d) {
    return wg_sim_step_frame(SIM(c), c->state, dt, st, d);
}

static void backup(wc_cloth* c) { wg_sim_backup(SIM(c)); }

/* the textures back, then the mirror from them (the sleep state's strain is measured on it) */
static void restore_backup(wc_cloth* c) {
    wg_sim_restore_backup(SIM(c));
    wc_diag quiet;
    memset(&quiet, 0, sizeof quiet);
    (void)wg_sim_download(SIM(c), c->state, &quiet);
}

/* One pass: teleport x' = dT x, v' = dT.R v (BDF2's history dropped); inertia
 * x' = Rc x + (p0 - Rc p0), v' = Rc v + (V0 - Rc V0) + clin dV, and a second pass for BDF2's
 * history when it is valid. */
static void carry(wc_cloth* c, const wc_carry* k) {
    const double zero[3] = {0.0, 0.0, 0.0};
    if (k->teleport) {
        wg_sim_transform(SIM(c), k->dT.R, k->dT.t, k->dT.R, zero);
        c->state->hist_valid = 0;   /* BDF2 restarts with a backward-Euler substep */
        return;
    }
    double Rx[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, tx[3] = {0.0, 0.0, 0.0}, dv[3] = {0.0, 0.0, 0.0};
    if (k->rotated) {
        double q[3];
        memcpy(Rx, k->Rc, sizeof Rx);
        m3_mulv(q, k->Rc, k->p0);
        v3_sub(tx, k->p0, q);
        m3_mulv(q, k->Rc, k->V0);
        v3_sub(dv, k->V0, q);
    }
    if (k->linear) v3_axpy(dv, k->clin, k->dV);
    wg_sim_transform(SIM(c), Rx, tx, Rx, dv);
    if (c->state->hist_valid) {
        /* BDF2's history as x and v, and as if the cloth had always moved that much faster:
           x_prev -= hist_h clin dV (cloth_backend.h wc_carry) */
        if (k->linear) v3_axpy(tx, -k->clin * c->state->hist_h, k->dV);
        wg_sim_transform_history(SIM(c), Rx, tx, Rx, dv);
    }
}

static wc_status download(wc_cloth* c, wc_diag* d) { return wg_sim_download(SIM(c), c->state, d); }
static wc_status upload(wc_cloth* c, wc_diag* d) { return wg_sim_upload(SIM(c), c->state, d); }
static double max_abs(wc_cloth* c) { return wg_sim_max_abs(SIM(c)); }

/* r's arrays or buffers from the output passes (object space with the cloth's transform) */
static wc_status output(wc_cloth* c, const wc_output_request* r, wc_diag* d) {
    wg_output_request q;
    memset(&q, 0, sizeof q);
    q.to_object = r->to_object;
    memcpy(q.R, c->object.R, sizeof q.R);
    memcpy(q.t, c->object.t, sizeof q.t);
    q.unit_scale = c->settings.unit_scale;
    q.positions = r->positions;
    q.normals = r->normals;
    q.position_buffer = r->position_buffer;
    q.normal_buffer = r->normal_buffer;
    q.position_offset = r->position_offset;
    q.normal_offset = r->normal_offset;
    return wg_sim_output(SIM(c), &q, d);
}

#define PER_VERTEX "3 floats per host vertex"
#define HEADLESS_REFUSAL                                                                                        \
    "the context is WEFT_GL_HEADLESS: its GL context is Weft's own, so the host's buffer names mean nothing " \
    "there (create the context with WEFT_GL_HOST_CURRENT)"

static wc_status write_gl(wc_cloth* c, const wc_output_request* r, wc_diag* d) {
    if (!DEV(c->device)->host_gl) return wc_fail(d, WC_ERROR_UNSUPPORTED, HEADLESS_REFUSAL);
    if (r->position_offset % 4 || r->normal_offset % 4)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "offsets %zu and %zu must be multiples of 4 bytes",
                       r->position_offset, r->normal_offset);
    const size_t need = 3 * sizeof(float) * (size_t)c->n_host;
    if (r->position_buffer && r->position_buffer == r->normal_buffer) {
        size_t lo = r->position_offset < r->normal_offset ? r->position_offset : r->normal_offset;
        size_t hi = r->position_offset < r->normal_offset ? r->normal_offset : r->position_offset;
        if (hi - lo < need)
            return wc_fail(d, WC_ERROR_INVALID_ARGUMENT,
                           "the position and normal ranges of buffer %u overlap (offsets %zu and %zu, %zu bytes each)",
                           r->position_buffer, r->position_offset, r->normal_offset, need);
    }
    if (!r->position_buffer && !r->normal_buffer) return WC_OK;
    wc_status st = begin(c->device, d);
    if (st != WC_OK) return st;
    if (r->position_buffer)
        st = wg_host_buffer_check(r->position_buffer, r->position_offset, need, "position_buffer", PER_VERTEX, d);
    if (st == WC_OK && r->normal_buffer)
        st = wg_host_buffer_check(r->normal_buffer, r->normal_offset, need, "normal_buffer", PER_VERTEX, d);
    if (st == WC_OK) st = output(c, r, d);
    end(c->device);
    return st;
}

/* a deforming body's vertices from a host buffer: the range checked, then kept on the GPU where
   the passes move bodies (compute), else read back */
static wc_status read_gl(wc_cloth* c, int index, const wc_gl_vertex_source* src, float* out, wc_gl_vertex_result* res,
                         wc_diag* d) {
    if (!DEV(c->device)->host_gl) return wc_fail(d, WC_ERROR_UNSUPPORTED, HEADLESS_REFUSAL);
    const size_t need = (size_t)(src->n - 1) * src->stride + 3 * sizeof(float);
    wc_status st = begin(c->device, d);
    if (st != WC_OK) return st;
    st = wg_host_buffer_check(src->buffer, src->offset, need, "buffer", "3 floats per body vertex at the stride", d);
    wg_mesh* mesh = wg_sim_mesh(SIM(c));
    res->taken = 0;
    if (st == WC_OK && mesh && mesh->body) {
        wc_diag quiet = *d;
        quiet.log = NULL;
        glGetError();
        st = wg_mesh_body_take(mesh, index, src->buffer, src->offset, src->stride, &res->bad_vertex, res->bad,
                               &res->moves, &quiet);
        GLenum e = glGetError();
        if (st == WC_OK && e != GL_NO_ERROR) st = wc_fail(&quiet, WC_ERROR_GPU, "GL error %s", wg_gl_error_name(e));
        res->taken = st == WC_OK;
        if (st == WC_ERROR_UNSUPPORTED) st = WC_OK;   /* too long a range for the texture: read back below */
        else if (st != WC_OK) st = wc_fail(d, st, "%s", quiet.message);
    }
    if (st == WC_OK && !res->taken)
        st = wg_sim_read_host_vertices(SIM(c), src->buffer, src->offset, src->stride, src->n, out, d);
    end(c->device);
    return st;
}

static void mesh_pull(wc_cloth* c) { wg_mesh_body_pull(wg_sim_mesh(SIM(c))); }

static void stats(const wc_cloth* c, wc_backend_stats* out) {
    out->device_bytes = wg_sim_gpu_bytes(SIM(c));
    out->passes = wg_sim_debug_passes(SIM(c));
}

const wc_cloth_backend wg_cloth_backend = {
    .name = "GPU",
    .mirror = 1,
    .concurrent = 0,   /* one GL context: its passes run one cloth after the other */
    .device_create = device_create,
    .device_destroy = device_destroy,
    .defaults = defaults,
    .begin = begin,
    .end = end,
    .supports = supports,
    .create = create,
    .destroy = destroy,
    .step_frame = step_frame,
    .backup = backup,
    .restore_backup = restore_backup,
    .carry = carry,
    .download = download,
    .upload = upload,
    .max_abs = max_abs,
    .output = output,
    .write_gl = write_gl,
    .stats = stats,
    .read_gl = read_gl,
    .mesh_pull = mesh_pull,
};
