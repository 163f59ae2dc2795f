/* Triangle-mesh colliders (core/mesh_collider.h) in the step: the mesh sphere's signed distance
 * against the analytic sphere's (within the icosphere's sagitta); a sheet dropped on a static
 * icosphere and on a box with sharp edges never has a particle behind the surface (nor deeper
 * than rounding into the thickness shell) at any frame and comes to rest; a thin bar moving at
 * 15 m/s (30 bar widths per frame, one step per frame) through a hanging sheet pushes it and no
 * particle's path ever crosses the bar (checked after every frame with the crossing test on the
 * frame's motion, and the penetration measure; the crossing tests of begin and of the projection
 * checked alone, each failing when disabled); a deforming flat collider (its vertices moved
 * sideways every frame by the test) carries a cloth resting on it by friction (Coulomb's
 * closed form: it lags by v^2 / (2 mu g)), and leaves it where it is without friction. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "step.h"
#include "test_meshes.h"
#include "test_support.h"
#include "vec3.h"

/* Flat square grid of (n+1)^2 vertices in the plane y = 0, [-s/2, s/2]^2, normals +y. */
static void square(tmesh* m, int n, double s) {
    m->nv = m->nt = 0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) tm_vert(m, -0.5 * s + s * i / n, 0.0, -0.5 * s + s * j / n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            int a = i + (n + 1) * j, b = a + (n + 1), c = a + 1, d = b + 1;
            tm_tri(m, a, b, c);
            tm_tri(m, c, b, d);
        }
}

static wc_mesh_collider* make_collider(const tmesh* t, double thickness, double friction) {
    wc_mesh_collider* mc = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, t->x, t->nv, t->t, t->nt, thickness, friction, NULL, &d), WC_OK);
    return mc;
}

/* Deepest particle into the shell (thickness - signed distance; <= 0 when none). */
static double shell_depth(const wc_mesh_collider* mc, const double* x, int n) {
    double worst = -HUGE_VAL;
    for (int i = 0; i < n; ++i) {
        double d = wc_mesh_closest(mc, 1, x + 3 * i, HUGE_VAL, NULL, NULL);
        if (mc->thickness - d > worst) worst = mc->thickness - d;
    }
    return worst;
}

/* ---- tests ------------------------------------------------------------------------------------- */

static tmesh g_mesh;

static void test_sphere_distance_matches_analytic(void) {
    double c[3] = {0.05, 0.3, 0.02}, r = 0.3;
    icosphere(&g_mesh, 3, r, c);
    wc_mesh_collider* mc = make_collider(&g_mesh, 0.0, 0.0);
    /* the flat facets lie inside the sphere by at most the sagitta r (1 - cos(theta)), theta the
       angle from a facet's centre to its vertices */
    double sag = 0.0;
    for (int t = 0; t < g_mesh.nt; ++t) {
        double ctr[3] = {0, 0, 0};
        for (int k = 0; k < 3; ++k) v3_axpy(ctr, 1.0 / 3.0, g_mesh.x + 3 * g_mesh.t[3 * t + k]);
        double dc[3];
        v3_sub(dc, ctr, c);
        double s = r - v3_norm(dc);
        if (s > sag) sag = s;
    }
    unsigned rs = 7u;
    double worst = 0.0, worst_n = 0.0;
    for (int k = 0; k < 2000; ++k) {
        double p[3], dir[3];
        for (int q = 0; q < 3; ++q) {
            rs = rs * 1664525u + 1013904223u;
            dir[q] = (double)(rs >> 8) / (1u << 24) * 2.0 - 1.0;
        }
        rs = rs * 1664525u + 1013904223u;
        double rad = 0.05 + 0.5 * (double)(rs >> 8) / (1u << 24);
        double len = v3_norm(dir);
        for (int q = 0; q < 3; ++q) p[q] = c[q] + rad * dir[q] / len;
        double n[3], dm = wc_mesh_closest(mc, 1, p, HUGE_VAL, n, NULL);
        double da = rad - r;
        if (fabs(dm - da) > worst) worst = fabs(dm - da);
        /* the normal points away from the centre (outside: p - q; inside: the face's) */
        double radial[3];
        v3_scale(radial, dir, 1.0 / len);
        if (1.0 - v3_dot(n, radial) > worst_n) worst_n = 1.0 - v3_dot(n, radial);
        /* the bounded query agrees when the surface is within reach */
        double db = wc_mesh_closest(mc, 1, p, fabs(dm) + 1e-3, NULL, NULL);
        CHECK_NEAR(db, dm, 1e-12);
    }
    printf("  icosphere (%d triangles): |d_mesh - d_sphere| <= %.3g m (sagitta %.3g m), normals within %.3g rad\n",
           g_mesh.nt, worst, sag, acos(1.0 - worst_n));
    CHECK(worst <= sag + 1e-12);
    CHECK(worst_n < 0.1);
    double far[3] = {5, 5, 5};
    CHECK(wc_mesh_closest(mc, 1, far, 0.5, NULL, NULL) == HUGE_VAL);
    wc_mesh_collider_destroy(mc);
}

