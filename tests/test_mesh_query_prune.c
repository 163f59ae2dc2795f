/* The mesh colliders' pruned searches against their unpruned references (mesh_collider.h's
 * `exhaustive`) and against brute force, on bodies that move, deform and teleport:
 *  - wc_mesh_closest (the BVH's boxes farther than the best found skipped, from a first guess)
 *    returns bit for bit what the full search of the same reach returns (distance, normal,
 *    surface velocity), at points near the surface (on vertices and edges too, where several
 *    triangles tie), inside, far away, at both ends of a substep, for finite and unbounded
 *    reaches; its distance is brute force's (every triangle) to rounding; through a walking
 *    point's kept candidates (wc_mesh_near: the last closest triangle's distance bounding the
 *    next search from the start, the plane-distance prune) the same, and through a list as it
 *    is (wc_mesh_closest_kept) from any of its triangles or none, and its crossings
 *    (wc_mesh_ccd_near, short paths and long ones beyond its list) are the tree's bit for bit;
 *    wc_mesh_front_kept's "in front" (and "within reach") never where the full search's signed
 *    distance is negative (or beyond reach), at those points and at points on a listed
 *    triangle's plane, 1e-13 or 3e-9 off it, or a few mm in front of it;
 *  - the feature-pair detection's mask (mesh_pairs.h: only subtrees with a sharp vertex) is 1
 *    exactly above the non-degenerate triangles with a sharp vertex;
 *  - a sheet falling onto a moving, deforming, teleported box (sharp: feature pairs) and sphere
 *    steps to bit for bit the same positions with the prunes as without them. */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "colliders.h"
#include "geom.h"
#include "mesh_pairs.h"
#include "step.h"
#include "test_support.h"

typedef struct tmesh {
    int nv, nt;
    double x[3 * 700];
    int t[3 * 1300];
} tmesh;

static int tm_vert(tmesh* m, double x, double y, double z) {
    v3_set(m->x + 3 * m->nv, x, y, z);
    return m->nv++;
}

static void tm_tri(tmesh* m, int a, int b, int c) {
    int* t = m->t + 3 * m->nt++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

/* A UV sphere (rings x segments) of radius r around c, outward winding, with its vertices moved
 * by up to `bump` (m) at random: a lumpy body with shallow and sharp bends. */
static void lumpy_sphere(tmesh* m, int rings, int segs, double r, const double* c, double bump) {
    m->nv = m->nt = 0;
    int top = tm_vert(m, 0, r, 0);
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            double pi = acos(-1.0), th = pi * i / rings, ph = 2 * pi * j / segs;
            tm_vert(m, r * sin(th) * cos(ph), r * cos(th), -r * sin(th) * sin(ph));
        }
    int bot = tm_vert(m, 0, -r, 0);
    for (int j = 0; j < segs; ++j) {
        int j1 = (j + 1) % segs;
        tm_tri(m, top, 1 + j, 1 + j1);
        tm_tri(m, bot, 1 + (rings - 2) * segs + j1, 1 + (rings - 2) * segs + j);
        for (int i = 0; i < rings - 2; ++i) {
            int a = 1 + i * segs + j, b = 1 + i * segs + j1, cc = a + segs, d = b + segs;
            tm_tri(m, a, cc, b);
            tm_tri(m, b, cc, d);
        }
    }
    for (int k = 0; k < m->nv; ++k)
        for (int q = 0; q < 3; ++q) m->x[3 * k + q] += c[q] + srand1(bump);
}

/* An axis-aligned box [lo, hi], each face 2 x 2 quads of its own vertices (the faces meet at
 * boundary edges: sharp), outward winding; degenerate: plus a zero-area triangle (a vertex
 * repeated) on the top face. */
