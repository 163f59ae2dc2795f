/* The kept candidate lists (wc_mesh_near) judged in the body's fitted frame (mesh_pose.h), against
 * brute force and the full search, on a lumpy elongated body turning about an axis off its centre
 * (its far end moving several centimetres a substep: the travel alone would regather every list
 * every substep) while drifting; turning faster and bending (a residual the fit does not explain);
 * or drifting while its vertices shake, half up and half down (a residual of 3 mm), with a jump and a
 * rollback between:
 *  - every list a query box keeps without gathering holds every triangle whose box (the tree's
 *    leaf box, now) meets the query box: what the tree would visit, so the answers are the same;
 *  - the same at the edge of the bound: each face of a kept query box pushed out (bisection) to
 *    the farthest the bound still vouches for, and every triangle meeting that box listed;
 *  - closest points through the lists (wc_mesh_closest_near) equal the full search's bit for bit;
 *  - the frame does keep lists the travel would not (most of them on the rigid turn). */
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "colliders.h"
#include "mesh_collider.h"
#include "test_support.h"

#define POINTS 240
#define NV_MAX 400
#define NT_MAX 800

static int g_nv, g_nt;
static double g_rest[3 * NV_MAX];
static int g_tris[3 * NT_MAX];

/* A UV ellipsoid (semi-axes ax), centred at c, its vertices moved by up to bump at random. */
static void lumpy_ellipsoid(int rings, int segs, const double* ax, const double* c, double bump) {
    double pi = acos(-1.0);
    g_nv = g_nt = 0;
    v3_set(g_rest, c[0], c[1] + ax[1], c[2]);
    g_nv = 1;
    for (int i = 1; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            double th = pi * i / rings, ph = 2 * pi * j / segs;
            v3_set(g_rest + 3 * g_nv++, c[0] + ax[0] * sin(th) * cos(ph), c[1] + ax[1] * cos(th),
                   c[2] - ax[2] * sin(th) * sin(ph));
        }
    int bot = g_nv;
    v3_set(g_rest + 3 * g_nv++, c[0], c[1] - ax[1], c[2]);
    for (int j = 0; j < segs; ++j) {
        int j1 = (j + 1) % segs, *t;
        t = g_tris + 3 * g_nt++, t[0] = 0, t[1] = 1 + j, t[2] = 1 + j1;
        t = g_tris + 3 * g_nt++, t[0] = bot, t[1] = 1 + (rings - 2) * segs + j1, t[2] = 1 + (rings - 2) * segs + j;
        for (int i = 0; i < rings - 2; ++i) {
            int a = 1 + i * segs + j, b = 1 + i * segs + j1, cc = a + segs, d = b + segs;
            t = g_tris + 3 * g_nt++, t[0] = a, t[1] = cc, t[2] = b;
            t = g_tris + 3 * g_nt++, t[0] = b, t[1] = cc, t[2] = d;
        }
    }
    for (int k = 0; k < 3 * g_nv; ++k) g_rest[k] += srand1(bump);
}

/* The body's rigid pose at time s (frames): a turn of deg_per_frame about the y axis through the
 * origin, a drift along x and z. */
static double g_deg_per_frame;
static void pose(double s, const double* p, double* o) {
    double a = g_deg_per_frame * s * acos(-1.0) / 180.0, c = cos(a), sn = sin(a);
    v3_set(o, c * p[0] + sn * p[2] + 0.004 * s, p[1], -sn * p[0] + c * p[2] + 0.002 * s);
}

/* Positions at frame s: the pose, and from bend_from on a bend of the far end (x > 0.5 at rest)
 * growing with time (the residual an affine fit leaves). */
static double g_bend;   /* m a frame at the far end */
static double g_jitter; /* m: each vertex's offset, up or down, swapped every frame */
static void body_at(double s, double bend_from, double* x) {
    for (int i = 0; i < g_nv; ++i) {
        double p[3];
        v3_copy(p, g_rest + 3 * i);
        if (s > bend_from && p[0] > 0.5) p[1] += g_bend * (s - bend_from) * (p[0] - 0.5) / 0.4;
        if (s > bend_from) /* half the vertices up, half down, swapping every frame: the fit's residual */
            p[1] += (((int)floor(s) + i) % 2 ? 1.0 : -1.0) * g_jitter;
        pose(s, p, x + 3 * i);
    }
}

