/* Defaults of the cloth, attachment and collider defs and of the frame, and the validation of
 * the defs (every message names the offending field). Non-finite numbers are NONFINITE, values
 * outside their domain INVALID_ARGUMENT, vertex indices outside the mesh OUT_OF_RANGE. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "api_internal.h"

static void identity16(float* m) {
    memset(m, 0, 16 * sizeof(float));
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

weft_cloth_def weft_default_cloth_def(void) {
    weft_cloth_def d;
    memset(&d, 0, sizeof d);
    d.unit_scale = 1.0;
    d.weld_tolerance = 1e-6;
    identity16(d.transform);
    d.material.density = 0.15;
    d.material.stiffness[0] = 5000.0;
    d.material.stiffness[1] = 500.0;
    d.material.stiffness[2] = 50.0;
    d.material.damping[0] = 2.0;
    d.material.damping[1] = 0.5;
    d.material.damping[2] = 0.05;
    d.gravity[1] = -9.81;
    d.air_drag_normal = 0.5;
    d.air_drag_tangent = 0.02;
    d.solver = WEFT_SOLVER_PCG;
    d.tolerance = -1.0;
    d.max_iterations = 300;
    d.preconditioner = WEFT_PRECOND_DEFAULT;
    d.integrator = WEFT_INTEGRATOR_DEFAULT;
    d.newton_iterations = 0;
    d.line_search = -1;
    d.substeps = 1;
    d.max_frame_time = 0.25;
    d.strain_limit = 0.0;
    d.sleep_speed = 1e-3;
    d.sleep_time = 0.5;
    d.linear_inertia = 1.0;
    d.angular_inertia = 1.0;
    d.seam_close_time = 0.5;
    d.self_collision = -1;
    d.self_collision_thickness = 0.003;
    d.internal_cookie = WA_COOKIE_CLOTH;
    d.newton_forcing = -1.0;
    return d;
}

weft_attachment_def weft_default_attachment_def(void) {
    weft_attachment_def d;
    memset(&d, 0, sizeof d);
    identity16(d.bind_transform);
    d.internal_cookie = WA_COOKIE_ATTACHMENT;
    return d;
}

weft_collider_def weft_default_collider_def(void) {
    weft_collider_def d;
    memset(&d, 0, sizeof d);
    d.type = WEFT_COLLIDER_SPHERE;
    d.radius = 0.5;
    d.half_height = 0.5;
    d.thickness = 0.005;
    d.friction = 0.3;
    identity16(d.transform);
    d.internal_cookie = WA_COOKIE_COLLIDER;
    return d;
}

weft_frame weft_default_frame(void) {
    weft_frame f;
    memset(&f, 0, sizeof f);
    f.dt = 1.0 / 60.0;
    return f;
}

/* failure helpers: write the message, return the status */
#define FAIL(st, ...) return (snprintf(msg, msg_size, __VA_ARGS__), (st))

/* value must be finite and in [lo, hi] (hi may be INFINITY: then finite is enough) */
static weft_status check_range(double v, double lo, double hi, int lo_open, const char* name, char* msg,
                               size_t msg_size) {
    if (!isfinite(v)) FAIL(WEFT_ERROR_NONFINITE, "%s is %s", name, isnan(v) ? "NaN" : "Inf");
    if (v < lo || (lo_open && v == lo) || v > hi)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s = %g must be in %c%g, %g]", name, v, lo_open ? '(' : '[', lo, hi);
    return WEFT_OK;
}

#define RANGE(v, lo, hi, open, ...)                                                   \
    do {                                                                              \
        char name_[96];                                                               \
        snprintf(name_, sizeof name_, __VA_ARGS__);                                   \
        weft_status st_ = check_range((v), (lo), (hi), (open), name_, msg, msg_size); \
        if (st_ != WEFT_OK) return st_;                                               \
    } while (0)

#define XFORM(m, ...)                                                                  \
    do {                                                                               \
        char why_[160], name_[96];                                                     \
        weft_status st_ = wa_check_transform((m), why_, sizeof why_);                  \
        if (st_ != WEFT_OK) {                                                          \
            snprintf(name_, sizeof name_, __VA_ARGS__);                                \
            FAIL(st_, "%s%s", name_, why_);                                            \
        }                                                                              \
    } while (0)