static void box(tmesh* m, const double* lo, const double* hi, int degenerate) {
    m->nv = m->nt = 0;
    for (int ax = 0; ax < 3; ++ax)
        for (int side = 0; side < 2; ++side) {
            int u = (ax + 1) % 3, w = (ax + 2) % 3, base = m->nv;
            for (int j = 0; j <= 2; ++j)
                for (int i = 0; i <= 2; ++i) {
                    double p[3];
                    p[ax] = side ? hi[ax] : lo[ax];
                    p[u] = lo[u] + (hi[u] - lo[u]) * i / 2;
                    p[w] = lo[w] + (hi[w] - lo[w]) * j / 2;
                    tm_vert(m, p[0], p[1], p[2]);
                }
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    int a = base + i + 3 * j, b = a + 1, c = a + 3, d = c + 1;
                    if (side) {
                        tm_tri(m, a, b, d);
                        tm_tri(m, a, d, c);
                    } else {
                        tm_tri(m, a, d, b);
                        tm_tri(m, a, c, d);
                    }
                }
        }
    if (degenerate) tm_tri(m, 31, 31, 32); /* the y = hi face's centre vertex twice */
}

static wc_mesh_collider* make_collider(const tmesh* t, double thickness) {
    wc_mesh_collider* mc = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, t->x, t->nv, t->t, t->nt, thickness, 0.3, NULL, &d), WC_OK);
    return mc;
}

/* |distance| to the closest non-degenerate triangle, every triangle tried. */
static double brute_distance(const wc_mesh_collider* mc, int end, const double* p) {
    const double* x = end ? mc->xb : mc->xa;
    const double* nrm = end ? mc->nrm_b : mc->nrm_a;
    double best = HUGE_VAL;
    for (int t = 0; t < mc->n_tris; ++t) {
        const double* n = nrm + 3 * t;
        if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) continue;
        const int* v = mc->tris + 3 * t;
        best = fmin(best, wc_closest_on_triangle(p, x + 3 * v[0], x + 3 * v[1], x + 3 * v[2], NULL, NULL));
    }
    return sqrt(best);
}

/* A query point: on a random triangle's vertex, edge or face, moved off it along a random
 * direction by up to 3 cm (sometimes not at all), or anywhere around the body. */
static void random_point(const wc_mesh_collider* mc, int end, double* p) {
    const double* x = end ? mc->xb : mc->xa;
    double kind = urand();
    if (kind < 0.1) {
        v3_set(p, srand1(1.5), srand1(1.5), srand1(1.5));
        return;
    }
    const int* v = mc->tris + 3 * (int)(urand() * mc->n_tris);
    double w[3] = {urand(), urand(), urand()};
    if (kind < 0.4) w[(int)(urand() * 3)] = 0.0;            /* an edge */
    if (kind < 0.25) w[(int)(urand() * 3)] = 0.0;           /* a vertex (or an edge) */
    double s = w[0] + w[1] + w[2];
    if (!(s > 0.0)) w[0] = s = 1.0;
    v3_zero(p);
    for (int k = 0; k < 3; ++k) v3_axpy(p, w[k] / s, x + 3 * v[k]);
    double dir[3];
    rand_unit(dir);
    if (urand() < 0.8) v3_axpy(p, srand1(0.03), dir);
}

static int g_checked, g_found, g_walked, g_overflowed, g_kept_listed, g_kept_from, g_crossed, g_crossed_listed;

/* Walkers: points that keep their cached candidates (wc_mesh_near) from query to query while
 * they move by small random steps (now and then a jump), against the full search. */
enum { WALKERS = 16 };
static double g_walker[3 * WALKERS];
static wc_mesh_near g_near[WALKERS];

static int g_front, g_front_within, g_front_unproven;

/* wc_mesh_front_kept against the full search's answer d (wc_mesh_closest at reach r): when it
 * proves p in front, d >= 0 or, asked without `within`, HUGE_VAL; with `within` d < HUGE_VAL */
static void front_check(const wc_mesh_collider* mc, const wc_mesh_near* e, int at, int end, const double* p, double r,
                        double d) {
    int f0 = wc_mesh_front_kept(mc, e, at, end, p, r, 0), f1 = wc_mesh_front_kept(mc, e, at, end, p, r, 1);
    if ((f0 && !(d >= 0.0)) || (f1 && !(d >= 0.0 && d < HUGE_VAL)) || (f1 && !f0))
        printf("  front proven wrongly at (%.17g %.17g %.17g), reach %g, from %d: %d %d, distance %.17g\n", p[0], p[1],
               p[2], r, at, f0, f1, d);
    CHECK(!f0 || d >= 0.0);
    CHECK(!f1 || (d >= 0.0 && d < HUGE_VAL));
    CHECK(!f1 || f0);
    g_front += f0;
    g_front_within += f1;
    g_front_unproven += !f0 && d >= 0.0 && d < HUGE_VAL;
}

