/* Colliders and contacts. Distances are checked against independent references (plane by
 * construction, sphere by dense surface sampling, capsule by dense sampling of its axis) and
 * normals against finite-difference gradients. Contacts run through a test-local substep with
 * a diagonal system A = m I (no springs), whose filtered solution is closed form:
 * dv = z + S (b / m - z), r = A dv - b; positions then move x += h v. */
#include <stdlib.h>
#include "check.h"
#include "collide.h"
#include "vec3.h"

static unsigned long long rng_state = 88172645463325252ull;
static double urand(void) { /* [0, 1) */
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}
static double srand1(double s) { return s * (2.0 * urand() - 1.0); }
static void rand_unit(double* n) {
    do { v3_set(n, srand1(1), srand1(1), srand1(1)); } while (v3_norm(n) < 0.1);
    v3_scale(n, n, 1.0 / v3_norm(n));
}

static wc_collider plane(double nx, double ny, double nz, double off) {
    wc_collider c = {0};
    c.type = WC_COLLIDER_PLANE;
    v3_set(c.normal, nx, ny, nz);
    v3_scale(c.normal, c.normal, 1.0 / v3_norm(c.normal));
    c.offset = off;
    return c;
}
static wc_collider sphere(double x, double y, double z, double r) {
    wc_collider c = {0};
    c.type = WC_COLLIDER_SPHERE;
    v3_set(c.center, x, y, z);
    c.radius = r;
    return c;
}
static wc_collider capsule(const double* a, const double* b, double r) {
    wc_collider c = {0};
    c.type = WC_COLLIDER_CAPSULE;
    v3_copy(c.a, a);
    v3_copy(c.b, b);
    c.radius = r;
    return c;
}

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

/* ---- a test-local substep ---- */

typedef struct sim {
    int n;
    double *x, *v, *mass, *force, *r, *dv;
    wc_filter f;
    wc_contacts ct;
    unsigned char* pinned;   /* 3: pinned (S = 0, z = 0); 2: line along x; 0: free */
    wc_par par;
} sim;

static void sim_init(sim* s, int n, int threads) {
    s->n = n;
    s->x = calloc((size_t)3 * n, sizeof(double));
    s->v = calloc((size_t)3 * n, sizeof(double));
    s->force = calloc((size_t)3 * n, sizeof(double));
    s->r = calloc((size_t)3 * n, sizeof(double));
    s->dv = calloc((size_t)3 * n, sizeof(double));
    s->mass = malloc(sizeof(double) * n);
    s->pinned = calloc((size_t)n, 1);
    for (int i = 0; i < n; ++i) s->mass[i] = 0.01 * (1 + i % 3);
    s->f.n = n;
    s->f.S = malloc(sizeof(double) * 9 * n);
    s->f.z = malloc(sizeof(double) * 3 * n);
    s->f.ndof = malloc((size_t)n);
    s->ct.n = n;
    s->ct.collider = malloc(sizeof(int) * 2 * n);
    s->ct.normal = calloc((size_t)6 * n, sizeof(double));
    s->ct.released = calloc((size_t)n, 1);
    s->ct.active = 0;
    for (int i = 0; i < 2 * n; ++i) s->ct.collider[i] = -1;
    for (int i = 0; i < n; ++i) wc_filter_free_particle(&s->f, i);
    wc_par_init(&s->par, threads);
}

static void sim_free(sim* s) {
    free(s->x); free(s->v); free(s->force); free(s->r); free(s->dv); free(s->mass); free(s->pinned);
    free(s->f.S); free(s->f.z); free(s->f.ndof);
    free(s->ct.collider); free(s->ct.normal); free(s->ct.released);
}

/* What the step does before begin: free everything, then the pins. */
static void sim_reset_filter(sim* s) {
    for (int i = 0; i < s->n; ++i) {
        wc_filter_free_particle(&s->f, i);
        if (s->pinned[i] == 3) {
            m3_zero(s->f.S + 9 * i);
            s->f.ndof[i] = 3;
        } else if (s->pinned[i] == 2) {
            double d[3] = {1, 0, 0};
            m3_outer(s->f.S + 9 * i, d, d, 1.0);
            s->f.ndof[i] = 2;
        }
    }
}