weft_status wa_validate_cloth_def(const weft_cloth_def* d, char* msg, size_t msg_size) {
    if (d->internal_cookie != WA_COOKIE_CLOTH)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def was not initialised by weft_default_cloth_def() (internal_cookie)");
    const weft_mesh_desc* m = &d->mesh;
    if (m->path && m->positions)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh: both path and positions are set (give one source)");
    if (!m->path && !m->positions)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh: neither path nor positions is set");
    if (m->path && m->path[0] == '\0') FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.path is empty");
    if (m->positions) {
        if (m->n_vertices < 1) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.n_vertices = %d must be >= 1", m->n_vertices);
        if (m->n_faces < 1) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.n_faces = %d must be >= 1", m->n_faces);
        if (!m->face_sizes) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.face_sizes is NULL");
        if (!m->indices) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.indices is NULL");
        for (int i = 0; i < 3 * m->n_vertices; ++i)
            if (!isfinite(m->positions[i]))
                FAIL(WEFT_ERROR_NONFINITE, "def->mesh.positions[%d] (vertex %d) is %s", i, i / 3,
                     isnan(m->positions[i]) ? "NaN" : "Inf");
        long long total = 0;
        for (int f = 0; f < m->n_faces; ++f) {
            if (m->face_sizes[f] < 1)
                FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.face_sizes[%d] = %d must be >= 1", f, m->face_sizes[f]);
            total += m->face_sizes[f];
            if (total > 0x7fffffffLL) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->mesh.face_sizes: too many corners");
        }
        for (long long k = 0; k < total; ++k)
            if (m->indices[k] < 0 || m->indices[k] >= m->n_vertices)
                FAIL(WEFT_ERROR_OUT_OF_RANGE, "def->mesh.indices[%lld] = %d is outside [0, %d)", k, m->indices[k],
                     m->n_vertices);
    }
    RANGE(d->unit_scale, 0.0, 1e12, 1, "def->unit_scale");
    RANGE(d->weld_tolerance, 0.0, 1.0, 0, "def->weld_tolerance");
    XFORM(d->transform, "def->transform");
    RANGE(d->material.density, 0.0, INFINITY, 1, "def->material.density");
    for (int k = 0; k < 3; ++k) {
        RANGE(d->material.stiffness[k], 0.0, INFINITY, 0, "def->material.stiffness[%d]", k);
        RANGE(d->material.damping[k], 0.0, INFINITY, 0, "def->material.damping[%d]", k);
    }
    for (int k = 0; k < 3; ++k) {
        RANGE(d->gravity[k], -INFINITY, INFINITY, 0, "def->gravity[%d]", k);
        RANGE(d->wind[k], -INFINITY, INFINITY, 0, "def->wind[%d]", k);
    }
    RANGE(d->sew_distance, 0.0, INFINITY, 0, "def->sew_distance");
    RANGE(d->sew_stiffness, 0.0, INFINITY, 0, "def->sew_stiffness");
    RANGE(d->seam_close_time, 0.0, INFINITY, 0, "def->seam_close_time");
    if (d->n_seams < 0) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->n_seams = %d must be >= 0", d->n_seams);
    if (d->n_seams > 0 && (!d->seam_a || !d->seam_b))
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->n_seams = %d but def->seam_%c is NULL", d->n_seams, d->seam_a ? 'b' : 'a');
    for (int k = 0; k < d->n_seams; ++k) {
        if (d->seam_a[k] == d->seam_b[k])
            FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->seam_a[%d] = def->seam_b[%d] = %d: a vertex cannot be sewn to itself",
                 k, k, d->seam_a[k]);
        for (int s = 0; s < 2 && m->positions; ++s) {
            int v = s ? d->seam_b[k] : d->seam_a[k];
            if (v < 0 || v >= m->n_vertices)
                FAIL(WEFT_ERROR_OUT_OF_RANGE, "def->seam_%c[%d] = %d is outside [0, %d)", s ? 'b' : 'a', k, v, m->n_vertices);
        }
    }
    RANGE(d->air_drag_normal, 0.0, INFINITY, 0, "def->air_drag_normal");
    RANGE(d->air_drag_tangent, 0.0, INFINITY, 0, "def->air_drag_tangent");
    if ((unsigned)d->solver > WEFT_SOLVER_DIRECT)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->solver = %d is not a weft_solver", (int)d->solver);
    if (!isfinite(d->tolerance)) FAIL(WEFT_ERROR_NONFINITE, "def->tolerance is not finite");
    if (d->tolerance != -1.0 && !(d->tolerance >= 0 && d->tolerance < 1))
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->tolerance = %g must be -1 (default) or in [0, 1)", d->tolerance);
    if (d->max_iterations < 1) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->max_iterations = %d must be >= 1", d->max_iterations);
    if ((unsigned)d->preconditioner > WEFT_PRECOND_IC0)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->preconditioner = %d is not a weft_preconditioner", (int)d->preconditioner);
    if ((unsigned)d->integrator > WEFT_INTEGRATOR_TRBDF2)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->integrator = %d is not a weft_integrator", (int)d->integrator);
    if (d->newton_iterations < 0 || d->newton_iterations > 100)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->newton_iterations = %d must be in [0, 100] (0: default)",
             d->newton_iterations);
    if (d->line_search < -1 || d->line_search > 1)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->line_search = %d must be -1 (default), 0 or 1", d->line_search);
    if (!isfinite(d->newton_forcing)) FAIL(WEFT_ERROR_NONFINITE, "def->newton_forcing is not finite");
    if (d->newton_forcing != -1.0 && !(d->newton_forcing >= 0 && d->newton_forcing < 1))
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->newton_forcing = %g must be -1 (default) or in [0, 1)",
             d->newton_forcing);
    if (d->substeps < 1 || d->substeps > 100000)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->substeps = %d must be in [1, 100000]", d->substeps);
    RANGE(d->max_frame_time, 0.0, 1000.0, 1, "def->max_frame_time");
    RANGE(d->strain_limit, 0.0, INFINITY, 0, "def->strain_limit");
    RANGE(d->sleep_speed, 0.0, INFINITY, 0, "def->sleep_speed");
    RANGE(d->sleep_time, 0.0, INFINITY, 0, "def->sleep_time");
    RANGE(d->linear_inertia, 0.0, 1.0, 0, "def->linear_inertia");
    RANGE(d->angular_inertia, 0.0, 1.0, 0, "def->angular_inertia");
    if (d->self_collision < -1 || d->self_collision > 1)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->self_collision = %d must be -1 (default), 0 or 1", d->self_collision);
    RANGE(d->self_collision_thickness, 0.0, INFINITY, 1, "def->self_collision_thickness");
    if (d->n_attachments < 0) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->n_attachments = %d is negative", d->n_attachments);
    if (d->n_attachments > 0 && !d->attachments)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->attachments is NULL with n_attachments = %d", d->n_attachments);
    if (d->n_colliders < 0) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->n_colliders = %d is negative", d->n_colliders);
    if (d->n_colliders > 0 && !d->colliders)
        FAIL(WEFT_ERROR_INVALID_ARGUMENT, "def->colliders is NULL with n_colliders = %d", d->n_colliders);
    weft_status st = wa_validate_attachments(d->attachments, d->n_attachments, m->positions ? m->n_vertices : -1,
                                             "def->attachments", msg, msg_size);
    if (st != WEFT_OK) return st;
    st = wa_validate_mesh_colliders(d->mesh_colliders, d->n_mesh_colliders, msg, msg_size);
    if (st != WEFT_OK) return st;
    return wa_validate_colliders(d->colliders, d->n_colliders, "def->colliders", msg, msg_size);
}