static void walk(wc_mesh_collider* mc) {
    for (int i = 0; i < WALKERS; ++i) {
        double* p = g_walker + 3 * i;
        if (urand() < 0.05) {
            random_point(mc, 0, p);
        } else {
            double dir[3];
            rand_unit(dir);
            v3_axpy(p, urand() < 0.5 ? 0.002 * urand() : 0.02 * urand(), dir);
        }
        int end = urand() < 0.5;
        double u = urand(), reach = u < 0.1 ? 0.25 : u < 0.5 ? 0.03 : 0.01 + 0.03 * urand(); /* 0.25: too many */
        double n0[3] = {0, 0, 0}, v0[3] = {0, 0, 0}, n1[3] = {0, 0, 0}, v1[3] = {0, 0, 0};
        mc->exhaustive = 1;
        double d1 = wc_mesh_closest(mc, end, p, reach, n1, v1);
        mc->exhaustive = 0;
        double d0 = wc_mesh_closest_near(mc, &g_near[i], end, p, reach, n0, v0);
        int same = memcmp(&d0, &d1, sizeof d0) == 0 && memcmp(n0, n1, sizeof n0) == 0 &&
                   memcmp(v0, v1, sizeof v0) == 0;
        if (!same) printf("  cached differs at (%.17g %.17g %.17g), end %d, reach %g: %.17g vs %.17g\n", p[0], p[1],
                          p[2], end, reach, d0, d1);
        CHECK(same);
        if (g_near[i].count != -1) { /* the cover test's rounding scale, kept by the gathering */
            double s = 1.0;
            for (int k = 0; k < 6; ++k) s = fmax(s, fabs(g_near[i].box[k]));
            CHECK(memcmp(&s, &g_near[i].scale, sizeof s) == 0);
        }
        /* a crossing along a path from p (wc_mesh_ccd_near: the list fitted to p's query box, used
           when it covers the path's box, which it need not): the tree's answer bit for bit (from
           the front to the back of the same triangle at the same time and weights) */
        {
            double p1[3], dir[3], t0 = -1.0, t1 = -1.0, w0[3] = {0, 0, 0}, w1[3] = {0, 0, 0};
            int tri0 = -1, tri1 = -1;
            rand_unit(dir);
            v3_copy(p1, p);
            v3_axpy(p1, 0.04 * urand(), dir);
            if (urand() < 0.3) random_point(mc, end, p1); /* a long path: beyond the list */
            int c1 = wc_mesh_ccd(mc, p, p1, 1e-6, &t1, &tri1, w1);
            int c0 = wc_mesh_ccd_near(mc, &g_near[i], p, reach, p, p1, 1e-6, &t0, &tri0, w0);
            same = c0 == c1 && tri0 == tri1 && memcmp(&t0, &t1, sizeof t0) == 0 && memcmp(w0, w1, sizeof w0) == 0;
            if (!same) printf("  crossing differs from (%.17g %.17g %.17g), reach %g: %d %d (t %.17g %.17g)\n", p[0],
                              p[1], p[2], reach, c0, c1, t0, t1);
            CHECK(same);
            g_crossed += c1;
            g_crossed_listed += c1 && g_near[i].count >= 0;
        }
        /* through the list as it is (never gathered again), at a reach it may or may not cover:
           the tree's answer all the same, and the list untouched */
        double q[3], dir[3], r2 = 0.002 + 0.1 * urand();
        rand_unit(dir);
        v3_copy(q, p);
        v3_axpy(q, 0.04 * urand(), dir);
        wc_mesh_near before = g_near[i];
        mc->exhaustive = 1;
        double k1 = wc_mesh_closest(mc, end, q, r2, n1, v1);
        mc->exhaustive = 0;
        /* from a position in the list (its triangle's distance bounding the search from the
           start; any position, the answer is the same) or none */
        int at = g_near[i].count > 0 && urand() < 0.7 ? (int)(urand() * g_near[i].count) % g_near[i].count : -1;
        double k0 = wc_mesh_closest_kept(mc, &g_near[i], at, end, q, r2, n0, v0);
        same = memcmp(&k0, &k1, sizeof k0) == 0 && (k1 == HUGE_VAL || (memcmp(n0, n1, sizeof n0) == 0 &&
                                                                       memcmp(v0, v1, sizeof v0) == 0));
        if (!same) printf("  kept differs at (%.17g %.17g %.17g), reach %g, from %d: %.17g vs %.17g\n", q[0], q[1],
                          q[2], r2, at, k0, k1);
        CHECK(same);
        g_kept_from += at >= 0 && k1 < HUGE_VAL;
        CHECK(memcmp(&before, &g_near[i], sizeof before) == 0);
        front_check(mc, &g_near[i], at, end, q, r2, k1);
        /* on a listed triangle's plane, or just off it: where only the margin decides */
        if (g_near[i].count > 0) {
            int j = (int)(urand() * g_near[i].count) % g_near[i].count, t = g_near[i].tri[j];
            const int* v = mc->tris + 3 * t;
            const double* x = end ? mc->xb : mc->xa;
            const double* nt = (end ? mc->nrm_b : mc->nrm_a) + 3 * t;
            double w[3] = {urand(), urand(), urand()}, sw = w[0] + w[1] + w[2] + 1e-300, s[3] = {0, 0, 0};
            for (int k = 0; k < 3; ++k) v3_axpy(s, w[k] / sw, x + 3 * v[k]);
            double u2 = urand();
            if (u2 < 0.3) v3_axpy(s, u2 < 0.15 ? 1e-13 : -1e-13, nt);
            else if (u2 < 0.5) v3_axpy(s, srand1(3e-9), nt);
            else if (u2 < 0.9) v3_axpy(s, 0.004 * urand(), nt); /* in front of it: often proven */
            double rs = 0.002 + 0.03 * urand();
            mc->exhaustive = 1;
            double ks = wc_mesh_closest(mc, end, s, rs, NULL, NULL);
            mc->exhaustive = 0;
            double u3 = urand();
            front_check(mc, &g_near[i], u3 < 0.6 ? j : u3 < 0.8 ? (int)(urand() * g_near[i].count) % g_near[i].count : -1,
                        end, s, rs, ks);
        }
        g_kept_listed += g_near[i].count >= 0 && k1 < HUGE_VAL;
        ++g_walked;
        g_overflowed += g_near[i].count == -2;
    }
}

