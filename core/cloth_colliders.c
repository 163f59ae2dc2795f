/* Analytic colliders: a shape's local geometry mapped through the host's transform into core's
 * world wc_collider.
 *   plane    local y = 0, free side +y: normal = R (0, 1, 0) (renormalised), offset = normal . t
 *   sphere   local origin: center = t
 *   capsule  local segment (0, -half_height, 0)..(0, +half_height, 0): a, b = T (0, -+h, 0)
 * The velocity is that of the transform's origin over the frame, (t_next - t_prev) / dt: core
 * models a collider's motion as a rigid translation per substep (a spinning sphere's surface
 * speed is not seen by friction). Zero when dt <= 0 (creation, teleport, reset). */
#include <string.h>
#include "cloth_internal.h"
#include "vec3.h"

wc_status wc_cloth_build_colliders(wc_cloth* c, const wc_cloth_collider_def* defs, int n, wc_diag* d) {
    c->colliders = WC_NEW(&c->alloc, wc_cloth_collider, (size_t)n + 1);
    c->collider_xf = WC_NEW(&c->alloc, wc_xform, (size_t)n + 1);
    c->collider_next = WC_NEW(&c->alloc, wc_xform, (size_t)n + 1);
    c->world_colliders = WC_NEW(&c->alloc, wc_collider, (size_t)n + 1);
    if (!c->colliders || !c->collider_xf || !c->collider_next || !c->world_colliders)
        return wc_fail(d, WC_ERROR_OUT_OF_MEMORY, "out of memory");
    c->n_colliders = n;
    for (int k = 0; k < n; ++k) {
        const wc_cloth_collider_def* cd = &defs[k];
        wc_cloth_collider* q = &c->colliders[k];
        q->type = cd->type;
        q->radius = cd->type == WC_COLLIDER_PLANE ? 0.0 : cd->radius;
        q->half_height = cd->type == WC_COLLIDER_CAPSULE ? cd->half_height : 0.0;
        q->thickness = cd->thickness;
        q->friction = cd->friction;
        wc_xform_from_floats(&c->collider_xf[k], cd->transform);
    }
    wc_cloth_place_colliders(c, c->collider_xf, c->collider_xf, 0.0);
    wc_status st = wc_state_set_colliders(c->state, c->world_colliders, n, d);
    return st == WC_OK ? st : wc_diag_prefix(d, st, "def->colliders: ");
}

void wc_cloth_place_colliders(const wc_cloth* c, const wc_xform* next, const wc_xform* prev, double dt) {
    for (int k = 0; k < c->n_colliders; ++k) {
        const wc_cloth_collider* q = &c->colliders[k];
        const wc_xform* T = &next[k];
        wc_collider* w = &c->world_colliders[k];
        memset(w, 0, sizeof *w);
        w->type = q->type;
        w->radius = q->radius;
        w->thickness = q->thickness;
        w->friction = q->friction;
        if (q->type == WC_COLLIDER_PLANE) {
            const double up[3] = {0.0, 1.0, 0.0};
            double n[3];
            wc_xform_vector(T, up, n);
            v3_scale(w->normal, n, 1.0 / v3_norm(n));
            w->offset = v3_dot(w->normal, T->t);
        } else if (q->type == WC_COLLIDER_SPHERE) {
            v3_copy(w->center, T->t);
        } else {
            const double lo[3] = {0.0, -q->half_height, 0.0}, hi[3] = {0.0, q->half_height, 0.0};
            wc_xform_point(T, lo, w->a);
            wc_xform_point(T, hi, w->b);
        }
        if (dt > 0.0)
            for (int i = 0; i < 3; ++i) w->velocity[i] = (T->t[i] - prev[k].t[i]) / dt;
    }
}
