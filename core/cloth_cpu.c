/* Core's CPU backend (cloth_backend.h): the frame is wc_step_frame on the cloth's own wc_state,
 * which is the truth (no mirror, no device, nothing to back up or transfer). Every default of
 * the def is the CPU's (docs/design/cloth.md "Defaults"): the multigrid preconditioner with the
 * first Newton solve to 1e-2, or below WC_CPU_IC0_BELOW particles block IC(0) with every solve to
 * the tolerance; the tolerance 1e-3 with backward Euler below WC_CPU_LOOSE_BELOW particles (its
 * error is the time step's, not the solves'; the second-order integrators' is not, they keep 1e-4,
 * as does a named preconditioner and a larger cloth: docs/bench/precond_by_size.md "The small
 * cloths' tolerance", "The multigrid cloths' tolerance"); two Newton iterations with line search,
 * self-collision on for a garment. */
#include <math.h>
#include <stdio.h>
#include "cloth_internal.h"
#include "vec3.h"

static wc_status device_create(const wc_device_desc* desc, void** out, int* software, char* info, size_t info_len) {
    (void)desc;
    *out = NULL;
    *software = 0;
    if (info_len) snprintf(info, info_len, "CPU");
    return WC_OK;
}

static wc_status device_destroy(void* device, wc_diag* d) {
    (void)device, (void)d;
    return WC_OK;
}

static void defaults(const void* device, const wc_defaults_query* q, wc_backend_defaults* out) {
    (void)device;
    const int small = q->n_particles < WC_CPU_IC0_BELOW;
    out->preconditioner = small ? WC_PRECOND_IC0 : WC_PRECOND_AMG;
    /* the pair: forcing 0 with the preconditioner chosen here, 1e-2 with a named one */
    out->newton_forcing = small && !q->preconditioner_named ? 0.0 : 1e-2;
    /* and the tolerance: 1e-3 for backward Euler with the preconditioner chosen here, to the sizes measured */
    const int loose = q->n_particles < WC_CPU_LOOSE_BELOW && !q->preconditioner_named;
    out->tolerance = loose && q->integrator == WC_INTEGRATOR_BE ? 1e-3 : 1e-4;
    out->newton_iterations = 2;
    out->line_search = 1;
    out->garment_self_collision = 1;
}

static wc_status begin(void* device, wc_diag* d) {
    (void)device, (void)d;
    return WC_OK;
}

static void end(void* device) { (void)device; }

/* the CPU runs every feature a def can ask for */
static wc_status supports(const void* device, const wc_backend_query* q, wc_diag* d) {
    (void)device, (void)q, (void)d;
    return WC_OK;
}

static wc_status create(wc_cloth* c, wc_diag* d) {
    (void)d;
    c->sim = NULL;
    return WC_OK;
}

static wc_status destroy(wc_cloth* c, wc_diag* d) {
    (void)c, (void)d;
    return WC_OK;
}

static wc_status step_frame(wc_cloth* c, double dt, wc_step_stats* st, wc_diag* d) {
    return wc_step_frame(c->state, dt, st, d);
}

/* the state is the whole backup (cloth_snapshot.c) */
static void backup(wc_cloth* c) { (void)c; }
static void restore_backup(wc_cloth* c) { (void)c; }

/* v <- V0 + R (v - V0) for n velocities */
static void rotate_relative(double* v, int n, const double* R, const double* V0) {
    for (int i = 0; i < n; ++i) {
        double d[3], o[3];
        v3_sub(d, v + 3 * i, V0);
        m3_mulv(o, R, d);
        v3_add(v + 3 * i, V0, o);
    }
}

/* The carry as separate passes over the state (cloth_backend.h wc_carry). */
static void carry(wc_cloth* c, const wc_carry* k) {
    wc_state* s = c->state;
    int n = c->model.n_particles;
    if (k->teleport) {
        for (int i = 0; i < n; ++i) wc_xform_point(&k->dT, s->x + 3 * i, s->x + 3 * i);
        wc_rotate_vectors(s->v, n, k->dT.R);
        wc_rotate_vectors(s->dv, n, k->dT.R);
        s->hist_valid = 0;   /* BDF2 restarts with a backward-Euler substep */
        return;
    }
    if (k->rotated) {
        wc_rotate_points(s->x, n, k->Rc, k->p0);
        if (s->hist_valid) wc_rotate_points(s->x_prev, n, k->Rc, k->p0);
        rotate_relative(s->v, n, k->Rc, k->V0);
        if (s->hist_valid) rotate_relative(s->v_prev, n, k->Rc, k->V0);
        wc_rotate_vectors(s->dv, n, k->Rc);
    }
    if (k->linear) {
        for (int i = 0; i < n; ++i) v3_axpy(s->v + 3 * i, k->clin, k->dV);
        if (s->hist_valid)
            for (int i = 0; i < n; ++i) {
                v3_axpy(s->v_prev + 3 * i, k->clin, k->dV);
                v3_axpy(s->x_prev + 3 * i, -k->clin * s->hist_h, k->dV);
            }
    }
}

static wc_status no_transfer(wc_cloth* c, wc_diag* d) {
    (void)c, (void)d;
    return WC_OK;
}

/* no bound: the range check reads the state's positions */
static double max_abs(wc_cloth* c) {
    (void)c;
    return INFINITY;
}

static wc_status output(wc_cloth* c, const wc_output_request* r, wc_diag* d) {
    (void)d;
    wc_cloth_host_vertices(c, r);
    return WC_OK;
}

static wc_status write_gl(wc_cloth* c, const wc_output_request* r, wc_diag* d) {
    (void)c, (void)r;
    return wc_fail(d, WC_ERROR_UNSUPPORTED,
                   "the cloth runs on the CPU backend (only GPU cloths write GL buffers; use weft_cloth_get_vertices)");
}

static wc_status read_gl(wc_cloth* c, int index, const wc_gl_vertex_source* src, float* out,
                         wc_gl_vertex_result* res, wc_diag* d) {
    (void)c, (void)index, (void)src, (void)out, (void)res;
    return wc_fail(d, WC_ERROR_UNSUPPORTED,
                   "the cloth runs on the CPU backend (only GPU cloths read the host's GL buffers; use "
                   "weft_cloth_set_mesh_collider_vertices)");
}

static void stats(const wc_cloth* c, wc_backend_stats* out) { (void)c, (void)out; }

static void mesh_pull(wc_cloth* c) { (void)c; }

const wc_cloth_backend wc_cloth_cpu = {
    .name = "CPU",
    .mirror = 0,
    .concurrent = 1,   /* a cloth's step touches its own state only */
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
    .download = no_transfer,
    .upload = no_transfer,
    .max_abs = max_abs,
    .output = output,
    .write_gl = write_gl,
    .stats = stats,
    .read_gl = read_gl,
    .mesh_pull = mesh_pull,
};
