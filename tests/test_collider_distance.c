/* Distances of the analytic colliders (core/collide.h), checked against independent references:
 * the plane by construction, the sphere by dense surface sampling, the capsule by dense sampling
 * of its axis; normals against finite-difference gradients of the distance. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "colliders.h"

/* Finite-difference gradient of the distance equals the normal; the normal is unit. */
static int check_gradient(const wc_collider* c, const double* p) {
    double n[3], g[3], q[3], nn[3];
    wc_collider_distance(c, p, n);
    const double e = 1e-6;
    for (int k = 0; k < 3; ++k) {
        v3_copy(q, p);
        q[k] += e;
        double dp = wc_collider_distance(c, q, nn);
        q[k] -= 2 * e;
        double dm = wc_collider_distance(c, q, nn);
        g[k] = (dp - dm) / (2 * e);
    }
    double diff[3];
    v3_sub(diff, g, n);
    return v3_norm(diff) < 1e-6 && fabs(v3_norm(n) - 1.0) < 1e-14;
}

static void test_distance_plane(void) {
    int bad = 0;
    for (int it = 0; it < 200; ++it) {
        double n[3], t1[3], t2[3], q0[3], p[3], nout[3];
        rand_unit(n);
        wc_collider c = plane(n[0], n[1], n[2], srand1(3));
        v3_copy(n, c.normal);
        /* a point on the plane, plus tangential and normal offsets */
        v3_scale(q0, n, c.offset);
        double a[3] = {1, 0, 0};
        if (fabs(n[0]) > 0.9) v3_set(a, 0, 1, 0);
        v3_cross(t1, n, a);
        v3_scale(t1, t1, 1.0 / v3_norm(t1));
        v3_cross(t2, n, t1);
        double s = srand1(2);
        v3_copy(p, q0);
        v3_axpy(p, srand1(5), t1);
        v3_axpy(p, srand1(5), t2);
        v3_axpy(p, s, n);
        double d = wc_collider_distance(&c, p, nout);
        if (fabs(d - s) > 1e-12) ++bad;
        if (!check_gradient(&c, p)) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
}

static void test_distance_sphere(void) {
    /* Fibonacci points on the unit sphere */
    enum { NS = 40000 };
    double* pts = malloc(sizeof(double) * 3 * NS);
    for (int k = 0; k < NS; ++k) {
        double y = 1.0 - 2.0 * (k + 0.5) / NS, r = sqrt(1.0 - y * y), ph = k * 2.399963229728653;
        v3_set(pts + 3 * k, r * cos(ph), y, r * sin(ph));
    }
    int bad = 0, bad_grad = 0;
    double worst = 0.0;
    for (int it = 0; it < 100; ++it) {
        double R = 0.2 + urand();
        wc_collider c = sphere(srand1(2), srand1(2), srand1(2), R);
        double p[3], n[3], s[3];
        v3_set(p, c.center[0] + srand1(2 * R), c.center[1] + srand1(2 * R), c.center[2] + srand1(2 * R));
        double d = wc_collider_distance(&c, p, n);
        double best = HUGE_VAL;
        for (int k = 0; k < NS; ++k) {
            v3_copy(s, c.center);
            v3_axpy(s, R, pts + 3 * k);
            double e[3];
            v3_sub(e, p, s);
            if (v3_norm(e) < best) best = v3_norm(e);
        }
        double pc[3];
        v3_sub(pc, p, c.center);
        double ref = v3_norm(pc) < R ? -best : best;
        /* sample spacing ~ sqrt(4 pi / NS) R: the nearest sample is within half of it */
        double err = fabs(d - ref);
        if (err > worst) worst = err;
        if (err > 0.01 * R) ++bad;
        if (v3_norm(pc) > 1e-3 && !check_gradient(&c, p)) ++bad_grad;
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bad_grad, 0);
    CHECK(worst < 5e-3);
    /* deterministic unit normal at the center */
    wc_collider c = sphere(1, 2, 3, 0.5);
    double n[3];
    CHECK_NEAR(wc_collider_distance(&c, c.center, n), -0.5, 0);
    CHECK_NEAR(v3_norm(n), 1.0, 1e-15);
    free(pts);
}

static void test_distance_capsule(void) {
    enum { NA = 20001 };
    int bad = 0, bad_grad = 0;
    for (int it = 0; it < 200; ++it) {
        double a[3], b[3], p[3], n[3];
        v3_set(a, srand1(1), srand1(1), srand1(1));
        v3_set(b, srand1(1), srand1(1), srand1(1));
        if (it % 10 == 0) v3_copy(b, a); /* degenerate: a sphere */
        double R = 0.05 + 0.5 * urand();
        wc_collider c = capsule(a, b, R);
        v3_set(p, srand1(2), srand1(2), srand1(2));
        double d = wc_collider_distance(&c, p, n);
        /* dense sampling of the axis: the capsule is every point within R of it */
        double best = HUGE_VAL;
        for (int k = 0; k < NA; ++k) {
            double t = (double)k / (NA - 1), s[3], e[3];
            for (int q = 0; q < 3; ++q) s[q] = a[q] + t * (b[q] - a[q]);
            v3_sub(e, p, s);
            if (v3_norm(e) < best) best = v3_norm(e);
        }
        if (fabs(d - (best - R)) > 1e-8) ++bad;
        if (best > 1e-3 && !check_gradient(&c, p)) ++bad_grad;
        /* the closest surface point p - d n is on the surface */
        double q[3], nq[3];
        v3_copy(q, p);
        v3_axpy(q, -d, n);
        if (fabs(wc_collider_distance(&c, q, nq)) > 1e-12) ++bad;
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bad_grad, 0);
    /* on the axis: unit normal perpendicular to the axis; also for a vertical axis */
    double a[3] = {0, 0, 0}, b[3] = {1, 2, 0.5}, p[3] = {0.5, 1, 0.25}, n[3];
    wc_collider c = capsule(a, b, 0.3);
    CHECK_NEAR(wc_collider_distance(&c, p, n), -0.3, 1e-15);
    CHECK_NEAR(v3_norm(n), 1.0, 1e-15);
    double ab[3];
    v3_sub(ab, b, a);
    CHECK_NEAR(v3_dot(n, ab), 0.0, 1e-15);
    v3_set(b, 0, 3, 0);
    v3_set(p, 0, 1, 0);
    c = capsule(a, b, 0.3);
    wc_collider_distance(&c, p, n);
    CHECK_NEAR(v3_norm(n), 1.0, 1e-15);
    CHECK_NEAR(n[1], 0.0, 1e-15);
}

int main(void) {
    RUN_TEST(test_distance_plane);
    RUN_TEST(test_distance_sphere);
    RUN_TEST(test_distance_capsule);
    return TEST_SUMMARY();
}