/* A sheet dropped on a static mesh (and a floor plane); returns the largest speed at the end.
 * newton > 1: that many Newton iterations with a line search (the CPU backend's default is 2). */
static void drop_on(const char* name, const tmesh* t, double thickness, double friction, int newton) {
    int n = 16;
    wc_model m;
    CHECK(ts_sheet(&m, n, 1.0, 0.8, 0, 1.0));
    wc_state* s = NULL;
    wc_diag d = {0};
    wc_sim_def sd = wc_default_sim_def();
    if (newton > 1) {
        sd.newton_iterations = newton;
        sd.line_search = 1;
    }
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    wc_mesh_collider* mc = make_collider(t, thickness, friction);
    CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, &mc, 1, &d), WC_OK);
    wc_collider floor;
    memset(&floor, 0, sizeof floor);
    floor.type = WC_COLLIDER_PLANE;
    v3_set(floor.normal, 0, 1, 0);
    floor.thickness = 0.01;
    floor.friction = 0.5;
    CHECK_EQ_INT(wc_state_set_colliders(s, &floor, 1, &d), WC_OK);
    double worst_pen = 0.0, worst_shell = -HUGE_VAL;
    int contacts = 0, failed = 0, rollbacks = 0, pairs = 0;
    for (int f = 0; f < 150; ++f) {
        wc_step_stats st;
        if (wc_step_frame(s, 1.0 / 30, &st, &d) != WC_OK) ++failed;
        contacts = st.contacts;
        rollbacks += st.rollbacks;
        pairs += st.mesh_pairs_active;
        const wc_mesh_collider* cm = mc;
        double pen = wc_mesh_max_penetration(&cm, 1, s->x, m.n_particles);
        if (pen > worst_pen) worst_pen = pen;
        double sh = shell_depth(mc, s->x, m.n_particles);
        if (sh > worst_shell) worst_shell = sh;
    }
    double speed = wc_state_max_speed(s);
    printf("  %-6s (Newton %d): behind the surface %.3g m, into the %.3g m shell %.3g m at worst; %d in contact, "
           "%d feature pairs active (summed over substeps), %d rollbacks, fastest %.3g m/s at the end%s\n",
           name, newton, worst_pen, thickness, worst_shell, contacts, pairs, rollbacks, speed,
           s->asleep ? " (asleep)" : "");
    CHECK_EQ_INT(failed, 0);
    CHECK(worst_pen == 0.0);
    CHECK(worst_shell <= 1e-6);
    CHECK(contacts > 0);
    CHECK(speed < 0.05);
    wc_state_destroy(s);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
}

