/* `weft run` as a host of the public API: scene -> context, cloth def, attachments, colliders;
 * scene motions -> per-frame transforms. */
#include "run_host.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_xform.h"

static void capture_log(weft_log_level level, const char* message, void* user) {
    run_host* h = user;
    if (level >= WEFT_LOG_ERROR) snprintf(h->log_error, sizeof h->log_error, "%s", message);
}

const char* run_host_error(const run_host* h) {
    const char* m = h->ctx ? weft_context_last_error(h->ctx) : h->log_error;
    return m && m[0] ? m : "unknown error";
}

static weft_solver solver_of(wc_solver_type t) {
    switch (t) {
    case WC_SOLVER_JACOBI: return WEFT_SOLVER_JACOBI;
    case WC_SOLVER_CHEBYSHEV: return WEFT_SOLVER_CHEBYSHEV;
    case WC_SOLVER_DIRECT: return WEFT_SOLVER_DIRECT;
    default: return WEFT_SOLVER_PCG;
    }
}

static weft_collider_type collider_type_of(int t) {
    return t == WC_COLLIDER_PLANE ? WEFT_COLLIDER_PLANE
         : t == WC_COLLIDER_CAPSULE ? WEFT_COLLIDER_CAPSULE : WEFT_COLLIDER_SPHERE;
}

/* The mesh as the library will read it. A file goes by path, with the scene transform split
 * into a rigid placement and a uniform scale; a grid, or a file under a transform with shear or
 * non-uniform scale, goes as host arrays already in world space (the scene's own mesh), placed
 * by the identity. Arrays allocated here are returned in *pos_out / *sizes_out. */
static int describe_mesh(const scene* s, weft_cloth_def* def, double placement[16], float** pos_out,
                         int** sizes_out) {
    *pos_out = NULL;
    *sizes_out = NULL;
    xf_identity(placement);
    double scale = 1.0;
    if (!s->mesh_is_grid && (!s->has_transform || xf_split_uniform_scale(s->transform, placement, &scale))) {
        def->mesh.path = s->mesh_file;
        def->mesh.select = s->mesh_select;
        def->unit_scale = s->mesh_scale * scale;
        return 0;
    }
    xf_identity(placement);
    const wc_source_mesh* m = &s->src;
    float* pos = malloc(sizeof(float) * 3 * (size_t)(m->n_verts > 0 ? m->n_verts : 1));
    int* sizes = malloc(sizeof(int) * (size_t)(m->n_polys > 0 ? m->n_polys : 1));
    if (!pos || !sizes) {
        free(pos);
        free(sizes);
        return -1;
    }
    for (int i = 0; i < 3 * m->n_verts; ++i) pos[i] = (float)m->pos[i];
    for (int q = 0; q < m->n_polys; ++q) sizes[q] = m->poly_start[q + 1] - m->poly_start[q];
    def->mesh.positions = pos;
    def->mesh.n_vertices = m->n_verts;
    def->mesh.face_sizes = sizes;
    def->mesh.n_faces = m->n_polys;
    def->mesh.indices = m->poly_verts;
    def->unit_scale = 1.0;
    *pos_out = pos;
    *sizes_out = sizes;
    return 0;
}