/* Pruned against exhaustive (bit for bit) and brute force (to rounding) at random points. */
static void compare_queries(wc_mesh_collider* mc, int n_points) {
    const double reaches[4] = {HUGE_VAL, 0.004, 0.03, 0.5};
    for (int i = 0; i < n_points; ++i) {
        int end = urand() < 0.5;
        double p[3];
        random_point(mc, end, p);
        for (int r = 0; r < 4; ++r) {
            double n0[3] = {0, 0, 0}, v0[3] = {0, 0, 0}, n1[3] = {0, 0, 0}, v1[3] = {0, 0, 0};
            mc->exhaustive = 1;
            double d1 = wc_mesh_closest(mc, end, p, reaches[r], n1, v1);
            mc->exhaustive = 0;
            double d0 = wc_mesh_closest(mc, end, p, reaches[r], n0, v0);
            int same = memcmp(&d0, &d1, sizeof d0) == 0 && memcmp(n0, n1, sizeof n0) == 0 &&
                       memcmp(v0, v1, sizeof v0) == 0;
            if (!same) printf("  differs at (%.17g %.17g %.17g), end %d, reach %g: %.17g vs %.17g\n", p[0], p[1],
                              p[2], end, reaches[r], d0, d1);
            CHECK(same);
            double bf = brute_distance(mc, end, p);
            if (d0 < HUGE_VAL) {
                CHECK(fabs(fabs(d0) - bf) <= 1e-12 * (1.0 + bf));
                ++g_found;
            } else {
                CHECK(bf > reaches[r] - 1e-12);
            }
            ++g_checked;
        }
    }
}

/* Frames of a random deforming motion (every vertex moved, the whole body carried), substeps at
 * random fractions, a teleport and a reset to the frame's start between them. */