static void test_drop_on_sphere(void) {
    double c[3] = {0.05, 0.3, 0.02};
    icosphere(&g_mesh, 2, 0.3, c);
    drop_on("sphere", &g_mesh, 0.01, 0.4, 1);
    drop_on("sphere", &g_mesh, 0.01, 0.4, 2);
}

static void test_drop_on_box(void) {
    double lo[3] = {-0.25, 0.0, -0.2}, hi[3] = {0.25, 0.15, 0.2}; /* the sheet drapes down to the floor */
    box(&g_mesh, lo, hi);
    drop_on("box", &g_mesh, 0.005, 0.4, 1);
    drop_on("box", &g_mesh, 0.005, 0.4, 2);
}

static void test_fast_bar(void) {
    int n = 20;
    wc_model m;
    CHECK(ts_sheet(&m, n, 1.0, 1.0, 1, 1.0)); /* hanging in the XY plane, y in [0, 1], z = 0 */
    wc_state* s = NULL;
    wc_diag d = {0};
    wc_sim_def sd = wc_default_sim_def();
    sd.strain_limit = 0.1;
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    wc_pin pins[2];
    memset(pins, 0, sizeof pins);
    pins[0].particle = ts_sheet_particle(&m, n, 0, n - 1);
    pins[1].particle = ts_sheet_particle(&m, n, n - 1, n - 1);
    for (int k = 0; k < 2; ++k) v3_copy(pins[k].target, m.rest_pos + 3 * pins[k].particle);
    CHECK_EQ_INT(wc_state_set_pins(s, pins, 2, &d), WC_OK);
    /* a bar 2 m long (x), 2 cm x 2 cm, across the sheet's lower part, rising as it goes */
    double lo[3] = {-1.0, 0.1, -0.01}, hi[3] = {1.0, 0.12, 0.01};
    box(&g_mesh, lo, hi);
    double z0 = -0.35, speed = 15.0, rise = 4.0, dt = 1.0 / 25;
    for (int v = 0; v < g_mesh.nv; ++v) g_mesh.x[3 * v + 2] += z0;
    wc_mesh_collider* mc = make_collider(&g_mesh, 0.005, 0.3);
    CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, &mc, 1, &d), WC_OK);
    int np = m.n_particles, crossed = 0, failed = 0;
    double* prev = malloc(3 * (size_t)np * sizeof(double));
    double* target = malloc(3 * (size_t)g_mesh.nv * sizeof(double));
    double worst_pen = 0.0, pushed = 0.0;
    for (int f = 0; f < 8; ++f) {
        memcpy(prev, s->x, 3 * (size_t)np * sizeof(double));
        for (int v = 0; v < g_mesh.nv; ++v) {
            v3_copy(target + 3 * v, g_mesh.x + 3 * v);
            target[3 * v + 2] += speed * dt * (f + 1);
            target[3 * v + 1] += rise * dt * (f + 1);
        }
        CHECK_EQ_INT(wc_state_set_mesh_target(s, 0, target, &d), WC_OK);
        if (wc_step_frame(s, dt, NULL, &d) != WC_OK) ++failed;
        /* one substep per frame: the collider's last substep is the whole frame (xa -> xb) */
        for (int i = 0; i < np; ++i) {
            double t, w[3];
            int tri;
            if (wc_mesh_ccd(mc, prev + 3 * i, s->x + 3 * i, 0.0, &t, &tri, w)) ++crossed;
            if (s->x[3 * i + 2] > pushed) pushed = s->x[3 * i + 2];
        }
        const wc_mesh_collider* cm = mc;
        double pen = wc_mesh_max_penetration(&cm, 1, s->x, np);
        if (pen > worst_pen) worst_pen = pen;
    }
    printf("  bar at %.0f m/s (%.0f widths a frame): %d particle paths crossed it, %.3g m behind its surface at "
           "worst, the sheet pushed to z = %.3g m, %d failed frames\n",
           speed, speed * dt / 0.02, crossed, worst_pen, pushed, failed);
    CHECK_EQ_INT(crossed, 0);
    CHECK(worst_pen == 0.0);
    CHECK(pushed > 0.3);
    CHECK_EQ_INT(failed, 0);
    free(prev);
    free(target);
    wc_state_destroy(s);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
}

