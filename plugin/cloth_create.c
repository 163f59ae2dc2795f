/* Cloth creation, destruction, attachments and the info query: the def validated, converted to
 * core's wc_cloth_def, its model built, its backend chosen by the model (backend.c: AUTO by its
 * particle count; the def's DEFAULT choices resolved from that table), and the rest built by core
 * (core/cloth.h), which allocates everything a frame needs. */
#include <stdio.h>
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

/* The ABI's mesh description as core's. */
static wc_mesh_desc mesh_desc(const weft_mesh_desc* m, double unit_scale) {
    wc_mesh_desc o = {m->path, m->select, m->positions, m->n_vertices, m->face_sizes, m->n_faces, m->indices, unit_scale};
    return o;
}

/* Attachment defs as core's (out: n entries). */
static void attachment_defs(const weft_attachment_def* a, int n, wc_cloth_attachment_def* out) {
    for (int i = 0; i < n; ++i) {
        wc_cloth_attachment_def o = {a[i].vertices, a[i].n_vertices, a[i].bind_transform, a[i].free_axis};
        out[i] = o;
    }
}

static wc_sim_def sim_def_of(const weft_context* ctx, const weft_cloth_def* def) {
    wc_sim_def s = wc_default_sim_def();
    for (int k = 0; k < 3; ++k) {
        s.gravity[k] = def->gravity[k];
        s.air.wind[k] = def->wind[k];
    }
    s.air.normal_drag = def->air_drag_normal;
    s.air.tangent_drag = def->air_drag_tangent;
    s.solver.type = (wc_solver_type)def->solver; /* same numbering */
    if (def->tolerance >= 0) s.solver.tolerance = def->tolerance;   /* -1: the backend's, backend.c */
    s.solver.max_iterations = def->max_iterations;
    s.integrator = def->integrator == WEFT_INTEGRATOR_BDF2     ? WC_INTEGRATOR_BDF2
                   : def->integrator == WEFT_INTEGRATOR_TRBDF2 ? WC_INTEGRATOR_TRBDF2
                                                               : WC_INTEGRATOR_BE;
    s.self_thickness = def->self_collision_thickness;
    /* the backend's defaults (preconditioner, tolerance, Newton and its forcing, line search, self-collision)
       once it is chosen: backend.c */
    s.substeps = def->substeps;
    s.strain_limit = def->strain_limit;
    s.sleep_speed = def->sleep_speed;
    s.sleep_time = def->sleep_time;
    s.max_pins = 0;                       /* as many as particles: a particle is pinned at most once */
    s.max_colliders = def->n_colliders;
    s.threads = ctx->def.threads;
    return s;
}

static wc_model_def model_def_of(const weft_cloth_def* def) {
    wc_model_def md = wc_default_model_def();
    md.weld_tolerance = def->weld_tolerance;
    md.material.density = def->material.density;
    for (int k = 0; k < 3; ++k) {
        md.material.k[k] = def->material.stiffness[k];
        md.material.d[k] = def->material.damping[k];
    }
    md.material.k[WC_SPRING_SEAM] = def->sew_stiffness > 0 ? def->sew_stiffness : def->material.stiffness[0];
    md.material.d[WC_SPRING_SEAM] = def->material.damping[0];
    md.sew_distance = def->sew_distance;
    md.n_seam_pairs = def->n_seams;
    md.seam_a = def->seam_a;
    md.seam_b = def->seam_b;
    md.seam_close_time = def->seam_close_time;
    return md;
}

/* The def as core's, its arrays into the given ones (n_attachments, n_colliders and
 * n_mesh_colliders entries). */
static wc_cloth_def cloth_def_of(const weft_context* ctx, const weft_cloth_def* def, wc_cloth_attachment_def* att,
                                 wc_cloth_collider_def* col, wc_cloth_mesh_def* mesh) {
    wc_cloth_def o;
    memset(&o, 0, sizeof o);
    o.mesh = mesh_desc(&def->mesh, def->unit_scale);
    o.model = model_def_of(def);
    o.sim = sim_def_of(ctx, def);
    o.transform = def->transform;
    o.max_frame_time = def->max_frame_time;
    o.linear_inertia = def->linear_inertia;
    o.angular_inertia = def->angular_inertia;
    attachment_defs(def->attachments, def->n_attachments, att);
    o.attachments = att;
    o.n_attachments = def->n_attachments;
    for (int k = 0; k < def->n_colliders; ++k) {
        const weft_collider_def* c = &def->colliders[k];
        wc_cloth_collider_def q = {(int)c->type, c->radius, c->half_height, c->thickness, c->friction, c->transform};
        col[k] = q;   /* weft_collider_type and wc_collider_type share their numbering */
    }
    o.colliders = col;
    o.n_colliders = def->n_colliders;
    for (int k = 0; k < def->n_mesh_colliders; ++k) {
        const weft_mesh_collider_def* m = &def->mesh_colliders[k];
        wc_cloth_mesh_def q = {mesh_desc(&m->mesh, m->unit_scale), m->thickness, m->friction, m->push_speed,
                               m->transform};
        mesh[k] = q;
    }
    o.mesh_colliders = mesh;
    o.n_mesh_colliders = def->n_mesh_colliders;
    return o;
}