/* Solve A dv = b with A = m I, b = h force, through the filter; r = A dv - b; v += dv. */
static void sim_solve(sim* s, double h) {
    for (int i = 0; i < s->n; ++i) {
        double b[3], w[3], Sw[3];
        v3_scale(b, s->force + 3 * i, h);
        const double* z = s->f.z + 3 * i;
        v3_scale(w, b, 1.0 / s->mass[i]);
        v3_sub(w, w, z);
        wc_filter_apply(&s->f, i, w, Sw);
        v3_add(s->dv + 3 * i, z, Sw);
        for (int k = 0; k < 3; ++k) s->r[3 * i + k] = s->mass[i] * s->dv[3 * i + k] - b[k];
        v3_add(s->v + 3 * i, s->v + 3 * i, s->dv + 3 * i);
    }
}

/* One substep; returns particles projected. */
static int sim_step(sim* s, const wc_collider* c, int nc, double h) {
    sim_reset_filter(s);
    wc_contacts_begin(&s->ct, c, nc, s->x, s->v, h, &s->f, &s->par);
    sim_solve(s, h);
    wc_contacts_end(&s->ct, c, nc, s->r, s->mass, h, s->v, &s->par);
    for (int i = 0; i < 3 * s->n; ++i) s->x[i] += h * s->v[i];
    return wc_contacts_project(&s->ct, c, nc, &s->f, s->x, s->v, &s->par);
}

static void set_gravity(sim* s, double g) {
    for (int i = 0; i < s->n; ++i) v3_set(s->force + 3 * i, 0.0, -g * s->mass[i], 0.0);
}

static double shell_d(const wc_collider* c, const double* p, double* n) {
    return wc_collider_distance(c, p, n) - c->thickness;
}

/* A particle falling onto each collider type (slow and fast) ends on the shell, never inside,
 * with no velocity into the surface, in contact. */
static void test_fall_and_rest(void) {
    double a[3] = {-1, 0.2, 0}, b[3] = {1, 0.2, 0};
    wc_collider cs[3] = {plane(0, 1, 0, 0.1), sphere(0, 0, 0, 0.5), capsule(a, b, 0.3)};
    const double h = 1.0 / 240.0;
    for (int type = 0; type < 3; ++type)
        for (int fast = 0; fast < 2; ++fast) {
            wc_collider c = cs[type];
            c.thickness = 0.01;
            sim s;
            sim_init(&s, 1, 1);
            set_gravity(&s, 9.81);
            v3_set(s.x, 0.0, 2.0, 0.0);
            if (fast) s.v[1] = -40.0;
            double worst = 0.0, worst_vn = 0.0, n[3];
            for (int step = 0; step < 480; ++step) {
                sim_step(&s, &c, 1, h);
                double d = shell_d(&c, s.x, n);
                if (-d > worst) worst = -d;
                if (d < 1e-9 && -v3_dot(s.v, n) > worst_vn) worst_vn = -v3_dot(s.v, n);
            }
            double d = shell_d(&c, s.x, n);
            CHECK(worst <= 1e-12);
            CHECK(worst_vn <= 1e-12);
            CHECK_NEAR(d, 0.0, 1e-12);
            CHECK_NEAR(s.v[1], 0.0, 1e-12);
            CHECK_EQ_INT(s.ct.collider[0], 0);
            CHECK_EQ_INT(s.ct.active, 1);
            CHECK_EQ_INT(s.ct.released[0], 0);
            sim_free(&s);
        }
}

/* A particle approaching within this substep's reach is constrained before the solve and lands
 * exactly on the shell (nothing left for project); a penetrating one is pushed out first. */