/* The last resort alone (wc_contacts_project_from): a particle whose substep path went through
 * a 2 cm bar, ending outside it on the far side, is put back in front of the face it crossed,
 * at the thickness, with no velocity into the bar; without the start positions (closest point
 * only) it stays on the wrong side. Also a bar that sweeps over a particle at rest. */
static void test_projection_uncrosses(void) {
    double lo[3] = {-1.0, -0.01, -0.01}, hi[3] = {1.0, 0.01, 0.01};
    box(&g_mesh, lo, hi);
    wc_mesh_collider* mc = make_collider(&g_mesh, 0.005, 0.3);
    wc_collider c;
    memset(&c, 0, sizeof c);
    c.type = WC_COLLIDER_MESH;
    c.mesh = mc;
    c.thickness = mc->thickness;
    c.friction = mc->friction;
    int cid[2] = {-1, -1};
    double cn[6] = {0}, cv[6] = {0};
    unsigned char rel = 0, stick = 0;
    wc_contacts ct = {1, cid, cn, &rel, &stick, 0, cv, NULL, 0.0, NULL, 0};
    wc_par par;
    wc_par_init(&par, 1);
    wc_mesh_collider_substep(mc, 0.0, 1.0, 0.04);
    double x0[3] = {0.1, 0.0, -0.1}, x[3] = {0.1, 0.0, 0.1}, v[3] = {0.0, 0.0, 5.0};
    CHECK_EQ_INT(wc_contacts_project_from(&ct, &c, 1, NULL, x0, x, v, &par), 1);
    CHECK_NEAR(x[2], -0.015, 1e-12);
    CHECK_NEAR(v[2], 0.0, 1e-12);
    double y[3] = {0.1, 0.0, 0.1}, w[3] = {0.0, 0.0, 5.0};
    wc_contacts_project(&ct, &c, 1, NULL, y, w, &par);
    CHECK_NEAR(y[2], 0.1, 0); /* closest point only: the far side looks like the outside */
    /* the bar sweeps from z = -0.3 to z = +0.3 in the substep over a particle at rest at z = 0.1 */
    double* tgt = malloc(3 * (size_t)g_mesh.nv * sizeof(double));
    for (int k = 0; k < g_mesh.nv; ++k) {
        v3_copy(tgt + 3 * k, g_mesh.x + 3 * k);
        tgt[3 * k + 2] -= 0.3;
    }
    wc_diag d = {0};
    CHECK_EQ_INT(wc_mesh_collider_set_all(mc, tgt, &d), WC_OK);
    for (int k = 0; k < g_mesh.nv; ++k) tgt[3 * k + 2] += 0.6;
    CHECK_EQ_INT(wc_mesh_collider_set_target(mc, tgt, &d), WC_OK);
    wc_mesh_collider_substep(mc, 0.0, 1.0, 0.04);
    double p0[3] = {0.1, 0.0, 0.1}, p[3] = {0.1, 0.0, 0.1}, pv[3] = {0, 0, 0};
    CHECK_EQ_INT(wc_contacts_project_from(&ct, &c, 1, NULL, p0, p, pv, &par), 1);
    CHECK_NEAR(p[2], 0.3 + 0.01 + 0.005, 1e-12);
    CHECK_NEAR(pv[2], 15.0, 1e-9); /* the bar's speed 0.6 m / 0.04 s */
    printf("  uncrossed: a path through the bar ends at z = %.4g (front face - thickness = -0.015); a particle "
           "swept by it at z = %.4g, %.4g m/s\n", x[2], p[2], pv[2]);
    free(tgt);
    wc_mesh_collider_destroy(mc);
}

