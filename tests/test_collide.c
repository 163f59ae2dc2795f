/* Colliders' contacts (core/collide.h; their distances: test_collider_distance). Contacts run
 * through a test-local substep with a block-diagonal system (particles alone: A = m I, plus the
 * kinetic friction's damping), solved per particle through the filter, r = A dv - b; positions
 * then move x += h v. Friction is checked against Coulomb's closed forms for a particle alone
 * (sliding to rest, landing, a groove, an incline, a moving plane, an integrator's momentum
 * term); test_step_contacts checks it on cloth. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "collide_friction.h"
#include "colliders.h"

/* ---- a test-local substep ---- */

typedef struct sim {
    int n;
    double *x, *v, *mass, *force, *r, *dv, *b;
    double* A;               /* (n x 9) the diagonal system's blocks: m I, plus kinetic friction */
    int* diag;               /* (n) block of row i: i */
    const wc_collider* c;    /* the colliders of the substep (for friction) */
    int nc;
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
    s->b = calloc((size_t)3 * n, sizeof(double));
    s->A = calloc((size_t)9 * n, sizeof(double));
    s->diag = malloc(sizeof(int) * n);
    for (int i = 0; i < n; ++i) s->diag[i] = i;
    s->c = NULL;
    s->nc = 0;
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
    s->ct.stick = calloc((size_t)n, 1);
    s->ct.vel = NULL; /* each collider's rigid velocity */
    s->ct.pushed = NULL; /* no push_speed cap */
    s->ct.active = 0;
    for (int i = 0; i < 2 * n; ++i) s->ct.collider[i] = -1;
    for (int i = 0; i < n; ++i) wc_filter_free_particle(&s->f, i);
    wc_par_init(&s->par, threads);
}