static void moving_body(const tmesh* t, double thickness) {
    wc_mesh_collider* mc = make_collider(t, thickness);
    for (int i = 0; i < WALKERS; ++i) random_point(mc, 0, g_walker + 3 * i);
    wc_mesh_near_clear(g_near, WALKERS);
    double* target = malloc(3 * (size_t)t->nv * sizeof(double));
    wc_diag d = {0};
    double carry[3] = {0, 0, 0};
    for (int f = 0; f < 8; ++f) {
        double step[3] = {srand1(0.1), srand1(0.1), srand1(0.1)};
        v3_add(carry, carry, step);
        for (int k = 0; k < 3 * t->nv; ++k) target[k] = t->x[k] + carry[k % 3] + srand1(0.01);
        if (f == 5) { /* a teleport: from = to = there, nothing moves */
            CHECK_EQ_INT(wc_mesh_collider_set_all(mc, target, &d), WC_OK);
            wc_mesh_collider_substep(mc, 0.0, 0.0, 0.0);
            compare_queries(mc, 25);
            walk(mc);
            continue;
        }
        CHECK_EQ_INT(wc_mesh_collider_set_target(mc, target, &d), WC_OK);
        double a0 = 0.0;
        for (int s = 0; s < 3; ++s) {
            double a1 = s == 2 ? 1.0 : a0 + urand() * (1.0 - a0);
            wc_mesh_collider_substep(mc, a0, a1, 0.01);
            compare_queries(mc, 25);
            for (int w = 0; w < 4; ++w) walk(mc);
            a0 = a1;
        }
        if (f == 3) { /* a rollback to the frame's start: its first substep again */
            wc_mesh_collider_substep(mc, 0.0, 0.5, 0.01);
            compare_queries(mc, 25);
            walk(mc);
        }
        wc_mesh_collider_end_frame(mc);
    }
    free(target);
    wc_mesh_collider_destroy(mc);
}

static void test_closest_matches_full_search(void) {
    static tmesh t;
    double c[3] = {0.1, 0.2, -0.1};
    g_checked = g_found = g_walked = g_overflowed = g_kept_listed = g_kept_from = g_crossed = g_crossed_listed = 0;
    g_front = g_front_within = g_front_unproven = 0;
    lumpy_sphere(&t, 14, 24, 0.3, c, 0.01);
    moving_body(&t, 0.005);
    lumpy_sphere(&t, 6, 8, 0.3, c, 0.05); /* coarse and very lumpy: sharp bends */
    moving_body(&t, 0.0);
    double lo[3] = {-0.3, -0.1, -0.2}, hi[3] = {0.3, 0.1, 0.2};
    box(&t, lo, hi, 1);
    moving_body(&t, 0.01);
    printf("  %d queries: pruned = full search bit for bit, %d within reach = brute force; %d by walkers with "
           "cached candidates = full search bit for bit (%d with too many candidates), as many through the kept list "
           "without gathering (%d found with a list, %d from a listed triangle); %d crossings = the tree's bit for bit "
           "(%d with a list)\n",
           g_checked, g_found, g_walked, g_overflowed, g_kept_listed, g_kept_from, g_crossed, g_crossed_listed);
    printf("  in front proven by the planes (wc_mesh_front_kept): %d (%d within reach), %d in front "
           "within reach not proven\n", g_front, g_front_within, g_front_unproven);
    CHECK(g_front > 50 && g_front_within > 20);
    CHECK(g_crossed_listed > 20);
    CHECK(g_overflowed > 0 && g_overflowed < g_walked / 2);
    CHECK(g_kept_listed > g_walked / 4);
    CHECK(g_kept_from > g_kept_listed / 3);
    CHECK(g_found > g_checked / 3);
}

/* 1 when some non-degenerate triangle under node has a sharp vertex (by descending). */
static int any_sharp_below(const wc_mesh_collider* mc, const wc_mesh_sharp* sh, int node) {
    const int* ch = mc->bvh.child + 2 * node;
    if (ch[0] >= 0) return any_sharp_below(mc, sh, ch[0]) || any_sharp_below(mc, sh, ch[1]);
    const int* v = mc->tris + 3 * ch[1];
    const double* n = mc->nrm_a + 3 * ch[1];
    if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) return 0;
    return sh->sharp_vert[v[0]] || sh->sharp_vert[v[1]] || sh->sharp_vert[v[2]];
}

