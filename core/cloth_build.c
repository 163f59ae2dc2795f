/* Cloth creation (def -> host mesh -> model -> state, colliders placed, mesh colliders made,
 * attachments bound, outputs' range checked, backend taken) and destruction. Everything a frame
 * needs is allocated here (and by a new binding of attachments): a frame allocates nothing. */
#include <string.h>
#include "cloth_internal.h"

wc_status wc_cloth_destroy(wc_cloth* c, wc_diag* d) {
    if (!c) return WC_OK;
    /* a cloth whose creation stopped before a backend took it has nothing there */
    wc_status st = c->backend ? c->backend->destroy(c, d) : WC_OK;
    wc_state_destroy(c->state);
    wc_cloth_free_mesh_colliders(c); /* after the state, which borrowed them */
    wc_model_free(&c->model);
    void* arrays[] = {c->host_rest, c->attachments, c->attachment_xf, c->attachment_next, c->pin_particle,
                      c->pin_attachment, c->pin_local, c->pins, c->colliders, c->collider_xf, c->collider_next,
                      c->world_colliders, c->scratch, c->mark, c->backup};
    wc_allocator a = c->alloc;
    for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; ++i) wc_free(&a, arrays[i]);
    wc_free(&a, c);
    return st;
}

/* The host map and the model, from the def's mesh. */
static wc_status build_model(wc_cloth* c, const wc_cloth_def* def, wc_diag* d) {
    wc_source_mesh src;
    wc_status st = wc_mesh_desc_read(&def->mesh, &src, &c->alloc, d);
    if (st != WC_OK) return wc_diag_prefix(d, st, "def->mesh: ");
    c->settings.unit_scale = src.unit_scale;
    c->n_host = src.n_verts;
    c->host_rest = WC_NEW(&c->alloc, double, 3 * (size_t)src.n_verts);
    if (!c->host_rest) {
        wc_source_mesh_free(&src);
        return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory");
    }
    memcpy(c->host_rest, src.pos, 3 * (size_t)src.n_verts * sizeof(double));
    st = wc_model_build(&c->model, &src, &def->model, &c->alloc, d);
    wc_source_mesh_free(&src);
    return st == WC_OK ? st : wc_diag_prefix(d, st, "def->mesh: ");
}

/* Everything after the model: state, initial positions, colliders, mesh colliders, attachments
 * (whose binding allocates the backup). */
static wc_status build_state(wc_cloth* c, const wc_cloth_def* def, wc_diag* d) {
    const wc_model* m = &c->model;
    int n = m->n_particles;
    c->scratch = WC_NEW(&c->alloc, double, 3 * (size_t)n);
    c->mark = WC_NEW(&c->alloc, int, (size_t)n);
    if (!c->scratch || !c->mark) return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory");
    for (int i = 0; i < n; ++i) c->mark[i] = -1;
    wc_status st = wc_state_create(&c->state, m, &def->sim, &c->alloc, d);
    if (st != WC_OK) return st;

    /* particles start at transform x rest (rest positions are object space, metres) */
    wc_xform_from_floats(&c->object, def->transform);
    for (int i = 0; i < n; ++i) wc_xform_point(&c->object, m->rest_pos + 3 * i, c->scratch + 3 * i);
    st = wc_state_set_positions(c->state, c->scratch, NULL, d);
    if (st != WC_OK) return wc_diag_prefix(d, st, "def->transform: ");
    c->no_history = 1;

    st = wc_cloth_build_colliders(c, def->colliders, def->n_colliders, d);
    if (st == WC_OK) st = wc_cloth_build_mesh_colliders(c, def->mesh_colliders, def->n_mesh_colliders, d);
    if (st == WC_OK) st = wc_cloth_bind(c, def->attachments, def->n_attachments, "def->attachments", d);
    return st;
}

wc_status wc_cloth_create_model(wc_cloth** out, const wc_cloth_def* def, const wc_allocator* alloc, wc_diag* d) {
    *out = NULL;
    wc_cloth* c = WC_NEW(alloc, wc_cloth, 1);
    if (!c) return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory");
    c->alloc = *alloc;
    c->settings.max_frame_time = def->max_frame_time;
    c->settings.linear_inertia = def->linear_inertia;
    c->settings.angular_inertia = def->angular_inertia;
    wc_status st = build_model(c, def, d);
    if (st != WC_OK) {
        (void)wc_cloth_destroy(c, NULL);
        return st;
    }
    *out = c;
    return WC_OK;
}

wc_status wc_cloth_create_rest(wc_cloth* c, const wc_cloth_def* def, const wc_cloth_backend* backend, void* device,
                               wc_diag* d) {
    wc_status st = build_state(c, def, d);
    int vertex = -1;
    double value = 0.0;
    if (st == WC_OK && !wc_cloth_outputs_in_range(c, &c->object, &vertex, &value))
        st = wc_fail(d, WC_ERROR_OUT_OF_RANGE,
                     "def->mesh: host vertex %d has a coordinate of %g (after unit_scale and transform), beyond the %g "
                     "the float outputs hold", vertex, value, WC_CLOTH_MAX_COORD);
    if (st != WC_OK) return st;
    /* the backend takes the cloth built above (refusing what it lacks) */
    c->backend = backend;
    c->device = device;
    return backend->create(c, d);
}

wc_status wc_cloth_create(wc_cloth** out, const wc_cloth_def* def, const wc_cloth_backend* backend, void* device,
                          const wc_allocator* alloc, wc_diag* d) {
    wc_status st = wc_cloth_create_model(out, def, alloc, d);
    if (st != WC_OK) return st;
    st = wc_cloth_create_rest(*out, def, backend, device, d);
    if (st != WC_OK) {
        (void)wc_cloth_destroy(*out, NULL);
        *out = NULL;
    }
    return st;
}