weft_status weft_cloth_create(weft_context* ctx, const weft_cloth_def* def, weft_cloth* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_create";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    out->id = 0;
    if (!def) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: def is NULL", fn);
    char msg[400];
    weft_status st = wa_validate_cloth_def(def, msg, sizeof msg);
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, msg);

    wc_cloth_attachment_def* att = WC_NEW(&ctx->alloc, wc_cloth_attachment_def, (size_t)def->n_attachments + 1);
    wc_cloth_collider_def* col = WC_NEW(&ctx->alloc, wc_cloth_collider_def, (size_t)def->n_colliders + 1);
    wc_cloth_mesh_def* mesh = WC_NEW(&ctx->alloc, wc_cloth_mesh_def, (size_t)def->n_mesh_colliders + 1);
    wc_cloth* c = NULL;
    wa_cloth_backend b;
    wc_diag d = wa_core_diag(ctx);
    if (!att || !col || !mesh) {
        st = wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    } else {
        wc_cloth_def cd = cloth_def_of(ctx, def, att, col, mesh);
        wc_status cs = wc_cloth_create_model(&c, &cd, &ctx->alloc, &d);
        if (cs == WC_OK) {   /* the backend by the model (AUTO: its particle count), then the rest */
            wa_backend_for_cloth(ctx, def, &c->model, &cd.sim, &b);
            cs = wc_cloth_create_rest(c, &cd, b.table, b.device, &d);
            if (cs != WC_OK) {
                (void)wc_cloth_destroy(c, NULL);
                c = NULL;
            }
        }
        if (cs != WC_OK) st = wa_fail_core(ctx, fn, cs, &d);
    }
    wc_free(&ctx->alloc, att);
    wc_free(&ctx->alloc, col);
    wc_free(&ctx->alloc, mesh);
    if (st != WEFT_OK) return st;
    if (!wa_register(ctx, c, out)) {
        wa_cloth_free(ctx, c);
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory (handle table)", fn);
    }
    wa_slot* slot = wa_slot_of(ctx, *out);
    slot->backend = b.backend;
    snprintf(slot->backend_reason, sizeof slot->backend_reason, "%s", b.reason);
    wa_log(ctx, WEFT_LOG_INFO, "%s: %d particles on the %s backend: %s", fn, c->model.n_particles, b.table->name, b.reason);
    for (int k = 0; k < c->model.report.n_warnings; ++k) wa_log(ctx, WEFT_LOG_WARN, "%s: %s", fn, c->model.report.warnings[k]);
    return wa_ok(ctx);
}

weft_status weft_cloth_destroy(weft_context* ctx, weft_cloth cloth) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, "weft_cloth_destroy");
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    wa_unregister(ctx, cloth);
    wa_cloth_free(ctx, c);
    return wa_ok(ctx);
}

weft_status weft_cloth_set_attachments(weft_context* ctx, weft_cloth cloth, const weft_attachment_def* attachments,
                                       int n) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_set_attachments";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (n < 0) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: n = %d is negative", fn, n);
    if (n > 0 && !attachments) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: attachments is NULL with n = %d", fn, n);
    char msg[400];
    weft_status st = wa_validate_attachments(attachments, n, c->n_host, "attachments", msg, sizeof msg);
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, msg);
    wc_cloth_attachment_def* att = WC_NEW(&ctx->alloc, wc_cloth_attachment_def, (size_t)n + 1);
    if (!att) return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    attachment_defs(attachments, n, att);
    wc_diag d = wa_core_diag(ctx);
    wc_status cs = wc_cloth_set_attachments(c, att, n, "attachments", &d);
    wc_free(&ctx->alloc, att);
    return cs == WC_OK ? wa_ok(ctx) : wa_fail_core(ctx, fn, cs, &d);
}

weft_status weft_cloth_get_info(weft_context* ctx, weft_cloth cloth, weft_cloth_info* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_info";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wc_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (!out) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: out is NULL", fn);
    const wc_model* m = &c->model;
    weft_cloth_info i;
    memset(&i, 0, sizeof i);
    i.n_vertices = c->n_host;
    i.n_particles = m->n_particles;
    i.n_triangles = m->n_tris;
    for (int t = 0; t < 3; ++t) i.n_springs[t] = m->spring_type_start[t + 1] - m->spring_type_start[t];
    i.n_attachments = c->n_attachments;
    i.n_pinned_particles = c->n_pins;
    i.n_colliders = c->n_colliders;
    i.total_mass = c->state->total_mass;
    for (int k = 0; k < 3; ++k) {
        i.bbox_min[k] = m->report.bbox_min[k];
        i.bbox_max[k] = m->report.bbox_max[k];
    }
    i.snapshot_size = c->snapshot_size;
    const wa_slot* slot = wa_slot_of(ctx, cloth);
    i.backend = slot->backend;
    const wc_sim_def* sd = &c->state->def;
    i.preconditioner = sd->solver.preconditioner == WC_PRECOND_AMG   ? WEFT_PRECOND_AMG
                       : sd->solver.preconditioner == WC_PRECOND_IC0 ? WEFT_PRECOND_IC0
                                                                     : WEFT_PRECOND_BLOCK_JACOBI;
    i.integrator = sd->integrator == WC_INTEGRATOR_BDF2     ? WEFT_INTEGRATOR_BDF2
                   : sd->integrator == WC_INTEGRATOR_TRBDF2 ? WEFT_INTEGRATOR_TRBDF2
                                                            : WEFT_INTEGRATOR_BACKWARD_EULER;
    i.newton_iterations = sd->newton_iterations;
    i.line_search = sd->line_search;
    i.n_seams = m->n_seams;
    i.n_panels = m->n_panels;
    i.self_collision = sd->self_collision;
    i.self_collision_thickness = sd->self_thickness;
    i.newton_forcing = sd->newton_forcing;
    i.tolerance = sd->solver.tolerance;
    i.threads = c->state->par.threads;
    snprintf(i.backend_reason, sizeof i.backend_reason, "%s", slot->backend_reason);
    *out = i;
    return wa_ok(ctx);
}