static double g_qrest[3 * POINTS], g_qr[POINTS], g_drift[3 * POINTS];
static wc_mesh_near g_near[POINTS];
static long g_uses, g_kept, g_kept_by_pose, g_probes, g_listed_checked, g_same;

/* 1 when every triangle whose leaf box meets box is in e's list (brute force over the triangles). */
static int lists_all(const wc_mesh_collider* mc, const wc_mesh_near* e, const double* box) {
    const wc_bvh* b = &mc->bvh;
    int ok = 1;
    for (int t = 0; t < mc->n_tris; ++t) {
        if (!wc_box_overlap(b->box + 6 * b->leaf_of[t], box)) continue;
        int in = 0;
        for (int k = 0; k < e->count && !in; ++k) in = e->tri[k] == t;
        ++g_listed_checked;
        if (!in) ok = 0;
    }
    return ok;
}

/* The travel alone covers box for e (near_covers' first test). */
static int travel_covers(const wc_mesh_collider* mc, const wc_mesh_near* e, const double* box) {
    double scale = 1.0;
    for (int k = 0; k < 6; ++k) scale = fmax(scale, fabs(e->box[k]));
    double grow = (mc->travel - e->travel) * (1.0 + 1e-12) + 1e-12 * scale;
    for (int k = 0; k < 3; ++k)
        if (!(box[k] - grow >= e->box[k] && box[3 + k] + grow <= e->box[3 + k])) return 0;
    return 1;
}

/* Each face of box pushed out as far as the bound vouches for (bisection), the lists checked there. */
static void probe_edges(const wc_mesh_collider* mc, const wc_mesh_near* e, const double* box) {
    double scale = 1.0;
    for (int k = 0; k < 6; ++k) scale = fmax(scale, fabs(e->box[k]));
    for (int f = 0; f < 6; ++f) {
        double lo = 0.0, hi = 0.2, q[6];
        for (int it = 0; it < 30; ++it) {
            double mid = 0.5 * (lo + hi);
            memcpy(q, box, sizeof q);
            q[f] += f < 3 ? -mid : mid;
            if (wc_mesh_poses_cover(&mc->poses, e->epoch, e->box, q, 1e-12 * scale)) lo = mid;
            else hi = mid;
        }
        memcpy(q, box, sizeof q);
        q[f] += f < 3 ? -lo : lo;
        if (!wc_mesh_poses_cover(&mc->poses, e->epoch, e->box, q, 1e-12 * scale)) continue;
        ++g_probes;
        CHECK(lists_all(mc, e, q));
    }
}

/* Every query point at the body's pose at s (plus its own drift), its list fitted and checked. */
static void query_all(const wc_mesh_collider* mc, double s) {
    for (int i = 0; i < POINTS; ++i) {
        double p[3], box[6];
        for (int k = 0; k < 3; ++k) g_drift[3 * i + k] += srand1(0.001);
        pose(s, g_qrest + 3 * i, p);
        v3_add(p, p, g_drift + 3 * i);
        for (int k = 0; k < 3; ++k) box[k] = p[k] - g_qr[i], box[3 + k] = p[k] + g_qr[i];
        wc_mesh_near* e = g_near + i;
        wc_mesh_near before = *e;
        int travel = before.count >= 0 && travel_covers(mc, e, box);
        int fitted = wc_mesh_near_fit(mc, e, box);
        ++g_uses;
        int kept = before.count != -1 && memcmp(&before, e, sizeof before) == 0;
        if (kept && fitted) {
            ++g_kept;
            if (!travel) ++g_kept_by_pose;
            CHECK(lists_all(mc, e, box));
            if (!travel) probe_edges(mc, e, box);
        }
        /* the closest point through the list, bit for bit the full search's */
        for (int end = 0; end < 2; ++end) {
            double n0[3] = {0}, v0[3] = {0}, n1[3] = {0}, v1[3] = {0};
            double d0 = wc_mesh_closest(mc, end, p, g_qr[i], n0, v0);
            double d1 = wc_mesh_closest_near(mc, e, end, p, g_qr[i], n1, v1);
            int same = memcmp(&d0, &d1, sizeof d0) == 0 && memcmp(n0, n1, sizeof n0) == 0 &&
                       memcmp(v0, v1, sizeof v0) == 0;
            CHECK(same);
            g_same += same;
        }
    }
}

