/* A scene as a host of the public API: scene -> context, cloth def, attachments, colliders;
 * scene motions -> per-frame transforms. */
#include "scene_host.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_colliders.h"
#include "scene_xform.h"

static void capture_log(weft_log_level level, const char* message, void* user) {
    scene_host* h = user;
    if (level >= WEFT_LOG_ERROR) snprintf(h->log_error, sizeof h->log_error, "%s", message);
}

const char* scene_host_error(const scene_host* h) {
    const char* m = h->ctx ? weft_context_last_error(h->ctx) : h->log_error;
    return m && m[0] ? m : "unknown error";
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
    const scene_mesh* m = &s->mesh;
    float* pos = malloc(sizeof(float) * 3 * (size_t)(m->n_vertices > 0 ? m->n_vertices : 1));
    int* sizes = malloc(sizeof(int) * (size_t)(m->n_faces > 0 ? m->n_faces : 1));
    if (!pos || !sizes) {
        free(pos);
        free(sizes);
        return -1;
    }
    for (int i = 0; i < 3 * m->n_vertices; ++i) pos[i] = (float)m->positions[i];
    for (int q = 0; q < m->n_faces; ++q) sizes[q] = m->face_sizes[q];
    def->mesh.positions = pos;
    def->mesh.n_vertices = m->n_vertices;
    def->mesh.face_sizes = sizes;
    def->mesh.n_faces = m->n_faces;
    def->mesh.indices = m->indices;
    def->unit_scale = 1.0;
    *pos_out = pos;
    *sizes_out = sizes;
    return 0;
}

/* What a host sets itself beside the scene's cloth def: the frame length it steps at and the
 * object's inertia. */
static void describe_settings(const scene* s, weft_cloth_def* def) {
    if (def->max_frame_time < 1.0 / s->fps) def->max_frame_time = 1.0 / s->fps;
    def->linear_inertia = s->object.linear_inertia;
    def->angular_inertia = s->object.angular_inertia;
}

/* has_particle[v] = 1 for host vertices the library simulates. A vertex whose polygons were all
 * dropped (degenerate) has no particle; the library reports it with a zero normal, which a
 * vertex of a kept (non-degenerate) triangle never has. NULL when out of memory. */
