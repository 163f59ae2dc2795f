/* Test helpers shared by test_collide and test_collider_distance: the tests' fixed-seed random
 * numbers (test_rng.h, this file's own seed) and constructors of the analytic colliders. */
#ifndef WEFT_TESTS_COLLIDERS_H
#define WEFT_TESTS_COLLIDERS_H
#include "collide.h"
#include "vec3.h"

#ifndef TEST_RNG_SEED
#define TEST_RNG_SEED 88172645463325252ull
#endif
#include "test_rng.h"
static inline double srand1(double s) { return s * (2.0 * urand() - 1.0); }
static inline void rand_unit(double* n) {
    do { v3_set(n, srand1(1), srand1(1), srand1(1)); } while (v3_norm(n) < 0.1);
    v3_scale(n, n, 1.0 / v3_norm(n));
}

static inline wc_collider plane(double nx, double ny, double nz, double off) {
    wc_collider c = {0};
    c.type = WC_COLLIDER_PLANE;
    v3_set(c.normal, nx, ny, nz);
    v3_scale(c.normal, c.normal, 1.0 / v3_norm(c.normal));
    c.offset = off;
    return c;
}
static inline wc_collider sphere(double x, double y, double z, double r) {
    wc_collider c = {0};
    c.type = WC_COLLIDER_SPHERE;
    v3_set(c.center, x, y, z);
    c.radius = r;
    return c;
}
static inline wc_collider capsule(const double* a, const double* b, double r) {
    wc_collider c = {0};
    c.type = WC_COLLIDER_CAPSULE;
    v3_copy(c.a, a);
    v3_copy(c.b, b);
    c.radius = r;
    return c;
}

#endif