/* The crossing test of wc_contacts_begin: one mesh, a static floor plate 5 cm under a particle at
 * rest and a bar that sweeps through the particle in the substep (from z = -0.3 to 0.3). The
 * particle's closest point is on the plate (normal +y, no approach), so the closest-point rules
 * alone would leave it unconstrained; the crossing puts it in contact with the bar's front face,
 * with the velocity that lands it on the shell at the end: (0.3 + 0.01 + 0.005 - 0.1) / h. */
static void test_begin_catches_crossing(void) {
    double lo[3] = {-1.0, -0.01, -0.31}, hi[3] = {1.0, 0.01, -0.29};
    box(&g_mesh, lo, hi);
    int a = tm_vert(&g_mesh, -1, -0.05, -1), b = tm_vert(&g_mesh, -1, -0.05, 1), c2 = tm_vert(&g_mesh, 1, -0.05, -1);
    tm_tri(&g_mesh, a, b, c2);
    wc_mesh_collider* mc = make_collider(&g_mesh, 0.005, 0.0);
    double* tgt = malloc(3 * (size_t)g_mesh.nv * sizeof(double));
    memcpy(tgt, g_mesh.x, 3 * (size_t)g_mesh.nv * sizeof(double));
    for (int k = 0; k < 8; ++k) tgt[3 * k + 2] += 0.6;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_mesh_collider_set_target(mc, tgt, &d), WC_OK);
    double h = 0.04;
    wc_mesh_collider_substep(mc, 0.0, 1.0, h);
    wc_collider c;
    memset(&c, 0, sizeof c);
    c.type = WC_COLLIDER_MESH;
    c.mesh = mc;
    c.thickness = mc->thickness;
    int cid[2] = {-1, -1};
    double cn[6] = {0}, cv[6] = {0}, S[9], z[3];
    unsigned char rel = 0, stick = 0, ndof = 0;
    wc_contacts ct = {1, cid, cn, &rel, &stick, 0, cv, NULL, 0.0, NULL, 0};
    wc_filter f = {1, S, z, &ndof};
    wc_filter_free_particle(&f, 0);
    wc_par par;
    wc_par_init(&par, 1);
    double x[3] = {0.1, 0.0, 0.1}, v[3] = {0, 0, 0};
    CHECK_EQ_INT(wc_contacts_begin(&ct, &c, 1, x, v, h, &f, &par), 1);
    CHECK_EQ_INT(ndof, 1);
    CHECK_NEAR(cn[2], 1.0, 1e-12);          /* the bar's front face */
    CHECK_NEAR(cv[2], 15.0, 1e-9);          /* its velocity at the crossing point */
    CHECK_NEAR(z[2], (0.3 + 0.01 + 0.005 - 0.1) / h, 1e-9);
    printf("  begin: a particle the bar sweeps through (closest point on the plate) gets dv = %.4g m/s "
           "along the bar's face normal (lands on the shell)\n", z[2]);
    free(tgt);
    wc_mesh_collider_destroy(mc);
}

/* A 0.5 m sheet resting on a 3 m flat collider whose vertices the test moves along +x at speed
 * v from rest: returns the sheet's mean x displacement after `frames` frames of motion. */