static void test_landing_and_correction(void) {
    wc_collider c = plane(0, 1, 0, 0.0);
    c.thickness = 0.02;
    const double h = 0.01;
    sim s;
    sim_init(&s, 2, 1);
    set_gravity(&s, 9.81);
    v3_set(s.x, 0.3, 0.02 + 0.015, 0.0); /* 1.5 cm above the shell, 2 cm per substep reach */
    v3_set(s.v, 1.0, -2.0, 0.0);
    v3_set(s.x + 3, 0.0, 0.005, 0.0);    /* 1.5 cm inside the shell, moving down */
    v3_set(s.v + 3, 0.0, -1.0, 0.5);
    sim_reset_filter(&s);
    int cnt = wc_contacts_begin(&s.ct, &c, 1, s.x, s.v, h, &s.f, &s.par);
    CHECK_EQ_INT(cnt, 2);
    CHECK_NEAR(s.x[1], 0.035, 0);           /* not moved */
    CHECK_NEAR(s.x[4], 0.02, 1e-15);        /* pushed onto the shell */
    CHECK_EQ_INT(s.f.ndof[0], 1);
    sim_solve(&s, h);
    CHECK_NEAR(s.v[1], -1.5, 1e-12);        /* -d / h */
    CHECK_NEAR(s.v[0], 1.0, 1e-15);         /* tangential untouched (no friction yet) */
    CHECK_NEAR(s.v[4], 0.0, 1e-15);
    CHECK_NEAR(s.v[5], 0.5, 1e-15);
    wc_contacts_end(&s.ct, &c, 1, s.r, s.mass, h, s.v, &s.par);
    for (int i = 0; i < 6; ++i) s.x[i] += h * s.v[i];
    CHECK_NEAR(s.x[1], 0.02, 1e-15);
    int moved = wc_contacts_project(&s.ct, &c, 1, &s.f, s.x, s.v, &s.par);
    CHECK_EQ_INT(moved, 0);
    CHECK_NEAR(s.v[1], 0.0, 1e-15);          /* inward velocity on the shell removed */
    sim_free(&s);
}

/* A moving plane: after the solve the particle moves with it along the normal. */
static void test_moving_collider(void) {
    wc_collider c = plane(0, 1, 0, 0.0);
    v3_set(c.velocity, 0.3, 0.5, 0.0);
    sim s;
    sim_init(&s, 1, 1);
    set_gravity(&s, 9.81);
    sim_reset_filter(&s);
    wc_contacts_begin(&s.ct, &c, 1, s.x, s.v, 0.01, &s.f, &s.par);
    CHECK_EQ_INT(s.f.ndof[0], 1);
    sim_solve(&s, 0.01);
    CHECK_NEAR(s.v[1], 0.5, 1e-15);
    CHECK_NEAR(s.v[0], 0.0, 1e-15);
    sim_free(&s);
}

/* Resting under gravity keeps the contact (force m g along n); lifted by a force above m g it
 * is released, is not re-grabbed while outside, and leaves. */
static void test_keep_and_release(void) {
    wc_collider c = plane(0, 1, 0, 0.0);
    const double h = 0.005, g = 9.81;
    sim s;
    sim_init(&s, 1, 1);
    set_gravity(&s, g);
    for (int step = 0; step < 20; ++step) {
        sim_step(&s, &c, 1, h);
        CHECK_EQ_INT(s.ct.collider[0], 0);
        CHECK_EQ_INT(s.ct.released[0], 0);
        CHECK_NEAR(s.r[1] / h, s.mass[0] * g, 1e-12); /* lambda = m g */
    }
    CHECK_NEAR(s.x[1], 0.0, 1e-15);
    s.force[1] = 2.0 * s.mass[0] * g; /* net upward */
    sim_step(&s, &c, 1, h);
    CHECK_EQ_INT(s.ct.released[0], 1);
    CHECK_EQ_INT(s.ct.collider[0], -1);
    CHECK_EQ_INT(s.ct.active, 0);
    sim_reset_filter(&s);
    wc_contacts_begin(&s.ct, &c, 1, s.x, s.v, h, &s.f, &s.par);
    CHECK_EQ_INT(s.f.ndof[0], 0);
    double y0 = s.x[1];
    for (int step = 0; step < 5; ++step) sim_step(&s, &c, 1, h);
    CHECK(s.x[1] > y0 + 1e-4);
    CHECK(s.v[1] > 0.0);
    CHECK_EQ_INT(s.ct.released[0], 0);
    sim_free(&s);
}

/* Frictionless particle sliding from near the top of a sphere (shell radius R) from rest: it
 * stays in contact (held through the curvature) and is released where gravity can no longer
 * supply the centripetal force, cos(theta) = 2/3 cos(theta0) (energy conservation). */