static void describe_settings(const scene* s, weft_cloth_def* def) {
    const wc_material* mat = &s->model_def.material;
    def->weld_tolerance = s->model_def.weld_tolerance;
    def->sew_distance = s->model_def.sew_distance;   /* sewing (sew.h): seams from mesh.seams */
    def->sew_stiffness = 0.0;                         /* the stretch stiffness */
    def->n_seams = s->model_def.n_seam_pairs;
    def->seam_a = s->seam_a;
    def->seam_b = s->seam_b;
    def->seam_close_time = s->model_def.seam_close_time;
    def->material.density = mat->density;
    for (int t = 0; t < 3; ++t) {   /* WC_SPRING_* and WEFT_SPRING_* share the order */
        def->material.stiffness[t] = mat->k[t];
        def->material.damping[t] = mat->d[t];
    }
    for (int k = 0; k < 3; ++k) {
        def->gravity[k] = s->sim.gravity[k];
        def->wind[k] = s->sim.air.wind[k];
    }
    def->air_drag_normal = s->sim.air.normal_drag;
    def->air_drag_tangent = s->sim.air.tangent_drag;
    def->solver = solver_of(s->sim.solver.type);
    def->tolerance = s->sim.solver.tolerance;
    def->max_iterations = s->sim.solver.max_iterations;
    def->preconditioner = s->preconditioner == WC_PRECOND_AMG            ? WEFT_PRECOND_AMG
                          : s->preconditioner == WC_PRECOND_BLOCK_JACOBI ? WEFT_PRECOND_BLOCK_JACOBI
                                                                         : WEFT_PRECOND_DEFAULT;
    def->integrator = s->integrator == WC_INTEGRATOR_BDF2     ? WEFT_INTEGRATOR_BDF2
                      : s->integrator == WC_INTEGRATOR_TRBDF2 ? WEFT_INTEGRATOR_TRBDF2
                      : s->integrator == WC_INTEGRATOR_BE     ? WEFT_INTEGRATOR_BACKWARD_EULER
                                                          : WEFT_INTEGRATOR_DEFAULT;
    def->newton_iterations = s->newton_iterations;
    def->line_search = s->line_search;
    def->self_collision = s->self_collision;
    def->self_collision_thickness = s->sim.self_thickness;
    def->substeps = s->sim.substeps;
    def->strain_limit = s->sim.strain_limit;
    if (def->max_frame_time < 1.0 / s->fps) def->max_frame_time = 1.0 / s->fps;
    def->linear_inertia = s->object.linear_inertia;
    def->angular_inertia = s->object.angular_inertia;
}

/* has_particle[v] = 1 for host vertices the library simulates. A vertex whose polygons were all
 * dropped (degenerate) has no particle; the library reports it with a zero normal, which a
 * vertex of a kept (non-degenerate) triangle never has. NULL when out of memory. */
static unsigned char* simulated_vertices(run_host* h, weft_status* st) {
    const int n = h->info.n_vertices;
    float* normals = malloc(sizeof(float) * 3 * (size_t)(n > 0 ? n : 1));
    unsigned char* has = malloc((size_t)(n > 0 ? n : 1));
    int count = 0;
    *st = normals && has ? weft_cloth_get_vertices(h->ctx, h->cloth, WEFT_SPACE_WORLD, NULL, normals, n, &count)
                         : WEFT_ERROR_OUT_OF_MEMORY;
    for (int v = 0; v < n && *st == WEFT_OK; ++v) {
        const float* q = normals + 3 * (size_t)v;
        has[v] = q[0] != 0 || q[1] != 0 || q[2] != 0;
    }
    free(normals);
    if (*st != WEFT_OK) {
        free(has);
        return NULL;
    }
    return has;
}

/* The pin groups as attachments, bound now (at rest, identity bind transforms). A vertex only a
 * "select" chose is skipped when it has no particle (a "vertices" entry naming one is refused by
 * the library, with the vertex in the message). att: (n_attachments), its vertex lists are
 * allocated here (the caller frees them). *oom = 1 when out of memory. */