static void sim_free(sim* s) {
    free(s->x); free(s->v); free(s->force); free(s->r); free(s->dv); free(s->b); free(s->A); free(s->diag); free(s->mass); free(s->pinned);
    free(s->f.S); free(s->f.z); free(s->f.ndof);
    free(s->ct.collider); free(s->ct.normal); free(s->ct.released); free(s->ct.stick);
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

/* Contacts of a substep (wc_contacts_begin), remembering the colliders for the friction. */
static int sim_begin(sim* s, const wc_collider* c, int nc, double h) {
    s->c = c;
    s->nc = nc;
    return wc_contacts_begin(&s->ct, c, nc, s->x, s->v, h, &s->f, &s->par);
}

/* Filtered solve of the block-diagonal system: dv_i = z_i + S_i y_i with
 * (S A_ii S + I - S) y_i = S (b_i - A_ii z_i); r = A dv - b. */
static void sim_filtered_solve(sim* s) {
    for (int i = 0; i < s->n; ++i) {
        const double* Aii = s->A + 9 * i;
        const double* S = s->f.S + 9 * i;
        const double* z = s->f.z + 3 * i;
        double Az[3], rhs[3], Srhs[3], T[9], M[9], Minv[9], y[3], Sy[3];
        m3_mulv(Az, Aii, z);
        v3_sub(rhs, s->b + 3 * i, Az);
        m3_mulv(Srhs, S, rhs);
        m3_mul(T, Aii, S);
        m3_mul(M, S, T);
        for (int k = 0; k < 9; ++k) M[k] += (k % 4 == 0 ? 1.0 : 0.0) - S[k];
        if (m3_inverse(Minv, M) == 0.0) m3_identity(Minv, 1.0); /* never: M is SPD */
        m3_mulv(y, Minv, Srhs);
        m3_mulv(Sy, S, y);
        v3_add(s->dv + 3 * i, z, Sy);
        m3_mulv(s->r + 3 * i, Aii, s->dv + 3 * i);
        v3_sub(s->r + 3 * i, s->r + 3 * i, s->b + 3 * i);
    }
}

/* The step's solve with A = m I, b = h force: friction (sticking as constraints, sliding as
 * damping in A and b), the solve, the re-solves while sticking contacts let go; v += dv. */
static void sim_solve(sim* s, double h) {
    for (int i = 0; i < s->n; ++i) m3_identity(s->A + 9 * i, s->mass[i]);
    for (int k = 0; k < 3 * s->n; ++k) s->b[k] = h * s->force[k];
    int stuck = wc_contacts_friction(&s->ct, s->c, s->nc, s->v, s->mass, s->force, NULL, h, &s->f, s->A, s->diag, s->b,
                                     &s->par);
    sim_filtered_solve(s);
    for (int pass = 0; pass < 4 && stuck > 0; ++pass) {
        int changed = wc_contacts_friction_recheck(&s->ct, s->c, s->nc, s->v, s->mass, s->r, &s->f, s->A, s->diag,
                                                   s->b, &s->par);
        if (changed == 0) break;
        stuck -= changed;
        sim_filtered_solve(s);
    }
    for (int k = 0; k < 3 * s->n; ++k) s->v[k] += s->dv[k];
}

/* One substep; returns particles projected. */
static int sim_step(sim* s, const wc_collider* c, int nc, double h) {
    sim_reset_filter(s);
    sim_begin(s, c, nc, h);
    sim_solve(s, h);
    wc_contacts_end(&s->ct, nc, s->r, &s->par);
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
    int cnt = sim_begin(&s, &c, 1, h);
    CHECK_EQ_INT(cnt, 2);
    CHECK_NEAR(s.x[1], 0.035, 0);           /* not moved */
    CHECK_NEAR(s.x[4], 0.02, 1e-15);        /* pushed onto the shell */
    CHECK_EQ_INT(s.f.ndof[0], 1);
    sim_solve(&s, h);
    CHECK_NEAR(s.v[1], -1.5, 1e-12);        /* -d / h */
    CHECK_NEAR(s.v[0], 1.0, 1e-15);         /* tangential untouched (no friction yet) */
    CHECK_NEAR(s.v[4], 0.0, 1e-15);
    CHECK_NEAR(s.v[5], 0.5, 1e-15);
    wc_contacts_end(&s.ct, 1, s.r, &s.par);
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
    sim_begin(&s, &c, 1, 0.01);
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
    sim_begin(&s, &c, 1, h);
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

/* Coulomb friction of one particle alone (A = m I), against closed forms. Sliding on a plane
 * (resting on it, or moving with it) the relative tangential speed falls by mu g h per substep
 * (the friction impulse mu m g h), keeps its direction, reaches exactly 0 in substep
 * ceil(|u0| / (mu g h)) and stays there (the contact sticks: the particle moves with the plane);
 * it never reverses. */
static void test_friction_slide_to_rest(void) {
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
            double u0[3] = {s.v[0] - c.velocity[0], 0.0, s.v[2] - c.velocity[2]};
            double st0 = v3_norm(u0);
            int bad_speed = 0, reversed = 0, bad_normal = 0, stuck_at = -1, unstuck = 0;
            for (int step = 1; step <= 200; ++step) {
                sim_step(&s, &c, 1, h);
                double u[3] = {s.v[0] - c.velocity[0], 0.0, s.v[2] - c.velocity[2]};
                double expect = fmax(0.0, st0 - mus[k] * g * h * step);
                if (!(fabs(v3_norm(u) - expect) <= 1e-12)) ++bad_speed;
                if (v3_dot(u, u0) < 0.0 || fabs(u[0] * u0[2] - u[2] * u0[0]) > 1e-14) ++reversed;
                if (fabs(s.v[1]) > 1e-15 || fabs(s.x[1]) > 1e-15) ++bad_normal;
                if (stuck_at < 0 && s.ct.stick[0]) stuck_at = step;
                if (stuck_at >= 0 && !s.ct.stick[0]) ++unstuck;
            }
            CHECK_EQ_INT(bad_speed, 0);
            CHECK_EQ_INT(reversed, 0);
            CHECK_EQ_INT(bad_normal, 0);
            CHECK_EQ_INT(unstuck, 0);
            if (k == 0) {
                CHECK_EQ_INT(stuck_at, -1); /* frictionless: never stuck */
            } else {
                CHECK_EQ_INT(stuck_at, (int)ceil(st0 / (mus[k] * g * h)));
                CHECK_NEAR(s.v[0], c.velocity[0], 0.0);
                CHECK_NEAR(s.v[2], c.velocity[2], 0.0);
            }
            sim_free(&s);
        }
}

/* The integrator's momentum term (wc_contacts_friction's mom: TR-BDF2's trapezoidal stage, where
 * M mom = h f_n is the explicit half of the force, bdf2.h): the particle alone gets M mom + h f,
 * so a particle resting on a plane under gravity has the normal impulse 2 m g h, and a slip
 * mu g h < u0 <= 2 mu g h stops dead in one substep. Predicted without mom (as before), the
 * particle alone had half that bound: it slid, and kept 0.5 mu g h of its slip. */
static void test_friction_momentum_term(void) {
    const double h = 0.01, g = 9.81, mu = 0.5, u0 = 1.5 * mu * g * h;
    for (int with = 0; with < 2; ++with) {
        wc_collider c = plane(0, 1, 0, 0.0);
        c.friction = mu;
        sim s;
        sim_init(&s, 1, 1);
        set_gravity(&s, g);
        v3_set(s.v, u0, 0.0, 0.0);
        double mom[3];
        v3_scale(mom, s.force, h / s.mass[0]);
        sim_reset_filter(&s);
        CHECK_EQ_INT(sim_begin(&s, &c, 1, h), 1);
        m3_identity(s.A, s.mass[0]);
        for (int k = 0; k < 3; ++k) s.b[k] = h * s.force[k] + s.mass[0] * mom[k];
        int stuck = wc_contacts_friction(&s.ct, s.c, s.nc, s.v, s.mass, s.force, with ? mom : NULL, h, &s.f, s.A,
                                         s.diag, s.b, &s.par);
        sim_filtered_solve(&s);
        int changed = stuck ? wc_contacts_friction_recheck(&s.ct, s.c, s.nc, s.v, s.mass, s.r, &s.f, s.A, s.diag,
                                                           s.b, &s.par)
                            : 0;
        CHECK_EQ_INT(stuck, with);
        CHECK_EQ_INT(changed, 0);
        double slip = s.v[0] + s.dv[0];
        if (with) CHECK_NEAR(slip, 0.0, 1e-15);
        else CHECK_NEAR(slip, u0 - mu * g * h, 1e-12);
        CHECK_NEAR(s.v[1] + s.dv[1], 0.0, 1e-15);   /* it stays on the plane */
        sim_free(&s);
    }
}

/* Coulomb at a landing: a particle reaching a plane gets the normal impulse that stops its
 * approach, m vn' (vn' = vn - d / h: the constraint lands it on the shell at the end of the
 * substep), plus m g h; friction takes up to mu times that from its tangential momentum
 * m u0 in the same substep: u0 <= mu (vn' + g h): it stops dead; otherwise it keeps sliding with
 * u0 - mu (vn' + g h N) after N substeps. */
static void test_friction_landing(void) {
    const double h = 0.005, g = 9.81, mu = 0.5, vn = 2.0, x0 = 0.5 * vn * h;
    for (int fast = 0; fast < 2; ++fast) {
        double u0 = fast ? 3.0 : 0.2;
        wc_collider c = plane(0, 1, 0, 0.0);
        c.friction = mu;
        sim s;
        sim_init(&s, 1, 1);
        set_gravity(&s, g);
        v3_set(s.x, 0.0, x0, 0.0); /* lands half way through the first substep */
        v3_set(s.v, u0, -vn, 0.0);
        for (int step = 1; step <= 20; ++step) {
            sim_step(&s, &c, 1, h);
            CHECK_NEAR(s.x[1], 0.0, 1e-15);
            double expect = fast ? u0 - mu * (vn - x0 / h + g * h * step) : 0.0;
            CHECK_NEAR(s.v[0], expect, 1e-12);
        }
        sim_free(&s);
    }
}

/* Two contacts: a particle sliding along the bottom of a V groove (two planes whose normals lean
 * +-alpha from vertical). Each wall pushes with m g / (2 cos(alpha)), so the friction bound is the
 * sum mu m g h / cos(alpha) per substep, counted once per wall: the speed falls by that much per
 * substep and stops exactly; alpha = 0 would be one plane. */
static void test_friction_groove(void) {
    const double h = 0.01, g = 9.81, mu = 0.3, u0 = 0.6;
    const double alpha = 30.0 * 3.14159265358979323846 / 180.0;
    wc_collider cs[2] = {plane(sin(alpha), cos(alpha), 0, 0.0), plane(-sin(alpha), cos(alpha), 0, 0.0)};
    cs[0].friction = cs[1].friction = mu;
    sim s;
    sim_init(&s, 1, 1);
    set_gravity(&s, g);
    v3_set(s.v, 0.0, 0.0, u0);
    int bad = 0, two = 1;
    for (int step = 1; step <= 40; ++step) {
        sim_step(&s, cs, 2, h);
        double expect = fmax(0.0, u0 - mu * g * h * step / cos(alpha));
        if (!(fabs(s.v[2] - expect) <= 1e-12) || fabs(s.v[0]) > 1e-15 || fabs(s.v[1]) > 1e-15) ++bad;
        two &= s.ct.collider[1] >= 0;
    }
    CHECK_EQ_INT(bad, 0);
    CHECK(two);
    CHECK(s.ct.stick[0]);
    CHECK_NEAR(s.v[2], 0.0, 0.0);
    sim_free(&s);
}

/* A particle at rest on a plane inclined by theta: it stays exactly where it is when
 * tan(theta) < mu; otherwise it slides down with a = g (sin(theta) - mu cos(theta)). Backward
 * Euler (v += h a, then x += h v) gives x_N = a h^2 N (N + 1) / 2 = a (T^2 + h T) / 2, a h T / 2
 * from the closed form a T^2 / 2 (first order in h): checked with tolerance a h T, and the error
 * halving as h halves. */
static double incline_run(double theta, double mu, double h, double T, double* drift) {
    const double g = 9.81;
    wc_collider c = plane(-sin(theta), cos(theta), 0, 0.0);
    c.friction = mu;
    sim s;
    sim_init(&s, 1, 1);
    set_gravity(&s, g);
    double down[3] = {-cos(theta), -sin(theta), 0.0}, worst_normal = 0.0;
    int steps = (int)lround(T / h);
    *drift = 0.0;
    for (int step = 0; step < steps; ++step) {
        sim_step(&s, &c, 1, h);
        double nn[3];
        worst_normal = fmax(worst_normal, fabs(shell_d(&c, s.x, nn)));
        *drift = fmax(*drift, v3_norm(s.x));
        CHECK(v3_dot(s.v, down) >= 0.0); /* never up the slope */
    }
    CHECK(worst_normal < 1e-14);
    double along = v3_dot(s.x, down);
    sim_free(&s);
    return along;
}

static void test_friction_incline(void) {
    const double g = 9.81, T = 1.0;
    const double deg = 3.14159265358979323846 / 180.0;
    struct { double theta, mu; } cases[] = {{20 * deg, 0.5}, {30 * deg, 0.6}, {40 * deg, 0.85}, {30 * deg, 0.3},
                                             {40 * deg, 0.5}, {20 * deg, 0.1}};
    for (int k = 0; k < 6; ++k) {
        double th = cases[k].theta, mu = cases[k].mu, drift;
        if (tan(th) < mu) {
            incline_run(th, mu, 0.01, T, &drift);
            printf("  incline %2.0f deg, mu %.2f (tan %.3f): sticks, drift %.2g m\n", th / deg, mu, tan(th), drift);
            CHECK(drift == 0.0);
        } else {
            double a = g * (sin(th) - mu * cos(th)), exact = 0.5 * a * T * T;
            double e1 = incline_run(th, mu, 0.01, T, &drift) - exact;
            double e2 = incline_run(th, mu, 0.005, T, &drift) - exact;
            printf("  incline %2.0f deg, mu %.2f (tan %.3f): slides %.5f m in %g s (closed form %.5f): "
                   "error %.2e at h = 0.01, %.2e at h = 0.005\n", th / deg, mu, tan(th), exact + e1, T, exact, e1, e2);
            CHECK(fabs(e1) <= a * 0.01 * T);
            CHECK(fabs(e2) <= a * 0.005 * T);
            CHECK_NEAR(e1 / e2, 2.0, 0.05); /* first order */
        }
    }
}

/* A plane moving along itself at speed V drags a particle resting on it: the particle's speed
 * rises by mu g h per substep, never passes V, reaches it exactly and then moves with the plane
 * (stuck). */
static void test_friction_drag(void) {
    const double h = 0.01, g = 9.81, mu = 0.4, V = 0.5;
    wc_collider c = plane(0, 1, 0, 0.0);
    c.friction = mu;
    v3_set(c.velocity, V, 0.0, 0.0);
    sim s;
    sim_init(&s, 1, 1);
    set_gravity(&s, g);
    int bad = 0, beyond = 0;
    double prev = 0.0;
    for (int step = 1; step <= 60; ++step) {
        sim_step(&s, &c, 1, h);
        double expect = fmin(V, mu * g * h * step);
        if (!(fabs(s.v[0] - expect) <= 1e-12)) ++bad;
        if (s.v[0] > V || s.v[0] < prev) ++beyond;
        prev = s.v[0];
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(beyond, 0);
    CHECK_NEAR(s.v[0], V, 0.0);
    CHECK(s.ct.stick[0]);
    sim_free(&s);
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
        int cnt = sim_begin(&s, cs, 2, h);
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
        wc_contacts_end(&s.ct, 2, s.r, &s.par);
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
    sim_begin(&s, pp, 2, 0.01);
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
    int cnt = sim_begin(&s, &c, 1, 0.01);
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
    RUN_TEST(test_fall_and_rest);
    RUN_TEST(test_landing_and_correction);
    RUN_TEST(test_moving_collider);
    RUN_TEST(test_keep_and_release);
    RUN_TEST(test_slide_off_sphere);
    RUN_TEST(test_friction_slide_to_rest);
    RUN_TEST(test_friction_landing);
    RUN_TEST(test_friction_momentum_term);
    RUN_TEST(test_friction_groove);
    RUN_TEST(test_friction_incline);
    RUN_TEST(test_friction_drag);
    RUN_TEST(test_two_contacts);
    RUN_TEST(test_pinned);
    RUN_TEST(test_rain_deterministic);
    return TEST_SUMMARY();
}