static unsigned char* simulated_vertices(scene_host* h, weft_status* st) {
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
static weft_status attach_pins(scene_host* h, const scene* s, weft_attachment_def* att, int* oom) {
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
static weft_status give_up(scene_host* h, weft_status st) {
    scene_host_destroy(h);
    return st;
}

/* The scene's mesh colliders, then the opts' extra ones, as defs (*out allocated, NULL when
 * none), and h's per-frame arrays (the extra ones' transforms: their defs'). */
static int describe_mesh_colliders(scene_host* h, const scene* s, const scene_host_opts* opts,
                                   weft_mesh_collider_def** out) {
    *out = NULL;
    h->n_scene_mesh = s->n_mesh_colliders;
    h->n_mesh = s->n_mesh_colliders + opts->n_mesh_colliders;
    if (h->n_mesh == 0) return 0;
    int most = 1;
    for (int i = 0; i < s->n_mesh_colliders; ++i)
        if (s->mesh_colliders[i].n_verts > most) most = s->mesh_colliders[i].n_verts;
    *out = calloc((size_t)h->n_mesh, sizeof **out);
    h->mesh_xf = calloc(16 * (size_t)h->n_mesh, sizeof(float));
    h->mesh_verts = calloc(3 * (size_t)most, sizeof(float));
    if (!*out || !h->mesh_xf || !h->mesh_verts) return -1;
    for (int i = 0; i < s->n_mesh_colliders; ++i) {
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
    for (int i = 0; i < opts->n_mesh_colliders; ++i) {
        (*out)[s->n_mesh_colliders + i] = opts->mesh_colliders[i];
        memcpy(h->mesh_xf + 16 * (size_t)(s->n_mesh_colliders + i), opts->mesh_colliders[i].transform,
               16 * sizeof(float));
    }
    return 0;
}

/* The scene's colliders placed in the API's local conventions (col: n_colliders defs; their
 * rest placements into h->collider_rest). */
static void describe_colliders(scene_host* h, const scene* s, weft_collider_def* col) {
    for (int i = 0; i < h->n_colliders; ++i) {
        const scene_collider* c = &s->colliders[i];
        double* rest = h->collider_rest + 16 * (size_t)i;
        col[i] = weft_default_collider_def();
        col[i].type = c->type;
        scene_collider_placement(c, rest, &col[i].half_height);
        if (c->type != WEFT_COLLIDER_PLANE) col[i].radius = c->radius;
        col[i].thickness = c->thickness;
        col[i].friction = c->friction;
        xf_to_float(rest, col[i].transform);
    }
}

/* Mesh collider i at time t: motion x transform, and (vertex animation) its vertices. */
static void mesh_collider_frame(scene_host* h, const scene* s, int i, double t) {
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

/* The context: the borrowed one, or a new one (its creation errors caught by the logger). */
static weft_status open_context(scene_host* h, const scene_host_opts* opts) {
    if (opts->ctx) {
        h->ctx = opts->ctx;
        return WEFT_OK;
    }
    weft_context_def cd = weft_default_context_def();
    cd.backend = opts->backend;
    cd.threads = opts->threads;
    cd.log = capture_log;
    cd.log_user = h;
    cd.log_level = WEFT_LOG_ERROR;
    weft_status st = weft_context_create(WEFT_ABI, &cd, &h->ctx);
    h->own_ctx = st == WEFT_OK;
    return st;
}

weft_status scene_host_create(scene_host* h, const scene* s, const scene_host_opts* opts, const char* name,
                              char* msg, size_t cap) {
    memset(h, 0, sizeof *h);
    weft_status st = open_context(h, opts);
    if (st != WEFT_OK) {
        snprintf(msg, cap, "%s: cannot create a context: %s", name, scene_host_error(h));
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
    weft_cloth_def def = s->def;
    int oom = !att || !col || !h->attachment_xf || !h->collider_xf || !h->collider_rest ||
              describe_mesh(s, &def, h->object_rest, &mesh_pos, &mesh_sizes) != 0;
    int mismatch = 0;   /* cannot happen: the library and the scene read the mesh with the same code */
    if (!oom) {
        describe_settings(s, &def);
        xf_to_float(h->object_rest, def.transform);
        describe_colliders(h, s, col);
        def.n_colliders = h->n_colliders;
        def.colliders = h->n_colliders > 0 ? col : NULL;
        if (describe_mesh_colliders(h, s, opts, &mcol) != 0) oom = 1;
        def.n_mesh_colliders = h->n_mesh;
        def.mesh_colliders = mcol;
        if (!oom) st = weft_cloth_create(h->ctx, &def, &h->cloth);
        if (st == WEFT_OK) st = weft_cloth_get_info(h->ctx, h->cloth, &h->info);
        if (st == WEFT_OK && h->info.n_vertices != s->mesh.n_vertices) mismatch = 1;
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
                 h->info.n_vertices, s->mesh.n_vertices);
        return give_up(h, WEFT_ERROR_IMPORT);
    }
    if (st != WEFT_OK) {
        char note[160];
        explain_attachment(s, scene_host_error(h), note, sizeof note);
        snprintf(msg, cap, "%s: %s%s", name, scene_host_error(h), note);
        return give_up(h, st);
    }
    h->positions = malloc(sizeof(float) * 3 * (size_t)(h->info.n_vertices > 0 ? h->info.n_vertices : 1));
    st = h->positions ? scene_host_read_positions(h) : WEFT_ERROR_OUT_OF_MEMORY;
    if (st != WEFT_OK) {
        snprintf(msg, cap, "%s: %s", name, h->positions ? scene_host_error(h) : "out of memory");
        return give_up(h, st);
    }
    return WEFT_OK;
}

void scene_host_destroy(scene_host* h) {
    if (h->own_ctx) weft_context_destroy(h->ctx);   /* and the cloth */
    else if (h->ctx && h->cloth.id) weft_cloth_destroy(h->ctx, h->cloth);
    free(h->attachment_xf);
    free(h->collider_xf);
    free(h->collider_rest);
    free(h->mesh_xf);
    free(h->mesh_verts);
    free(h->positions);
    memset(h, 0, sizeof *h);
}

weft_status scene_host_read_positions(scene_host* h) {
    int count = 0;
    return weft_cloth_get_vertices(h->ctx, h->cloth, WEFT_SPACE_WORLD, h->positions, NULL, h->info.n_vertices,
                                   &count);
}

weft_frame scene_host_frame(scene_host* h, const scene* s, int frame, double dt) {
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
        scene_motion_at(&s->colliders[i].motion, t, m);
        xf_mul(m, h->collider_rest + 16 * (size_t)i, out);
        xf_to_float(out, h->collider_xf + 16 * (size_t)i);
    }
    fr.attachment_transforms = h->n_attachments > 0 ? h->attachment_xf : NULL;
    fr.collider_transforms = h->n_colliders > 0 ? h->collider_xf : NULL;
    for (int i = 0; i < h->n_scene_mesh; ++i) mesh_collider_frame(h, s, i, t);   /* motion x transform, or vertices */
    fr.mesh_collider_transforms = h->n_mesh > 0 ? h->mesh_xf : NULL;
    return fr;
}