static void test_slide_off_sphere(void) {
    const double R = 1.0, th0 = 0.05, h = 1.0 / 2000.0, g = 9.81;
    wc_collider c = sphere(0, 0, 0, 0.9);
    c.thickness = 0.1;
    sim s;
    sim_init(&s, 1, 1);
    set_gravity(&s, g);
    v3_set(s.x, R * sin(th0), R * cos(th0), 0.0);
    double release = -1.0;
    int lost_early = 0;
    for (int step = 0; step < 20000 && release < 0; ++step) {
        sim_step(&s, &c, 1, h);
        double cth = s.x[1] / v3_norm(s.x);
        if (s.ct.released[0]) release = cth;
        else if (s.ct.active == 0 && step > 0) lost_early = 1;
    }
    CHECK(!lost_early);
    CHECK_NEAR(release, 2.0 / 3.0 * cos(th0), 0.005);
    printf("slide off a sphere: released at cos %.5f, expected %.5f\n", release, 2.0 / 3.0 * cos(th0));
    sim_free(&s);
}

/* Friction: tangential relative speed |vt| becomes max(0, |vt| - mu dvn), dvn = lambda h / m. */
static void test_friction(void) {
    const double h = 0.01, g = 9.81;
    double mus[4] = {0.0, 0.5, 2.0, 1e3};
    for (int mv = 0; mv < 2; ++mv)
        for (int k = 0; k < 4; ++k) {
            wc_collider c = plane(0, 1, 0, 0.0);
            c.friction = mus[k];
            if (mv) v3_set(c.velocity, 0.0, 0.0, 1.0);
            sim s;
            sim_init(&s, 1, 1);
            set_gravity(&s, g);
            v3_set(s.v, 0.3, 0.0, 0.4); /* |vt| = 0.5 (relative: (0.3, -0.6) when moving) */
            sim_reset_filter(&s);
            wc_contacts_begin(&s.ct, &c, 1, s.x, s.v, h, &s.f, &s.par);
            sim_solve(&s, h);
            double vt0[3] = {s.v[0] - c.velocity[0], 0.0, s.v[2] - c.velocity[2]};
            double st0 = v3_norm(vt0), dvn = g * h;
            wc_contacts_end(&s.ct, &c, 1, s.r, s.mass, h, s.v, &s.par);
            double vt1[3] = {s.v[0] - c.velocity[0], 0.0, s.v[2] - c.velocity[2]};
            double expect = fmax(0.0, st0 - mus[k] * dvn);
            CHECK_NEAR(v3_norm(vt1), expect, 1e-14);
            CHECK_NEAR(s.v[1], 0.0, 1e-15);
            if (expect > 0) /* direction kept */
                CHECK_NEAR(vt1[0] * vt0[2] - vt1[2] * vt0[0], 0.0, 1e-15);
            if (k == 0) CHECK_NEAR(v3_norm(vt1), st0, 1e-15);
            if (k == 3) CHECK_NEAR(v3_norm(vt1), 0.0, 1e-15);
            sim_free(&s);
        }
}

/* In the corner between a plane and a sphere: two contacts, S of rank 1 along the crease,
 * both relative normal velocities cancelled; the force splits over the two normals. */