static weft_status attach_pins(run_host* h, const scene* s, weft_attachment_def* att, int* oom) {
    int any_select = 0;
    for (int i = 0; i < s->n_pins; ++i) any_select |= s->pins[i].from_select;
    const int n = h->info.n_vertices;
    unsigned char* named = calloc((size_t)(n > 0 ? n : 1), 1);   /* by a "vertices" entry */
    weft_status st = WEFT_OK;
    unsigned char* has = any_select ? simulated_vertices(h, &st) : NULL;
    *oom = !named || st == WEFT_ERROR_OUT_OF_MEMORY;
    if (*oom || st != WEFT_OK) {
        free(named);
        free(has);
        return *oom ? WEFT_ERROR_OUT_OF_MEMORY : st;
    }
    for (int i = 0; i < s->n_pins; ++i)
        if (!s->pins[i].from_select)
            for (int k = 0; k < s->pins[i].n_vertices; ++k) named[s->pins[i].vertices[k]] = 1;
    for (int i = 0; i < h->n_attachments && !*oom; ++i) {
        const scene_pin_group* g = &s->pin_groups[i];
        int* verts = malloc(sizeof(int) * (size_t)(g->n_vertices > 0 ? g->n_vertices : 1));
        att[i] = weft_default_attachment_def();
        att[i].vertices = verts;
        *oom = !verts;
        for (int k = 0; k < g->n_vertices && verts; ++k) {
            const int v = g->vertices[k];
            if (named[v] || !has || has[v]) verts[att[i].n_vertices++] = v;
        }
        for (int k = 0; k < 3; ++k) att[i].free_axis[k] = (float)g->free_axis[k];
    }
    free(named);
    free(has);
    if (*oom) return WEFT_ERROR_OUT_OF_MEMORY;
    return weft_cloth_set_attachments(h->ctx, h->cloth, att, h->n_attachments);
}

/* "attachments[i]" in a library message -> which pins entries that is. */
static void explain_attachment(const scene* s, const char* lib, char* note, size_t cap) {
    note[0] = '\0';
    const char* at = strstr(lib, "attachments[");
    if (!at) return;
    const int i = atoi(at + 12);
    if (i >= 0 && i < s->n_pin_groups)
        snprintf(note, cap, " (attachments[%d] are the pins with the free_axis and motion of pins[%d])", i,
                 s->pin_groups[i].first_pin);
}

/* Release h and return st (msg already written). */
static weft_status give_up(run_host* h, weft_status st) {
    run_host_destroy(h);
    return st;
}

/* The scene's mesh colliders as defs (*out allocated, NULL when none) and h's per-frame arrays. */
static int describe_mesh_colliders(run_host* h, const scene* s, weft_mesh_collider_def** out) {
    *out = NULL;
    h->n_mesh = s->n_mesh_colliders;
    if (h->n_mesh == 0) return 0;
    int most = 1;
    for (int i = 0; i < h->n_mesh; ++i)
        if (s->mesh_colliders[i].n_verts > most) most = s->mesh_colliders[i].n_verts;
    *out = calloc((size_t)h->n_mesh, sizeof **out);
    h->mesh_xf = calloc(16 * (size_t)h->n_mesh, sizeof(float));
    h->mesh_verts = calloc(3 * (size_t)most, sizeof(float));
    if (!*out || !h->mesh_xf || !h->mesh_verts) return -1;
    for (int i = 0; i < h->n_mesh; ++i) {
        const scene_mesh_collider* m = &s->mesh_colliders[i];
        weft_mesh_collider_def* d = &(*out)[i];
        *d = weft_default_mesh_collider_def();
        d->mesh.path = m->file;
        d->mesh.select = m->select;
        d->unit_scale = m->scale;
        xf_to_float(m->transform, d->transform);
        d->thickness = m->thickness;
        d->friction = m->friction;
        if (m->push_speed >= 0) d->push_speed = m->push_speed;
    }
    return 0;
}

/* Mesh collider i at time t: motion x transform, and (vertex animation) its vertices. */
static void mesh_collider_frame(run_host* h, const scene* s, int i, double t) {
    const scene_mesh_collider* m = &s->mesh_colliders[i];
    double mo[16], M[16];
    scene_motion_at(&m->motion, t, mo);
    xf_mul(mo, m->transform, M);
    xf_to_float(M, h->mesh_xf + 16 * (size_t)i);
    if (m->n_frames == 0) return;
    /* file frames at frames_fps, interpolated linearly, held at the last */
    double u = t * m->frames_fps;
    int i0 = (int)floor(u);
    double a = u - i0;
    if (i0 < 0) i0 = 0, a = 0.0;
    if (i0 >= m->n_frames - 1) i0 = m->n_frames - 1, a = 0.0;
    const double* f0 = m->frames + 3 * (size_t)m->n_verts * i0;
    const double* f1 = a > 0.0 ? f0 + 3 * (size_t)m->n_verts : f0;
    for (int v = 0; v < m->n_verts; ++v) {
        double p[3], w[3];
        for (int k = 0; k < 3; ++k) p[k] = (1.0 - a) * f0[3 * v + k] + a * f1[3 * v + k];
        xf_apply(M, p, w);
        for (int k = 0; k < 3; ++k) h->mesh_verts[3 * v + k] = (float)w[k];
    }
    (void)weft_cloth_set_mesh_collider_vertices(h->ctx, h->cloth, i, h->mesh_verts, m->n_verts);
}

