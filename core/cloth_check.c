/* The collision check: the crossings of a cloth with itself at its current positions
 * (self_collide.h's counter, through a BVH built for the call) and the deepest particle behind
 * the surface of any collider: the mesh colliders (at their current end-of-frame positions) and
 * the analytic ones (at their last frame's placement), thickness not included. Allocates (not
 * part of a frame). */
#include "cloth_internal.h"
#include "self_collide.h"

static double analytic_penetration(const wc_state* s) {
    double deepest = 0.0;
    for (int k = 0; k < s->n_colliders; ++k)
        for (int i = 0; i < s->model->n_particles; ++i) {
            double n[3], d = wc_collider_distance(&s->colliders[k], s->x + 3 * i, n);
            if (-d > deepest) deepest = -d;
        }
    return deepest;
}

wc_status wc_cloth_check_collisions(wc_cloth* c, int* self_intersections, double* max_penetration, wc_diag* d) {
    /* a device's positions are read back first */
    wc_status st = wc_cloth_download(c, d);
    if (st == WC_OK) st = wc_cloth_mesh_pull(c, d);   /* and the bodies a device moves */
    if (st != WC_OK) return st;
    int count = 0;
    st = wc_self_intersections(&c->model, c->state->x, &c->alloc, &count, d);
    if (st != WC_OK) return st;
    *self_intersections = count;
    double mesh = wc_mesh_max_penetration((const wc_mesh_collider* const*)c->mesh, c->n_mesh, c->state->x,
                                          c->model.n_particles);
    double analytic = analytic_penetration(c->state);
    *max_penetration = mesh > analytic ? mesh : analytic;
    return WC_OK;
}
