/* Colliders: local geometry mapped through the host's transform into core's world wc_collider.
 *   plane    local y = 0, free side +y: normal = R (0, 1, 0) (renormalised), offset = normal . t
 *   sphere   local origin: center = t
 *   capsule  local segment (0, -half_height, 0)..(0, +half_height, 0): a, b = T (0, -+h, 0)
 * The velocity is that of the transform's origin over the frame, (t_next - t_prev) / dt: core
 * models a collider's motion as a rigid translation per substep (a spinning sphere's surface
 * speed is not seen by friction). Zero when dt <= 0 (creation, teleport, reset). */
#include <string.h>
#include "api_internal.h"
#include "vec3.h"

void wa_world_colliders(const wa_cloth* c, const wa_xform* next, const wa_xform* prev, double dt) {
    for (int k = 0; k < c->n_colliders; ++k) {
        const wa_collider* q = &c->colliders[k];
        const wa_xform* T = &next[k];
        wc_collider* w = &c->wc_colliders[k];
        memset(w, 0, sizeof *w);
        w->type = q->type;   /* weft_collider_type and wc_collider_type share their numbering */
        w->radius = q->radius;
        w->thickness = q->thickness;
        w->friction = q->friction;
        if (q->type == WEFT_COLLIDER_PLANE) {
            const double up[3] = {0.0, 1.0, 0.0};
            double n[3];
            wa_xform_vector(T, up, n);
            v3_scale(w->normal, n, 1.0 / v3_norm(n));
            w->offset = v3_dot(w->normal, T->t);
        } else if (q->type == WEFT_COLLIDER_SPHERE) {
            v3_copy(w->center, T->t);
        } else {
            const double lo[3] = {0.0, -q->half_height, 0.0}, hi[3] = {0.0, q->half_height, 0.0};
            wa_xform_point(T, lo, w->a);
            wa_xform_point(T, hi, w->b);
        }
        if (dt > 0.0)
            for (int i = 0; i < 3; ++i) w->velocity[i] = (T->t[i] - prev[k].t[i]) / dt;
    }
}