weft_status run_host_create(run_host* h, const scene* s, const run_host_opts* opts, const char* name, char* msg,
                            size_t cap) {
    memset(h, 0, sizeof *h);
    weft_context_def cd = weft_default_context_def();
    cd.backend = opts->backend;
    cd.threads = opts->threads;
    cd.log = capture_log;
    cd.log_user = h;
    cd.log_level = WEFT_LOG_ERROR;
    weft_status st = weft_context_create(WEFT_ABI, &cd, &h->ctx);
    if (st != WEFT_OK) {
        snprintf(msg, cap, "%s: cannot create a context: %s", name, run_host_error(h));
        return give_up(h, st);
    }

    h->n_attachments = s->n_pin_groups;
    h->n_colliders = s->n_colliders;
    const size_t na = (size_t)(h->n_attachments > 0 ? h->n_attachments : 1);
    const size_t nc = (size_t)(h->n_colliders > 0 ? h->n_colliders : 1);
    weft_attachment_def* att = calloc(na, sizeof *att);   /* vertex lists: attach_pins */
    weft_collider_def* col = calloc(nc, sizeof *col);
    h->attachment_xf = calloc(na * 16, sizeof(float));
    h->collider_xf = calloc(nc * 16, sizeof(float));
    h->collider_rest = calloc(nc * 16, sizeof(double));
    float* mesh_pos = NULL;
    int* mesh_sizes = NULL;
    weft_mesh_collider_def* mcol = NULL;
    weft_cloth_def def = weft_default_cloth_def();
    int oom = !att || !col || !h->attachment_xf || !h->collider_xf || !h->collider_rest ||
              describe_mesh(s, &def, h->object_rest, &mesh_pos, &mesh_sizes) != 0;
    int mismatch = 0;   /* cannot happen: the library and the scene import with the same code */
    if (!oom) {
        describe_settings(s, &def);
        xf_to_float(h->object_rest, def.transform);
        for (int i = 0; i < h->n_colliders; ++i) {
            const wc_collider* c = &s->colliders[i];
            double* rest = h->collider_rest + 16 * (size_t)i;
            col[i] = weft_default_collider_def();
            col[i].type = collider_type_of(c->type);
            scene_collider_placement(c, rest, &col[i].half_height);
            if (c->type != WC_COLLIDER_PLANE) col[i].radius = c->radius;
            col[i].thickness = c->thickness;
            col[i].friction = c->friction;
            xf_to_float(rest, col[i].transform);
        }
        def.n_colliders = h->n_colliders;
        def.colliders = h->n_colliders > 0 ? col : NULL;
        if (describe_mesh_colliders(h, s, &mcol) != 0) oom = 1;
        def.n_mesh_colliders = h->n_mesh;
        def.mesh_colliders = mcol;
        if (!oom) st = weft_cloth_create(h->ctx, &def, &h->cloth);
        if (st == WEFT_OK) st = weft_cloth_get_info(h->ctx, h->cloth, &h->info);
        if (st == WEFT_OK && h->info.n_vertices != s->src.n_verts) mismatch = 1;
        else if (st == WEFT_OK && h->n_attachments > 0) st = attach_pins(h, s, att, &oom);
    }
    if (att)
        for (int i = 0; i < h->n_attachments; ++i) free((int*)att[i].vertices);
    free(att);
    free(col);
    free(mcol);
    free(mesh_pos);
    free(mesh_sizes);
    if (oom) {
        snprintf(msg, cap, "%s: out of memory", name);
        return give_up(h, WEFT_ERROR_OUT_OF_MEMORY);
    }
    if (mismatch) {
        snprintf(msg, cap, "%s: the library read %d host vertices from the mesh, the scene %d", name,
                 h->info.n_vertices, s->src.n_verts);
        return give_up(h, WEFT_ERROR_IMPORT);
    }
    if (st != WEFT_OK) {
        char note[160];
        explain_attachment(s, run_host_error(h), note, sizeof note);
        snprintf(msg, cap, "%s: %s%s", name, run_host_error(h), note);
        return give_up(h, st);
    }
    h->positions = malloc(sizeof(float) * 3 * (size_t)(h->info.n_vertices > 0 ? h->info.n_vertices : 1));
    st = h->positions ? run_host_read_positions(h) : WEFT_ERROR_OUT_OF_MEMORY;
    if (st != WEFT_OK) {
        snprintf(msg, cap, "%s: %s", name, h->positions ? run_host_error(h) : "out of memory");
        return give_up(h, st);
    }
    return WEFT_OK;
}

