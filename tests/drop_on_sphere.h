/* The scene of the integrators' collider tests (test_bdf2.c, test_trbdf2.c): a sheet dropped onto
 * a sphere (radius 0.25 m) lying on a floor, both with thickness 5 mm and friction 0.4, stepped at
 * 30 fps until it falls asleep (at most 360 frames). */
#ifndef WEFT_TESTS_DROP_ON_SPHERE_H
#define WEFT_TESTS_DROP_ON_SPHERE_H
#include <string.h>
#include "check.h"
#include "collide.h"
#include "step.h"
#include "vec3.h"

/* Sets the two colliders on s, the sphere of the given radius (m; its centre stays at (0.1, 0.25,
 * 0.05)), and steps it; *slept: it fell asleep; *frames: the frames stepped; *bdf2 (may be NULL):
 * the BDF2 substeps taken; *worst_depth: the deepest any particle went behind a collider's surface
 * (m). */
static inline void drop_on_sphere_radius(wc_state* s, double radius, int* slept, int* frames, int* bdf2,
                                         double* worst_depth) {
    wc_collider c[2];
    memset(c, 0, sizeof c);
    c[0].type = WC_COLLIDER_PLANE;
    v3_set(c[0].normal, 0, 1, 0);
    c[0].offset = 0.0;
    c[0].thickness = 0.005;
    c[0].friction = 0.4;
    c[1].type = WC_COLLIDER_SPHERE;
    v3_set(c[1].center, 0.1, 0.25, 0.05);
    c[1].radius = radius;
    c[1].thickness = 0.005;
    c[1].friction = 0.4;
    wc_diag dg = {0};
    CHECK_EQ_INT(wc_state_set_colliders(s, c, 2, &dg), WC_OK);
    *slept = 0;
    if (bdf2) *bdf2 = 0;
    *worst_depth = 0.0;
    *frames = 0;
    for (int f = 0; f < 360 && !*slept; ++f) {
        ++*frames;
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &dg), WC_OK);
        if (bdf2) *bdf2 += st.bdf2_substeps;
        *slept = st.fell_asleep;
        for (int i = 0; i < s->model->n_particles; ++i) {
            CHECK(v3_finite(s->x + 3 * i));
            for (int k = 0; k < 2; ++k) {
                double n[3], d = wc_collider_distance(&c[k], s->x + 3 * i, n);
                if (-d > *worst_depth) *worst_depth = -d;
            }
        }
    }
}

/* The scene as above with the sphere's radius 0.25 m. */
static inline void drop_on_sphere(wc_state* s, int* slept, int* bdf2, double* worst_depth) {
    int frames;
    drop_on_sphere_radius(s, 0.25, slept, &frames, bdf2, worst_depth);
}

#endif