static double carried(double friction, double v, int frames) {
    int n = 10;
    wc_model m;
    CHECK(ts_sheet(&m, n, 0.5, 0.02, 0, 1.0));
    wc_state* s = NULL;
    wc_diag d = {0};
    wc_sim_def sd = wc_default_sim_def();
    sd.substeps = 2;
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    square(&g_mesh, 6, 3.0);
    wc_mesh_collider* mc = make_collider(&g_mesh, 0.005, friction);
    CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, &mc, 1, &d), WC_OK);
    double dt = 1.0 / 30;
    int failed = 0;
    for (int f = 0; f < 20; ++f) /* settle */
        if (wc_step_frame(s, dt, NULL, &d) != WC_OK) ++failed;
    double x0 = 0.0, x1 = 0.0;
    for (int i = 0; i < m.n_particles; ++i) x0 += s->x[3 * i] / m.n_particles;
    double* target = malloc(3 * (size_t)g_mesh.nv * sizeof(double));
    for (int f = 0; f < frames; ++f) {
        /* deforming, not rigid: every vertex moved by the test, the far edge a little more */
        for (int k = 0; k < g_mesh.nv; ++k) {
            v3_copy(target + 3 * k, g_mesh.x + 3 * k);
            double stretch = g_mesh.x[3 * k] > 1.4 ? 1.01 : 1.0;
            target[3 * k] += v * dt * (f + 1) * stretch;
        }
        CHECK_EQ_INT(wc_state_set_mesh_target(s, 0, target, &d), WC_OK);
        if (wc_step_frame(s, dt, NULL, &d) != WC_OK) ++failed;
    }
    for (int i = 0; i < m.n_particles; ++i) x1 += s->x[3 * i] / m.n_particles;
    double y_min = HUGE_VAL;
    for (int i = 0; i < m.n_particles; ++i) y_min = fmin(y_min, s->x[3 * i + 1]);
    CHECK_EQ_INT(failed, 0);
    CHECK(y_min >= 0.005 - 1e-9);
    free(target);
    wc_state_destroy(s);
    wc_mesh_collider_destroy(mc);
    wc_model_free(&m);
    return x1 - x0;
}

static void test_deforming_carries(void) {
    double v = 0.3, mu = 0.5, g = 9.81;
    int frames = 30;
    double moved = carried(mu, v, frames), still = carried(0.0, v, frames);
    double expect = v * frames / 30.0 - v * v / (2 * mu * g);
    printf("  flat collider moving at %.2g m/s for %.2g s: sheet carried %.4g m with mu = %.2g (Coulomb: %.4g m), "
           "%.3g m without friction\n",
           v, frames / 30.0, moved, mu, expect, still);
    CHECK(fabs(moved - expect) < 0.1 * expect);
    CHECK(fabs(still) < 0.01);
}

/* Whether the collider moves in the frame: from != to on the host (any bit); on a device, what
 * its backend found (device_moves), whatever core's stale from and to hold. */
static void test_moving(void) {
    static tmesh t;
    square(&t, 2, 1.0);
    wc_mesh_collider* mc = make_collider(&t, 0.0, 0.0);
    if (!mc) return;
    wc_diag d = {0};
    CHECK(!wc_mesh_collider_moving(mc));
    double* x = malloc(3 * (size_t)t.nv * sizeof(double));
    memcpy(x, t.x, 3 * (size_t)t.nv * sizeof(double));
    x[4] = nextafter(x[4], 1.0);   /* one bit */
    CHECK_EQ_INT(wc_mesh_collider_set_target(mc, x, &d), WC_OK);
    CHECK(wc_mesh_collider_moving(mc));
    mc->on_device = 1;   /* the device's frame: core's from != to are stale */
    CHECK(!wc_mesh_collider_moving(mc));
    mc->device_moves = 1;
    CHECK(wc_mesh_collider_moving(mc));
    mc->on_device = mc->device_moves = 0;
    wc_mesh_collider_end_frame(mc);
    CHECK(!wc_mesh_collider_moving(mc));
    mc->on_device = mc->device_moves = 1;
    CHECK(wc_mesh_collider_moving(mc));
    free(x);
    wc_mesh_collider_destroy(mc);
}

int main(void) {
    RUN_TEST(test_moving);
    RUN_TEST(test_sphere_distance_matches_analytic);
    RUN_TEST(test_drop_on_sphere);
    RUN_TEST(test_drop_on_box);
    RUN_TEST(test_projection_uncrosses);
    RUN_TEST(test_begin_catches_crossing);
    RUN_TEST(test_fast_bar);
    RUN_TEST(test_deforming_carries);
    return TEST_SUMMARY();
}
