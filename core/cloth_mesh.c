/* The cloth's triangle-mesh colliders (mesh_collider.h): creation from the def's meshes
 * (polygons triangulated, nothing welded), and their per-frame targets: the rigid transform x
 * rest shape, or vertices the host set for the next frame (a deforming body). The core object
 * holds the rest shape (object space, m) and the world positions at the frame's start and end;
 * the step moves it linearly between them. Creation allocates everything; a frame allocates
 * nothing. */
#include <string.h>
#include "cloth_internal.h"
#include "triangulate.h"

/* Triangles of every polygon of src (allocated into *tris, count *nt). */
static wc_status triangulate(const wc_allocator* A, const wc_source_mesh* src, int** tris, int* nt, wc_diag* d) {
    long long total = 0;
    int kmax = 3;
    for (int p = 0; p < src->n_polys; ++p) {
        int k = src->poly_start[p + 1] - src->poly_start[p];
        total += k - 2;
        if (k > kmax) kmax = k;
    }
    if (total < 1 || total > 0x7fffffffLL / 3) return wc_fail(d, WC_ERROR_EMPTY_MESH, "%lld triangles", total);
    *tris = WC_NEW(A, int, 3 * (size_t)total);
    unsigned char* mask = WC_NEW(A, unsigned char, (size_t)kmax);
    int* scratch = WC_NEW(A, int, (size_t)kmax);
    if (!*tris || !mask || !scratch) {
        wc_free(A, mask);
        wc_free(A, scratch);
        return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory (%lld triangles)", total);
    }
    int at = 0;
    for (int p = 0; p < src->n_polys; ++p) {
        int s0 = src->poly_start[p], k = src->poly_start[p + 1] - s0;
        at += wc_triangulate_polygon(src->poly_verts + s0, k, src->pos, *tris + 3 * at, mask, scratch);
    }
    *nt = at;
    wc_free(A, mask);
    wc_free(A, scratch);
    return WC_OK;
}

/* World positions transform x rest of collider k into c->mesh_scratch. */
static void world_positions(const wc_cloth* c, int k, const wc_xform* T) {
    const wc_mesh_collider* m = c->mesh[k];
    for (int v = 0; v < m->n_verts; ++v) wc_xform_point(T, m->rest + 3 * v, c->mesh_scratch + 3 * v);
}

/* Read, triangulate and create collider k of the def. */
static wc_status create_one(wc_cloth* c, int k, const wc_cloth_mesh_def* md, wc_diag* d) {
    const wc_allocator* A = &c->alloc;
    wc_source_mesh src;
    wc_status st = wc_mesh_desc_read(&md->mesh, &src, A, d);
    int* tris = NULL;
    int nt = 0;
    if (st == WC_OK) st = triangulate(A, &src, &tris, &nt, d);
    if (st == WC_OK)
        st = wc_mesh_collider_create(&c->mesh[k], src.pos, src.n_verts, tris, nt, md->thickness, md->friction, A, d);
    wc_free(A, tris);
    wc_source_mesh_free(&src);
    if (st != WC_OK) return wc_diag_prefix(d, st, "def->mesh_colliders[%d].mesh: ", k);
    c->mesh[k]->push_speed = md->push_speed;
    wc_xform_from_floats(&c->mesh_xf[k], md->transform);
    return WC_OK;
}

wc_status wc_cloth_build_mesh_colliders(wc_cloth* c, const wc_cloth_mesh_def* defs, int n, wc_diag* d) {
    if (n == 0) return WC_OK;
    const wc_allocator* A = &c->alloc;
    c->mesh = WC_NEW(A, wc_mesh_collider*, (size_t)n);
    c->mesh_xf = WC_NEW(A, wc_xform, (size_t)n);
    c->mesh_next = WC_NEW(A, wc_xform, (size_t)n);
    c->mesh_pending = WC_NEW(A, int, (size_t)n);
    if (!c->mesh || !c->mesh_xf || !c->mesh_next || !c->mesh_pending)
        return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory");
    c->n_mesh = n;
    int most = 0;
    for (int k = 0; k < n; ++k) {
        wc_status st = create_one(c, k, &defs[k], d);
        if (st != WC_OK) return st;
        if (c->mesh[k]->n_verts > most) most = c->mesh[k]->n_verts;
    }
    c->mesh_scratch = WC_NEW(A, double, 3 * (size_t)most);
    c->mesh_read = WC_NEW(A, float, 3 * (size_t)most);
    if (!c->mesh_scratch || !c->mesh_read) return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory");
    for (int k = 0; k < n; ++k) {
        world_positions(c, k, &c->mesh_xf[k]);
        if (wc_mesh_collider_set_all(c->mesh[k], c->mesh_scratch, d) != WC_OK)
            return wc_diag_prefix(d, WC_ERROR_OUT_OF_RANGE, "def->mesh_colliders[%d].transform: ", k);
    }
    return wc_state_attach_mesh_colliders(c->state, c->mesh, n, d);
}