static void test_two_contacts(void) {
    wc_collider cs[2] = {plane(0, 1, 0, 0.0), sphere(0, 0.5, 0, 1.0)};
    const double h = 0.01, g = 9.81;
    for (int variant = 0; variant < 4; ++variant) {
        sim s;
        sim_init(&s, 1, 1);
        v3_set(s.x, 0.86, -0.001, 0.0);
        /* along the crease (z = 0: r is the applied force alone), or approaching (variant 3) */
        v3_set(s.v, variant == 3 ? -0.2 : 0.0, variant == 3 ? -0.3 : 0.0, 0.1);
        /* 0: pushed into the crease; 1: pushed into the plane, away from the sphere; 2, 3: gravity */
        double fx = variant == 0 ? -1.0 : (variant == 1 ? 1.0 : 0.0);
        v3_set(s.force, fx * s.mass[0], -g * s.mass[0], 0.0);
        sim_reset_filter(&s);
        int cnt = wc_contacts_begin(&s.ct, cs, 2, s.x, s.v, h, &s.f, &s.par);
        CHECK_EQ_INT(cnt, 1);
        CHECK_EQ_INT(s.f.ndof[0], 2);
        CHECK_EQ_INT(s.ct.collider[0], 1); /* the sphere is deeper (4.7 mm vs 1 mm) */
        CHECK_EQ_INT(s.ct.collider[1], 0);
        double n1[3], n2[3];
        double d1 = shell_d(&cs[0], s.x, n1), d2 = shell_d(&cs[1], s.x, n2);
        CHECK(d1 >= -1e-12 && d1 <= 1e-12);
        CHECK(d2 >= -1e-12 && d2 <= 1e-12);
        const double* S = s.f.S;
        double SS[9], Sn[3], tr = S[0] + S[4] + S[8];
        m3_mul(SS, S, S);
        double err = 0.0;
        for (int q = 0; q < 9; ++q) err = fmax(err, fabs(SS[q] - S[q]));
        for (int q = 0; q < 3; ++q)
            for (int p = 0; p < 3; ++p) err = fmax(err, fabs(S[3 * q + p] - S[3 * p + q]));
        CHECK(err < 1e-15);
        CHECK_NEAR(tr, 1.0, 1e-15);
        m3_mulv(Sn, S, n1);
        CHECK(v3_norm(Sn) < 1e-15);
        m3_mulv(Sn, S, n2);
        CHECK(v3_norm(Sn) < 1e-15);
        CHECK_NEAR(S[8], 1.0, 1e-15); /* the crease runs along z */
        sim_solve(&s, h);
        CHECK_NEAR(v3_dot(s.v, n1), 0.0, 1e-13);
        CHECK_NEAR(v3_dot(s.v, n2), 0.0, 1e-13);
        CHECK_NEAR(s.v[2], 0.1, 1e-15);
        wc_contacts_end(&s.ct, cs, 2, s.r, s.mass, h, s.v, &s.par);
        if (variant == 0) {
            CHECK_EQ_INT(s.ct.collider[0], 1); /* deepest first */
            CHECK_EQ_INT(s.ct.collider[1], 0);
            CHECK_EQ_INT(s.ct.released[0], 0);
        } else if (variant == 1) {
            CHECK_EQ_INT(s.ct.collider[0], 0);
            CHECK_EQ_INT(s.ct.collider[1], -1);
            CHECK_EQ_INT(s.ct.released[0], 1);
        }
        sim_free(&s);
    }
    /* nearly parallel normals (two planes 1 degree apart): one constraint */
    double t = 1.0 * 3.14159265358979 / 180.0;
    wc_collider pp[2] = {plane(0, 1, 0, 0.0), plane(sin(t), cos(t), 0, 0.0)};
    sim s;
    sim_init(&s, 1, 1);
    v3_set(s.x, 0.0, -0.01, 0.0);
    sim_reset_filter(&s);
    wc_contacts_begin(&s.ct, pp, 2, s.x, s.v, 0.01, &s.f, &s.par);
    CHECK_EQ_INT(s.f.ndof[0], 1);
    CHECK_EQ_INT(s.ct.collider[1], -1);
    sim_free(&s);
}

/* Pinned particles are never touched; line-pinned ones get no contact constraint (their filter
 * entry stays) but are still projected out. */
static void test_pinned(void) {
    wc_collider c = sphere(0, 0, 0, 1.0);
    sim s;
    sim_init(&s, 2, 1);
    s.pinned[0] = 3;
    s.pinned[1] = 2;
    v3_set(s.x, 0.5, 0.0, 0.0);
    v3_set(s.x + 3, 0.0, 0.5, 0.0);
    v3_set(s.v, 0.0, -1.0, 0.0);
    v3_set(s.v + 3, 0.0, -1.0, 0.0);
    sim_reset_filter(&s);
    double S1[9];
    memcpy(S1, s.f.S + 9, sizeof S1);
    int cnt = wc_contacts_begin(&s.ct, &c, 1, s.x, s.v, 0.01, &s.f, &s.par);
    CHECK_EQ_INT(cnt, 0);
    CHECK_NEAR(s.x[0], 0.5, 0);
    CHECK_NEAR(s.x[4], 0.5, 0);
    CHECK_EQ_INT(s.f.ndof[0], 3);
    CHECK_EQ_INT(s.f.ndof[1], 2);
    CHECK(memcmp(S1, s.f.S + 9, sizeof S1) == 0);
    int moved = wc_contacts_project(&s.ct, &c, 1, &s.f, s.x, s.v, &s.par);
    CHECK_EQ_INT(moved, 1);
    CHECK_NEAR(s.x[0], 0.5, 0);
    CHECK_NEAR(s.v[1], -1.0, 0);
    CHECK_NEAR(s.x[4], 1.0, 1e-15);
    CHECK_NEAR(s.v[4], 0.0, 1e-15);
    sim_free(&s);
}

