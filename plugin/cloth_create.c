/* Cloth creation (def -> host mesh -> wc_model -> wc_state, attachments bound, colliders placed),
 * destruction and the info query. Everything a frame needs is allocated here (and in
 * weft_cloth_set_attachments): weft_cloth_step allocates nothing. */
#include <string.h>
#include "api_internal.h"

void wa_cloth_free(wa_cloth* c) {
    if (!c) return;
    wc_allocator a = c->ctx->alloc;
    wa_gpu_cloth_destroy(c);   /* inside the context's GL context */
    wc_state_destroy(c->state);
    wa_free_mesh_colliders(c); /* after the state, which borrowed them */
    wc_model_free(&c->model);
    void* arrays[] = {c->host_rest, c->attachments, c->attachment_xf, c->attachment_next, c->pin_particle,
                      c->pin_attachment, c->pin_local, c->pins, c->colliders, c->collider_xf, c->collider_next,
                      c->wc_colliders, c->scratch, c->mark, c->backup};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i) wc_free(&a, arrays[i]);
    wc_free(&a, c);
}

/* The host mesh from the def's file or arrays (positions float -> double, times unit_scale). */
static weft_status read_mesh(weft_context* ctx, const weft_cloth_def* def, wc_source_mesh* src, const char* fn) {
    wc_diag d = wa_core_diag(ctx);
    weft_status st;
    if (def->mesh.path) {
        wc_import_opts o = wc_default_import_opts();
        o.scale = def->unit_scale;
        o.select = def->mesh.select;
        st = wa_status(wc_import_file(src, &ctx->alloc, def->mesh.path, &o, &d));
    } else {
        int n = def->mesh.n_vertices;
        double* pos = WC_NEW(&ctx->alloc, double, 3 * (size_t)n);
        if (!pos) return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory (%d vertices)", fn, n);
        for (int i = 0; i < 3 * n; ++i) pos[i] = (double)def->mesh.positions[i];
        st = wa_status(wc_source_mesh_from_arrays(src, &ctx->alloc, pos, n, def->mesh.face_sizes, def->mesh.n_faces,
                                        def->mesh.indices, def->unit_scale, &d));
        wc_free(&ctx->alloc, pos);
    }
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: def->mesh: %s", fn, d.message);
    return WEFT_OK;
}

/* The backends' defaults for the DEFAULT / 0 / -1 choices of the def (README "Defaults", where
 * the measurements behind them are). CPU: the multigrid preconditioner, backward Euler, two
 * Newton iterations with line search (zero rollbacks over 90 frames on five of the six sample
 * scenes, one on the sixth; one Baraff-Witkin step rolls back 19 times on the hanging sheet).
 * GPU: its own multigrid on compute-shader passes (every sample scene's solves converge, in 1.1-2.2x
 * less time on llvmpipe but the skirt's; README "The GPU's multigrid"), block Jacobi on fragment
 * passes; one backward-Euler step without search, all it has. */
static void resolve_defaults(const weft_context* ctx, const weft_cloth_def* def, wc_sim_def* s) {
    int gpu = ctx->backend == WEFT_BACKEND_GPU;
    s->solver.preconditioner = def->preconditioner == WEFT_PRECOND_AMG            ? WC_PRECOND_AMG
                               : def->preconditioner == WEFT_PRECOND_BLOCK_JACOBI ? WC_PRECOND_BLOCK_JACOBI
                               : gpu && !wa_gpu_has_multigrid(ctx)               ? WC_PRECOND_BLOCK_JACOBI
                                                                                  : WC_PRECOND_AMG;
    s->integrator = def->integrator == WEFT_INTEGRATOR_BDF2     ? WC_INTEGRATOR_BDF2
                    : def->integrator == WEFT_INTEGRATOR_TRBDF2 ? WC_INTEGRATOR_TRBDF2
                                                                : WC_INTEGRATOR_BE;
    s->newton_iterations = def->newton_iterations > 0 ? def->newton_iterations : gpu ? 1 : 2;
    s->line_search = def->line_search >= 0 ? def->line_search : gpu ? 0 : 1;
    /* self-collision: on the CPU, on by default for a garment (a cloth with a body, i.e. a mesh
       collider, or with seams), where crossings are what a user sees first and the frame already
       pays for collision; off otherwise (it costs 10-20% of a one-thread frame on a cloth that
       does not touch itself, README "Self-collision"). GPU: off (it has no self-collision). */
    int garment = def->n_mesh_colliders > 0 || def->sew_distance > 0 || def->n_seams > 0;
    s->self_collision = def->self_collision >= 0 ? def->self_collision : !gpu && garment;
    s->self_thickness = def->self_collision_thickness;
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
    s.solver.tolerance = def->tolerance;
    s.solver.max_iterations = def->max_iterations;
    resolve_defaults(ctx, def, &s);
    s.substeps = def->substeps;
    s.strain_limit = def->strain_limit;
    s.sleep_speed = def->sleep_speed;
    s.sleep_time = def->sleep_time;
    s.max_pins = 0;                       /* as many as particles: a particle is pinned at most once */
    s.max_colliders = def->n_colliders;
    s.threads = ctx->def.threads;
    return s;
}