/* The sheet on the moving bodies, twice: with the prunes and without (exhaustive). */
static void drop(int exhaustive, int frames, double* x_out, int* pairs_out, int* mask_ok) {
    int n = 12;
    wc_model m;
    CHECK(ts_sheet(&m, n, 0.7, 0.2, 0, 1.0));
    wc_state* s = NULL;
    wc_diag d = {0};
    wc_sim_def sd = wc_default_sim_def();
    sd.substeps = 2;
    CHECK_EQ_INT(wc_state_create(&s, &m, &sd, NULL, &d), WC_OK);
    static tmesh tb, ts;
    double lo[3] = {-0.15, -0.1, -0.15}, hi[3] = {0.15, 0.1, 0.15}, c[3] = {0.2, -0.2, 0.1};
    box(&tb, lo, hi, 0);
    rng_state = 88172645463325252ull; /* the same lumps in both runs */
    lumpy_sphere(&ts, 8, 12, 0.25, c, 0.01);
    wc_mesh_collider* mc[2] = {make_collider(&tb, 0.005), make_collider(&ts, 0.005)};
    mc[0]->exhaustive = mc[1]->exhaustive = exhaustive;
    CHECK_EQ_INT(wc_state_attach_mesh_colliders(s, mc, 2, &d), WC_OK);
    double* tgt = malloc(3 * (size_t)ts.nv * sizeof(double));
    int pairs = 0;
    *mask_ok = 1;
    for (int f = 0; f < frames; ++f) {
        /* the box rises and turns; the sphere deforms (breathes) and slides */
        double a = 0.05 * f, ca = cos(a), sa = sin(a);
        for (int k = 0; k < tb.nv; ++k) {
            const double* p = tb.x + 3 * k;
            v3_set(tgt + 3 * k, ca * p[0] + sa * p[2], p[1] + 0.004 * f, -sa * p[0] + ca * p[2]);
        }
        if (f == 12) /* a teleport of the box: no motion over the jump */
            CHECK_EQ_INT(wc_mesh_collider_set_all(mc[0], tgt, &d), WC_OK);
        else
            CHECK_EQ_INT(wc_state_set_mesh_target(s, 0, tgt, &d), WC_OK);
        for (int k = 0; k < ts.nv; ++k) {
            const double* p = ts.x + 3 * k;
            double g = 1.0 + 0.02 * sin(0.7 * f + 3.0 * p[1]);
            v3_set(tgt + 3 * k, c[0] + g * (p[0] - c[0]) - 0.01 * f, c[1] + g * (p[1] - c[1]), c[2] + g * (p[2] - c[2]));
        }
        CHECK_EQ_INT(wc_state_set_mesh_target(s, 1, tgt, &d), WC_OK);
        wc_step_stats st;
        CHECK_EQ_INT(wc_step_frame(s, 1.0 / 30, &st, &d), WC_OK);
        pairs += st.mesh_pairs;
        for (int k = 0; k < 2; ++k)
            for (int node = 0; node < mc[k]->bvh.n_nodes; ++node)
                if (s->pairs->sharp[k].node_mask[node] != any_sharp_below(mc[k], &s->pairs->sharp[k], node))
                    *mask_ok = 0;
    }
    memcpy(x_out, s->x, 3 * (size_t)m.n_particles * sizeof(double));
    *pairs_out = pairs;
    free(tgt);
    wc_state_destroy(s);
    wc_mesh_collider_destroy(mc[0]);
    wc_mesh_collider_destroy(mc[1]);
    wc_model_free(&m);
}

static void test_steps_match_full_search(void) {
    enum { FRAMES = 16, NP = 144 };
    double xp[3 * NP], xf[3 * NP];
    int pairs_p = 0, pairs_f = 0, mask_p = 0, mask_f = 0;
    drop(0, FRAMES, xp, &pairs_p, &mask_p);
    drop(1, FRAMES, xf, &pairs_f, &mask_f);
    printf("  %d frames on a turning, teleported box and a breathing sphere: %d feature pairs (full search %d), "
           "positions %s\n", FRAMES, pairs_p, pairs_f, memcmp(xp, xf, sizeof xp) == 0 ? "bit for bit the same" : "differ");
    CHECK(pairs_p > 0);
    CHECK_EQ_INT(pairs_p, pairs_f);
    CHECK(memcmp(xp, xf, sizeof xp) == 0);
    CHECK(mask_p && mask_f);
}

int main(void) {
    RUN_TEST(test_closest_matches_full_search);
    RUN_TEST(test_steps_match_full_search);
    return TEST_SUMMARY();
}