void run_host_destroy(run_host* h) {
    weft_context_destroy(h->ctx);   /* and the cloth */
    free(h->attachment_xf);
    free(h->collider_xf);
    free(h->collider_rest);
    free(h->mesh_xf);
    free(h->mesh_verts);
    h->mesh_xf = h->mesh_verts = NULL;
    free(h->positions);
    h->ctx = NULL;
    h->attachment_xf = h->collider_xf = h->positions = NULL;
    h->collider_rest = NULL;
}

weft_status run_host_read_positions(run_host* h) {
    int count = 0;
    return weft_cloth_get_vertices(h->ctx, h->cloth, WEFT_SPACE_WORLD, h->positions, NULL, h->info.n_vertices,
                                   &count);
}

weft_frame run_host_frame(run_host* h, const scene* s, int frame, double dt) {
    const double t = frame * dt;
    weft_frame fr = weft_default_frame();
    fr.dt = dt;
    const scene_object* o = &s->object;
    if (h->next_teleport < o->n_teleports && o->teleports[h->next_teleport].frame == frame) {
        for (int k = 0; k < 3; ++k) h->jump[k] += o->teleports[h->next_teleport].translate[k];
        ++h->next_teleport;
        fr.flags |= WEFT_FRAME_TELEPORT;
    }
    double jump[16], m[16], tmp[16], out[16];
    xf_translation(h->jump, jump);
    scene_motion_at(&o->motion, t, m);   /* object: jump * motion * rest placement */
    xf_mul(m, h->object_rest, tmp);
    xf_mul(jump, tmp, out);
    xf_to_float(out, h->object_xf);
    fr.object_transform = h->object_xf;
    for (int i = 0; i < h->n_attachments; ++i) {   /* pins: jump * motion (bound at rest) */
        scene_motion_at(&s->pin_groups[i].motion, t, m);
        xf_mul(jump, m, out);
        xf_to_float(out, h->attachment_xf + 16 * (size_t)i);
    }
    for (int i = 0; i < h->n_colliders; ++i) {     /* colliders: motion * rest placement */
        scene_motion_at(&s->collider_motion[i], t, m);
        xf_mul(m, h->collider_rest + 16 * (size_t)i, out);
        xf_to_float(out, h->collider_xf + 16 * (size_t)i);
    }
    fr.attachment_transforms = h->n_attachments > 0 ? h->attachment_xf : NULL;
    fr.collider_transforms = h->n_colliders > 0 ? h->collider_xf : NULL;
    for (int i = 0; i < h->n_mesh; ++i) mesh_collider_frame(h, s, i, t);   /* mesh colliders: the same, or vertices */
    fr.mesh_collider_transforms = h->n_mesh > 0 ? h->mesh_xf : NULL;
    return fr;
}
