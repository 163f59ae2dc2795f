/* A collider: a plane, sphere, capsule or triangle mesh the cloth stays outside of, with its
 * thickness (the shell the cloth keeps clear of its surface), Coulomb friction and rigid
 * velocity, and its signed distance. The contacts of a substep that keep the cloth outside are
 * collide.h's. */
#ifndef WEFT_CORE_COLLIDER_H
#define WEFT_CORE_COLLIDER_H

typedef enum wc_collider_type {
    WC_COLLIDER_PLANE = 0,     /* {x : normal.x = offset}; free side normal.x > offset */
    WC_COLLIDER_SPHERE = 1,    /* center, radius */
    WC_COLLIDER_CAPSULE = 2,   /* segment a-b, radius */
    WC_COLLIDER_MESH = 3       /* a triangle mesh (mesh_collider.h; its own thickness and friction
                                  are copied here): built by the step, never set by a caller */
} wc_collider_type;

struct wc_mesh_collider;

typedef struct wc_collider {
    int type;                  /* wc_collider_type */
    double normal[3];          /* plane: unit normal */
    double offset;             /* plane: m */
    double center[3];          /* sphere: m */
    double a[3], b[3];         /* capsule: segment end points (m) */
    double radius;             /* sphere, capsule: m, >= 0 */
    double thickness;          /* m, >= 0: the cloth stays this far outside the surface */
    double friction;           /* Coulomb coefficient (static = kinetic), >= 0 */
    double velocity[3];        /* m/s: rigid translation velocity of the collider this substep
                                  (mesh: unused, the velocity is per point) */
    double push_speed;         /* m/s, >= 0: a particle found inside the shell is moved out by at
                                  most push_speed x h per substep (begin's and project's
                                  corrections together; collide.c); 0: at once */
    const struct wc_mesh_collider* mesh; /* mesh: the collider (borrowed), else NULL */
} wc_collider;

/* Signed distance from p to the collider's surface (negative inside; thickness not included) and
 * the outward unit normal at the closest surface point. A mesh: at its substep end positions. */
double wc_collider_distance(const wc_collider* c, const double* p, double* normal);

#endif