void wc_cloth_free_mesh_colliders(wc_cloth* c) {
    if (c->mesh)
        for (int k = 0; k < c->n_mesh; ++k) wc_mesh_collider_destroy(c->mesh[k]);
    void* arrays[] = {c->mesh, c->mesh_xf, c->mesh_next, c->mesh_pending, c->mesh_scratch, c->mesh_read};
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i) wc_free(&c->alloc, arrays[i]);
}

void wc_cloth_mesh_frame(wc_cloth* c, const float* transforms, int jump, const wc_diag* d) {
    for (int k = 0; k < c->n_mesh; ++k) {
        wc_mesh_collider* m = c->mesh[k];
        if (transforms) wc_xform_from_floats(&c->mesh_next[k], transforms + 16 * k);
        else c->mesh_next[k] = c->mesh_xf[k];
        if (!c->mesh_pending[k] && transforms) {
            /* a rigid transform is finite and rigid (checked by the caller); its image of a rest
               shape within 1e30 stays finite, and wc_state_set_mesh_target checks it */
            world_positions(c, k, &c->mesh_next[k]);
            wc_diag why = *d;
            why.log = NULL;
            if (wc_state_set_mesh_target(c->state, k, c->mesh_scratch, &why) != WC_OK)
                wc_log(d, WC_LOG_WARN, "mesh collider %d: %s (kept where it was)", k, why.message);
        }
        if (jump) {
            memcpy(c->mesh_scratch, m->to, 3 * (size_t)m->n_verts * sizeof(double));
            (void)wc_mesh_collider_set_all(m, c->mesh_scratch, NULL);
            wc_state_wake(c->state);
        }
    }
}

void wc_cloth_mesh_frame_done(wc_cloth* c) {
    for (int k = 0; k < c->n_mesh; ++k) {
        c->mesh_xf[k] = c->mesh_next[k];
        c->mesh_pending[k] = 0;
        c->mesh[k]->device_moves = 0;   /* the device's frame ended: from = to (a failed frame keeps it) */
    }
}

wc_status wc_cloth_set_mesh_vertices(wc_cloth* c, int index, const float* positions, wc_diag* d) {
    if (index < 0 || index >= c->n_mesh)
        return wc_fail(d, WC_ERROR_OUT_OF_RANGE, "index %d is outside [0, %d) (the cloth's mesh colliders)", index,
                       c->n_mesh);
    if (!positions) return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "positions is NULL");
    if (c->mesh[index]->on_device) {   /* the frame's start is the device's */
        wc_status st = wc_cloth_mesh_pull(c, d);
        if (st != WC_OK) return st;
    }
    for (int i = 0; i < 3 * c->mesh[index]->n_verts; ++i) c->mesh_scratch[i] = (double)positions[i];
    wc_status st = wc_state_set_mesh_target(c->state, index, c->mesh_scratch, d);
    if (st == WC_OK) c->mesh_pending[index] = 1;
    return st;
}

wc_status wc_cloth_read_mesh_gl(wc_cloth* c, int index, const wc_gl_vertex_source* src, const float** positions,
                                wc_gl_vertex_result* res, wc_diag* d) {
    if (index < 0 || index >= c->n_mesh)
        return wc_fail(d, WC_ERROR_OUT_OF_RANGE, "index %d is outside [0, %d) (the cloth's mesh colliders)", index,
                       c->n_mesh);
    if (!src || !positions || src->n != c->mesh[index]->n_verts)
        return wc_fail(d, WC_ERROR_INVALID_ARGUMENT, "the GL buffer's vertex count is not mesh collider %d's", index);
    memset(res, 0, sizeof *res);
    res->bad_vertex = -1;
    wc_status st = c->backend->read_gl(c, index, src, c->mesh_read, res, d);
    if (st != WC_OK) return st;
    *positions = c->mesh_read;
    if (res->taken && res->bad_vertex < 0) {
        c->mesh_pending[index] = 1;
        c->mesh[index]->device_moves = res->moves;
        if (res->moves) wc_state_wake(c->state);   /* as the array call: a body standing still lets it sleep */
    }
    return WC_OK;
}