static void turning_body(double deg_per_frame, double bend_from, double bend, double jitter) {
    const double ax[3] = {0.45, 0.25, 0.2}, c[3] = {0.45, 0.0, 0.0};
    g_deg_per_frame = deg_per_frame;
    g_bend = bend;
    g_jitter = jitter;
    lumpy_ellipsoid(9, 16, ax, c, 0.02);
    wc_mesh_collider* mc = NULL;
    wc_diag d = {0};
    CHECK_EQ_INT(wc_mesh_collider_create(&mc, g_rest, g_nv, g_tris, g_nt, 0.004, 0.3, NULL, &d), WC_OK);
    for (int i = 0; i < POINTS; ++i) {
        const int* t = g_tris + 3 * (int)(urand() * g_nt);
        double w[3] = {urand(), urand(), urand()}, sw = w[0] + w[1] + w[2], nrm[3];
        v3_zero(g_qrest + 3 * i);
        for (int k = 0; k < 3; ++k) v3_axpy(g_qrest + 3 * i, w[k] / sw, g_rest + 3 * t[k]);
        v3_sub(nrm, g_qrest + 3 * i, c);
        v3_axpy(g_qrest + 3 * i, srand1(0.03) / v3_norm(nrm), nrm);
        g_qr[i] = 0.02 + 0.04 * urand();
        v3_zero(g_drift + 3 * i);
    }
    wc_mesh_near_clear(g_near, POINTS);
    static double x[3 * NV_MAX];
    for (int f = 0; f < 14; ++f) {
        body_at(f + 1.0, bend_from, x);
        if (f == 6) { /* a jump: there at once, nothing moving */
            CHECK_EQ_INT(wc_mesh_collider_set_all(mc, x, &d), WC_OK);
            wc_mesh_collider_substep(mc, 0.0, 0.0, 0.0);
            query_all(mc, f + 1.0);
            continue;
        }
        CHECK_EQ_INT(wc_mesh_collider_set_target(mc, x, &d), WC_OK);
        for (int s = 0; s < 2; ++s) {
            wc_mesh_collider_substep(mc, 0.5 * s, 0.5 * (s + 1), 0.01);
            query_all(mc, f + 0.5 * (s + 1));
        }
        if (f == 3) { /* a rollback: the frame's first substep again */
            wc_mesh_collider_substep(mc, 0.0, 0.5, 0.01);
            query_all(mc, f + 0.5);
        }
        wc_mesh_collider_end_frame(mc);
    }
    wc_mesh_collider_destroy(mc);
}

static void test_lists_kept_in_the_body_frame(void) {
    const char* what[3] = {"rigid turn (the suit's 90 deg/s at 30 fps)", "faster, bending from frame 4",
                           "drifting, its vertices shaking by 3 mm from frame 2"};
    const double deg[3] = {3.0, 8.0, 0.0}, from[3] = {1e9, 4.0, 2.0}, bend[3] = {0.0, 0.02, 0.0},
                 jitter[3] = {0.0, 0.0, 0.003};
    for (int k = 0; k < 3; ++k) {
        g_uses = g_kept = g_kept_by_pose = g_probes = 0;
        turning_body(deg[k], from[k], bend[k], jitter[k]);
        printf("  %s: %ld uses, %ld kept (%ld by the frame, not the travel), %ld bound edges probed\n", what[k],
               g_uses, g_kept, g_kept_by_pose, g_probes);
        CHECK(g_kept_by_pose > (k == 0 ? g_uses / 3 : 0));
    }
    printf("  %ld triangles checked listed, %ld closest points the full search's bit for bit\n", g_listed_checked,
           g_same);
}

int main(void) {
    RUN_TEST(test_lists_kept_in_the_body_frame);
    return TEST_SUMMARY();
}