/* Everything after the model: state, initial positions, colliders, attachments, backup. */
static weft_status build_cloth(weft_context* ctx, wa_cloth* c, const weft_cloth_def* def, const char* fn) {
    const wc_model* m = &c->model;
    int n = m->n_particles;
    wc_allocator* A = &ctx->alloc;
    c->scratch = WC_NEW(A, double, 3 * (size_t)n);
    c->mark = WC_NEW(A, int, (size_t)n);
    int nc = def->n_colliders;
    c->colliders = WC_NEW(A, wa_collider, (size_t)nc + 1);
    c->collider_xf = WC_NEW(A, wa_xform, (size_t)nc + 1);
    c->collider_next = WC_NEW(A, wa_xform, (size_t)nc + 1);
    c->wc_colliders = WC_NEW(A, wc_collider, (size_t)nc + 1);
    if (!c->scratch || !c->mark || !c->colliders || !c->collider_xf || !c->collider_next || !c->wc_colliders)
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    for (int i = 0; i < n; ++i) c->mark[i] = -1;

    wc_sim_def sd = sim_def_of(ctx, def);
    wc_diag d = wa_core_diag(ctx);
    weft_status st = wa_status(wc_state_create(&c->state, m, &sd, A, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: %s", fn, d.message);

    /* particles start at transform x rest (rest positions are object space, metres) */
    wa_xform_from_floats(&c->object, def->transform);
    for (int i = 0; i < n; ++i) wa_xform_point(&c->object, m->rest_pos + 3 * i, c->scratch + 3 * i);
    st = wa_status(wc_state_set_positions(c->state, c->scratch, NULL, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: def->transform: %s", fn, d.message);
    c->no_history = 1;

    c->n_colliders = nc;
    for (int k = 0; k < nc; ++k) {
        const weft_collider_def* cd = &def->colliders[k];
        wa_collider* q = &c->colliders[k];
        q->type = (int)cd->type;
        q->radius = cd->type == WEFT_COLLIDER_PLANE ? 0.0 : cd->radius;
        q->half_height = cd->type == WEFT_COLLIDER_CAPSULE ? cd->half_height : 0.0;
        q->thickness = cd->thickness;
        q->friction = cd->friction;
        wa_xform_from_floats(&c->collider_xf[k], cd->transform);
    }
    wa_world_colliders(c, c->collider_xf, c->collider_xf, 0.0);
    st = wa_status(wc_state_set_colliders(c->state, c->wc_colliders, nc, &d));
    if (st != WEFT_OK) return wa_fail(ctx, st, "%s: def->colliders: %s", fn, d.message);

    st = wa_build_mesh_colliders(ctx, c, def, fn);
    if (st != WEFT_OK) return st;

    /* also allocates the backup for this attachment set */
    return wa_bind_attachments(ctx, c, def->attachments, def->n_attachments, fn, "def->attachments");
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

    wa_cloth* c = WC_NEW(&ctx->alloc, wa_cloth, 1);
    if (!c) return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    c->ctx = ctx;
    c->max_frame_time = def->max_frame_time;
    c->linear_inertia = def->linear_inertia;
    c->angular_inertia = def->angular_inertia;

    wc_source_mesh src;
    memset(&src, 0, sizeof src);
    st = read_mesh(ctx, def, &src, fn);
    if (st != WEFT_OK) {
        wa_cloth_free(c);
        return st;
    }
    c->unit_scale = src.unit_scale;
    c->n_host = src.n_verts;
    c->host_rest = WC_NEW(&ctx->alloc, double, 3 * (size_t)src.n_verts);
    if (!c->host_rest) {
        wc_source_mesh_free(&src);
        wa_cloth_free(c);
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    }
    memcpy(c->host_rest, src.pos, 3 * (size_t)src.n_verts * sizeof(double));

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
    wc_diag d = wa_core_diag(ctx);
    st = wa_status(wc_model_build(&c->model, &src, &md, &ctx->alloc, &d));
    wc_source_mesh_free(&src);
    if (st != WEFT_OK) {
        wa_cloth_free(c);
        return wa_fail(ctx, st, "%s: def->mesh: %s", fn, d.message);
    }
    st = build_cloth(ctx, c, def, fn);
    if (st != WEFT_OK) {
        wa_cloth_free(c);
        return st;
    }
    int bad_vertex = -1;
    double bad_value = 0.0;
    if (!wa_outputs_in_range(c, &c->object, &bad_vertex, &bad_value)) {
        wa_cloth_free(c);
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_RANGE,
                       "%s: def->mesh: host vertex %d has a coordinate of %g (after unit_scale and transform), "
                       "beyond the %g the float outputs hold", fn, bad_vertex, bad_value, WA_MAX_OUTPUT_COORD);
    }
    /* GPU backend: the model and the state built above go to textures (the direct solver is
     * refused there: WEFT_ERROR_UNSUPPORTED with wg_sim_create's message) */
    if (ctx->backend == WEFT_BACKEND_GPU && (st = wa_gpu_cloth_create(ctx, c, fn)) != WEFT_OK) {
        wa_cloth_free(c);
        return st;
    }
    if (!wa_register(ctx, c, out)) {
        wa_cloth_free(c);
        return wa_fail(ctx, WEFT_ERROR_OUT_OF_MEMORY, "%s: out of memory (handle table)", fn);
    }
    for (int k = 0; k < c->model.report.n_warnings; ++k) wa_log(ctx, WEFT_LOG_WARN, "%s: %s", fn, c->model.report.warnings[k]);
    return wa_ok(ctx);
}

weft_status weft_cloth_destroy(weft_context* ctx, weft_cloth cloth) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, "weft_cloth_destroy");
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    wa_unregister(ctx, cloth);
    wa_cloth_free(c);
    return wa_ok(ctx);
}

weft_status weft_cloth_set_attachments(weft_context* ctx, weft_cloth cloth, const weft_attachment_def* attachments,
                                       int n) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_set_attachments";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
    if (!c) return WEFT_ERROR_INVALID_HANDLE;
    if (n < 0) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: n = %d is negative", fn, n);
    if (n > 0 && !attachments) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: attachments is NULL with n = %d", fn, n);
    /* binding reads the current positions: a GPU cloth's mirror is refreshed first */
    if (c->gpu) {
        weft_status dst = wa_gpu_download(ctx, c, fn);
        if (dst != WEFT_OK) return dst;
    }
    weft_status st = wa_bind_attachments(ctx, c, attachments, n, fn, "attachments");
    return st == WEFT_OK ? wa_ok(ctx) : st;
}

weft_status weft_cloth_get_info(weft_context* ctx, weft_cloth cloth, weft_cloth_info* out) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    static const char fn[] = "weft_cloth_get_info";
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    wa_cloth* c = wa_lookup(ctx, cloth, fn);
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
    i.backend = ctx->backend;
    const wc_sim_def* sd = &c->state->def;
    i.preconditioner = sd->solver.preconditioner == WC_PRECOND_AMG ? WEFT_PRECOND_AMG : WEFT_PRECOND_BLOCK_JACOBI;
    i.integrator = sd->integrator == WC_INTEGRATOR_BDF2     ? WEFT_INTEGRATOR_BDF2
                   : sd->integrator == WC_INTEGRATOR_TRBDF2 ? WEFT_INTEGRATOR_TRBDF2
                                                            : WEFT_INTEGRATOR_BACKWARD_EULER;
    i.newton_iterations = sd->newton_iterations;
    i.line_search = sd->line_search;
    i.n_seams = m->n_seams;
    i.n_panels = m->n_panels;
    i.self_collision = sd->self_collision;
    i.self_collision_thickness = sd->self_thickness;
    *out = i;
    return wa_ok(ctx);
}