/* Many particles raining onto a plane, a sphere and a capsule: never inside after a substep,
 * and bit-identical with 1 and 2 threads. */
static void rain(int threads, double* x_out, double* v_out, int n, int* worst_ok) {
    double a[3] = {-0.8, 0.3, -0.5}, b[3] = {0.8, 0.4, 0.5};
    wc_collider cs[3] = {plane(0.1, 1, 0, 0.0), sphere(0.3, 0.2, 0.1, 0.4), capsule(a, b, 0.15)};
    for (int k = 0; k < 3; ++k) {
        cs[k].thickness = 0.005;
        cs[k].friction = 0.3;
    }
    sim s;
    sim_init(&s, n, threads);
    rng_state = 12345;
    for (int i = 0; i < n; ++i) {
        v3_set(s.x + 3 * i, srand1(1.0), 0.2 + 1.5 * urand(), srand1(1.0));
        v3_set(s.v + 3 * i, srand1(1.0), srand1(3.0), srand1(1.0));
        if (i % 17 == 0) s.pinned[i] = 3;
    }
    set_gravity(&s, 9.81);
    int ok = 1;
    for (int step = 0; step < 120; ++step) {
        sim_step(&s, cs, 3, 1.0 / 120.0);
        for (int i = 0; i < n; ++i) {
            if (s.pinned[i]) continue;
            for (int k = 0; k < 3; ++k) {
                double nn[3];
                if (shell_d(&cs[k], s.x + 3 * i, nn) < -1e-9) ok = 0;
            }
        }
    }
    *worst_ok = ok;
    int two = 0;
    for (int i = 0; i < n; ++i) two += s.ct.collider[2 * i + 1] >= 0;
    CHECK(s.ct.active > n / 2);
    CHECK(two > 0);
    printf("rain: %d threads, %d of %d particles in contact at the end (%d with two)\n", threads, s.ct.active, n,
           two);
    memcpy(x_out, s.x, sizeof(double) * 3 * n);
    memcpy(v_out, s.v, sizeof(double) * 3 * n);
    sim_free(&s);
}

static void test_rain_deterministic(void) {
    enum { N = 2000 };
    double* x1 = malloc(sizeof(double) * 3 * N);
    double* v1 = malloc(sizeof(double) * 3 * N);
    double* x2 = malloc(sizeof(double) * 3 * N);
    double* v2 = malloc(sizeof(double) * 3 * N);
    int ok1, ok2;
    rain(1, x1, v1, N, &ok1);
    rain(2, x2, v2, N, &ok2);
    CHECK(ok1);
    CHECK(ok2);
    CHECK(memcmp(x1, x2, sizeof(double) * 3 * N) == 0);
    CHECK(memcmp(v1, v2, sizeof(double) * 3 * N) == 0);
    free(x1); free(v1); free(x2); free(v2);
}

int main(void) {
    RUN_TEST(test_distance_plane);
    RUN_TEST(test_distance_sphere);
    RUN_TEST(test_distance_capsule);
    RUN_TEST(test_fall_and_rest);
    RUN_TEST(test_landing_and_correction);
    RUN_TEST(test_moving_collider);
    RUN_TEST(test_keep_and_release);
    RUN_TEST(test_slide_off_sphere);
    RUN_TEST(test_friction);
    RUN_TEST(test_two_contacts);
    RUN_TEST(test_pinned);
    RUN_TEST(test_rain_deterministic);
    return TEST_SUMMARY();
}