weft_status wa_validate_attachments(const weft_attachment_def* a, int n, int n_host, const char* prefix, char* msg,
                                    size_t msg_size) {
    for (int i = 0; i < n; ++i) {
        const weft_attachment_def* d = &a[i];
        if (d->internal_cookie != WA_COOKIE_ATTACHMENT)
            FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d] was not initialised by weft_default_attachment_def() (internal_cookie)",
                 prefix, i);
        if (d->n_vertices < 0) FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].n_vertices = %d is negative", prefix, i, d->n_vertices);
        if (d->n_vertices > 0 && !d->vertices)
            FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].vertices is NULL with n_vertices = %d", prefix, i, d->n_vertices);
        if (n_host >= 0)
            for (int k = 0; k < d->n_vertices; ++k)
                if (d->vertices[k] < 0 || d->vertices[k] >= n_host)
                    FAIL(WEFT_ERROR_OUT_OF_RANGE, "%s[%d].vertices[%d] = %d is outside [0, %d)", prefix, i, k,
                         d->vertices[k], n_host);
        XFORM(d->bind_transform, "%s[%d].bind_transform", prefix, i);
        for (int k = 0; k < 3; ++k)
            if (!isfinite(d->free_axis[k])) FAIL(WEFT_ERROR_NONFINITE, "%s[%d].free_axis[%d] is not finite", prefix, i, k);
        double len = sqrt((double)d->free_axis[0] * d->free_axis[0] + (double)d->free_axis[1] * d->free_axis[1] +
                          (double)d->free_axis[2] * d->free_axis[2]);
        if (len != 0.0 && fabs(len - 1.0) > 1e-3)
            FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].free_axis must be zero or a unit vector (length %g)", prefix, i, len);
    }
    return WEFT_OK;
}

weft_status wa_validate_colliders(const weft_collider_def* c, int n, const char* prefix, char* msg, size_t msg_size) {
    for (int i = 0; i < n; ++i) {
        const weft_collider_def* d = &c[i];
        if (d->internal_cookie != WA_COOKIE_COLLIDER)
            FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d] was not initialised by weft_default_collider_def() (internal_cookie)",
                 prefix, i);
        if ((unsigned)d->type > WEFT_COLLIDER_CAPSULE)
            FAIL(WEFT_ERROR_INVALID_ARGUMENT, "%s[%d].type = %d is not a weft_collider_type", prefix, i, (int)d->type);
        /* a field the type does not use must still be finite: a NaN there is a host bug */
        if (d->type != WEFT_COLLIDER_PLANE) RANGE(d->radius, 0.0, INFINITY, 1, "%s[%d].radius", prefix, i);
        else RANGE(d->radius, -INFINITY, INFINITY, 0, "%s[%d].radius (unused by a plane)", prefix, i);
        if (d->type == WEFT_COLLIDER_CAPSULE) RANGE(d->half_height, 0.0, INFINITY, 0, "%s[%d].half_height", prefix, i);
        else RANGE(d->half_height, -INFINITY, INFINITY, 0, "%s[%d].half_height (unused by this type)", prefix, i);
        RANGE(d->thickness, 0.0, INFINITY, 0, "%s[%d].thickness", prefix, i);
        RANGE(d->friction, 0.0, INFINITY, 0, "%s[%d].friction", prefix, i);
        XFORM(d->transform, "%s[%d].transform", prefix, i);
    }
    return WEFT_OK;
}
