/* A collider's signed distance: the analytic shapes in closed form, a mesh through its closest
 * point (collider.h). */
#include "collider.h"
#include <math.h>
#include "mesh_collider.h"
#include "vec3.h"

static void set_up(double* n) { v3_set(n, 0.0, 1.0, 0.0); }

/* Signed distance to a ball of radius r around q; u (unit or NULL) is the capsule axis, used to
 * pick a normal perpendicular to it when p is on the axis. */
static double ball_distance(const double* p, const double* q, double r, const double* u, double* n) {
    double d[3];
    v3_sub(d, p, q);
    double len = v3_norm(d);
    if (len > 0.0) {
        v3_scale(n, d, 1.0 / len);
        return len - r;
    }
    set_up(n);
    if (u) {
        /* up, or x when the axis is near vertical, made perpendicular to the axis */
        double w[3];
        v3_copy(w, n);
        v3_axpy(w, -v3_dot(w, u), u);
        if (v3_dot(w, w) < 0.25) {
            v3_set(w, 1.0, 0.0, 0.0);
            v3_axpy(w, -v3_dot(w, u), u);
        }
        v3_scale(n, w, 1.0 / v3_norm(w));
    }
    return -r;
}

double wc_collider_distance(const wc_collider* c, const double* p, double* normal) {
    switch (c->type) {
    case WC_COLLIDER_PLANE:
        v3_copy(normal, c->normal);
        return v3_dot(c->normal, p) - c->offset;
    case WC_COLLIDER_SPHERE:
        return ball_distance(p, c->center, c->radius, NULL, normal);
    case WC_COLLIDER_CAPSULE: {
        double ab[3], ap[3], q[3], u[3];
        v3_sub(ab, c->b, c->a);
        v3_sub(ap, p, c->a);
        double l2 = v3_dot(ab, ab);
        if (!(l2 > 0.0)) return ball_distance(p, c->a, c->radius, NULL, normal);
        double t = v3_dot(ap, ab) / l2;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        v3_copy(q, c->a);
        v3_axpy(q, t, ab);
        v3_scale(u, ab, 1.0 / sqrt(l2));
        return ball_distance(p, q, c->radius, u, normal);
    }
    case WC_COLLIDER_MESH: {
        double d = c->mesh ? wc_mesh_closest(c->mesh, 1, p, HUGE_VAL, normal, NULL) : HUGE_VAL;
        if (d < HUGE_VAL) return d;
        set_up(normal);
        return HUGE_VAL;
    }
    default:
        set_up(normal);
        return HUGE_VAL;
    }
}
