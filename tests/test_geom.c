/* The collision geometry (core/geom.c) and broad phase (core/bvh.c) against brute force: closest
 * points against dense sampling, continuous queries against the sign changes of a finely sampled
 * coplanarity function, BVH queries (before and after a refit) against testing every box. */
#include <stdlib.h>
#include <string.h>

#include "bvh.h"
#include "check.h"
#include "geom.h"
#include "vec3.h"

static unsigned rng_state = 12345u;
static double rnd(void) { /* uniform [-1, 1) */
    rng_state = rng_state * 1664525u + 1013904223u;
    return (double)(rng_state >> 8) / (double)(1u << 24) * 2.0 - 1.0;
}
static void rnd3(double* p, double s) { v3_set(p, s * rnd(), s * rnd(), s * rnd()); }

static void test_closest_on_triangle_brute(void) {
    int worse = 0;
    for (int trial = 0; trial < 300; ++trial) {
        double a[3], b[3], c[3], p[3], w[3], q[3];
        rnd3(a, 1); rnd3(b, 1); rnd3(c, 1); rnd3(p, 2);
        if (trial % 50 == 0) v3_copy(c, b); /* degenerate */
        double d2 = wc_closest_on_triangle(p, a, b, c, w, q);
        CHECK(w[0] >= -1e-12 && w[1] >= -1e-12 && w[2] >= -1e-12 && fabs(w[0] + w[1] + w[2] - 1) < 1e-12);
        double best = INFINITY;
        int N = 200;
        for (int i = 0; i <= N; ++i)
            for (int j = 0; i + j <= N; ++j) {
                double u = (double)i / N, v = (double)j / N, x[3], d[3];
                for (int k = 0; k < 3; ++k) x[k] = (1 - u - v) * a[k] + u * b[k] + v * c[k];
                v3_sub(d, p, x);
                double e = v3_dot(d, d);
                if (e < best) best = e;
            }
        /* the sampled minimum can only be larger, and not by much */
        if (d2 > best + 1e-12) ++worse;
        CHECK(sqrt(best) - sqrt(d2) < 0.02);
    }
    CHECK_EQ_INT(worse, 0);
}

static void test_closest_on_segments_brute(void) {
    int worse = 0;
    for (int trial = 0; trial < 300; ++trial) {
        double p0[3], p1[3], q0[3], q1[3], s, t;
        rnd3(p0, 1); rnd3(p1, 1); rnd3(q0, 1); rnd3(q1, 1);
        if (trial % 40 == 0) v3_copy(p1, p0);
        if (trial % 60 == 1) { /* parallel */
            double d[3];
            v3_sub(d, p1, p0);
            v3_add(q1, q0, d);
        }
        double d2 = wc_closest_on_segments(p0, p1, q0, q1, &s, &t);
        CHECK(s >= 0 && s <= 1 && t >= 0 && t <= 1);
        double best = INFINITY;
        for (int i = 0; i <= 400; ++i)
            for (int j = 0; j <= 400; ++j) {
                double a[3], b[3], d[3];
                for (int k = 0; k < 3; ++k) {
                    a[k] = p0[k] + i / 400.0 * (p1[k] - p0[k]);
                    b[k] = q0[k] + j / 400.0 * (q1[k] - q0[k]);
                }
                v3_sub(d, a, b);
                if (v3_dot(d, d) < best) best = v3_dot(d, d);
            }
        if (d2 > best + 1e-12) ++worse;
        CHECK(sqrt(best) - sqrt(d2) < 0.01);
    }
    CHECK_EQ_INT(worse, 0);
}

static void test_cubic_roots(void) {
    double r[3];
    /* (t - 0.2)(t - 0.5)(t - 0.9) */
    double c3 = 1, c2 = -(0.2 + 0.5 + 0.9), c1 = 0.2 * 0.5 + 0.2 * 0.9 + 0.5 * 0.9, c0 = -0.2 * 0.5 * 0.9;
    CHECK_EQ_INT(wc_cubic_roots01(c0, c1, c2, c3, 1, r), 3);
    CHECK_NEAR(r[0], 0.2, 1e-10);
    CHECK_NEAR(r[1], 0.5, 1e-10);
    CHECK_NEAR(r[2], 0.9, 1e-10);
    CHECK_EQ_INT(wc_cubic_roots01(1, 0, 0, 0, 1, r), 0);
    CHECK_EQ_INT(wc_cubic_roots01(0, 0, 0, 0, 1, r), -1);
    CHECK_EQ_INT(wc_cubic_roots01(-0.25, 0, 1, 0, 1, r), 1); /* t^2 - 1/4 */
    CHECK_NEAR(r[0], 0.5, 1e-10);
}

static void lerp(double* o, const double* a, const double* b, double t) {
    for (int k = 0; k < 3; ++k) o[k] = a[k] + t * (b[k] - a[k]);
}

/* A point falling through a still triangle, and random moving configurations against sampling:
 * every sampled crossing (sign change of the coplanarity function with the point inside the
 * triangle there) is found, no earlier than it, and every reported hit is a real contact. */
static void test_ccd_point_triangle(void) {
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 0, 1}, p0[3] = {0.2, 0.5, 0.2}, p1[3] = {0.2, -1.5, 0.2};
    double t, w[3];
    CHECK(wc_ccd_point_triangle(p0, a, b, c, p1, a, b, c, 1e-9, &t, w));
    CHECK_NEAR(t, 0.25, 1e-9);
    CHECK_NEAR(w[1], 0.2, 1e-9);
    CHECK_NEAR(w[2], 0.2, 1e-9);
    double p2[3] = {0.8, 0.5, 0.8}, p3[3] = {0.8, -1.5, 0.8}; /* outside the triangle */
    CHECK(!wc_ccd_point_triangle(p2, a, b, c, p3, a, b, c, 1e-9, &t, w));
    int found = 0, missed = 0, false_hits = 0, late = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        double X0[4][3], X1[4][3];
        for (int i = 0; i < 4; ++i) {
            rnd3(X0[i], 1);
            rnd3(X1[i], 1);
            v3_axpy(X1[i], 0.5, X0[i]);
        }
        double th, wh[3];
        int hit = wc_ccd_point_triangle(X0[0], X0[1], X0[2], X0[3], X1[0], X1[1], X1[2], X1[3], 1e-7, &th, wh);
        /* sampled: the first sign change with the point's projection inside */
        double first = -1, prev = 0;
        int S = 4000;
        for (int k = 0; k <= S; ++k) {
            double tt = (double)k / S, P[4][3], e1[3], e2[3], n[3], d[3];
            for (int i = 0; i < 4; ++i) lerp(P[i], X0[i], X1[i], tt);
            v3_sub(e1, P[2], P[1]);
            v3_sub(e2, P[3], P[1]);
            v3_cross(n, e1, e2);
            v3_sub(d, P[0], P[1]);
            double f = v3_dot(n, d);
            if (k > 0 && (f < 0) != (prev < 0)) {
                double ww[3];
                /* inside well away from the edges (sampling cannot judge grazing hits) */
                double dist2 = wc_closest_on_triangle(P[0], P[1], P[2], P[3], ww, NULL);
                (void)dist2;
                double nn = v3_norm(n);
                double off = fabs(f) / (nn > 0 ? nn : 1);
                if (ww[0] > 0.02 && ww[1] > 0.02 && ww[2] > 0.02 && off < 0.05) {
                    first = tt;
                    break;
                }
            }
            prev = f;
        }
        if (first >= 0) {
            ++found;
            if (!hit) ++missed;
            else if (th > first + 1e-9) ++late;
        }
        if (hit) {
            double P[4][3];
            for (int i = 0; i < 4; ++i) lerp(P[i], X0[i], X1[i], th);
            if (wc_closest_on_triangle(P[0], P[1], P[2], P[3], NULL, NULL) > 1e-12) ++false_hits;
        }
    }
    printf("  point-triangle: %d sampled crossings, %d missed, %d late, %d false hits\n", found, missed, late, false_hits);
    CHECK(found > 50);
    CHECK_EQ_INT(missed, 0);
    CHECK_EQ_INT(late, 0);
    CHECK_EQ_INT(false_hits, 0);
}

static void test_ccd_edge_edge(void) {
    /* two crossing edges, one sweeping down through the other */
    double p0[3] = {-1, 1, 0}, q0[3] = {1, 1, 0}, p1[3] = {-1, -1, 0}, q1[3] = {1, -1, 0};
    double r[3] = {0.3, 0, -1}, s[3] = {0.3, 0, 1};
    double t, sa, sb;
    CHECK(wc_ccd_edge_edge(p0, q0, r, s, p1, q1, r, s, 1e-9, &t, &sa, &sb));
    CHECK_NEAR(t, 0.5, 1e-9);
    CHECK_NEAR(sa, 0.65, 1e-9);
    CHECK_NEAR(sb, 0.5, 1e-9);
    double r2[3] = {1.3, 0, -1}, s2[3] = {1.3, 0, 1}; /* passes beyond the end of p-q */
    CHECK(!wc_ccd_edge_edge(p0, q0, r2, s2, p1, q1, r2, s2, 1e-9, &t, &sa, &sb));
    int found = 0, missed = 0, false_hits = 0, late = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        double X0[4][3], X1[4][3];
        for (int i = 0; i < 4; ++i) {
            rnd3(X0[i], 1);
            rnd3(X1[i], 1);
            v3_axpy(X1[i], 0.5, X0[i]);
        }
        double th, a, b;
        int hit = wc_ccd_edge_edge(X0[0], X0[1], X0[2], X0[3], X1[0], X1[1], X1[2], X1[3], 1e-7, &th, &a, &b);
        double first = -1, prev = 0;
        int S = 4000;
        for (int k = 0; k <= S; ++k) {
            double tt = (double)k / S, P[4][3], e1[3], e2[3], n[3], d[3];
            for (int i = 0; i < 4; ++i) lerp(P[i], X0[i], X1[i], tt);
            v3_sub(e1, P[1], P[0]);
            v3_sub(e2, P[3], P[2]);
            v3_cross(n, e1, e2);
            v3_sub(d, P[2], P[0]);
            double f = v3_dot(n, d);
            if (k > 0 && (f < 0) != (prev < 0)) {
                double sa2, sb2;
                double dist = sqrt(wc_closest_on_segments(P[0], P[1], P[2], P[3], &sa2, &sb2));
                if (sa2 > 0.02 && sa2 < 0.98 && sb2 > 0.02 && sb2 < 0.98 && dist < 0.01) {
                    first = tt;
                    break;
                }
            }
            prev = f;
        }
        if (first >= 0) {
            ++found;
            if (!hit) ++missed;
            else if (th > first + 1e-9) ++late;
        }
        if (hit) {
            double P[4][3];
            for (int i = 0; i < 4; ++i) lerp(P[i], X0[i], X1[i], th);
            if (wc_closest_on_segments(P[0], P[1], P[2], P[3], NULL, NULL) > 1e-12) ++false_hits;
        }
    }
    printf("  edge-edge: %d sampled crossings, %d missed, %d late, %d false hits\n", found, missed, late, false_hits);
    CHECK(found > 20);
    CHECK_EQ_INT(missed, 0);
    CHECK_EQ_INT(late, 0);
    CHECK_EQ_INT(false_hits, 0);
}

typedef struct hits {
    int n;
    int* list;
} hits;
static int collect(void* user, int prim) {
    hits* h = (hits*)user;
    h->list[h->n++] = prim;
    return 0;
}
static int cmp_int(const void* a, const void* b) { return *(const int*)a - *(const int*)b; }

static void random_boxes(double* boxes, int n, double spread) {
    for (int i = 0; i < n; ++i) {
        double c[3], r[3];
        rnd3(c, spread);
        rnd3(r, 0.05);
        for (int k = 0; k < 3; ++k) {
            boxes[6 * i + k] = c[k] - fabs(r[k]);
            boxes[6 * i + 3 + k] = c[k] + fabs(r[k]);
        }
    }
}

static void test_bvh_against_brute(void) {
    int sizes[] = {0, 1, 2, 3, 7, 100, 1000};
    for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); ++si) {
        int n = sizes[si];
        double* boxes = malloc(sizeof(double) * 6 * (n + 1));
        random_boxes(boxes, n, 1);
        wc_bvh b;
        CHECK(wc_bvh_build(&b, boxes, n, NULL, NULL) == WC_OK);
        CHECK_EQ_INT(b.n_nodes, n ? 2 * n - 1 : 0);
        hits h = {0, malloc(sizeof(int) * (n + 1))};
        int mismatches = 0;
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1) { /* deform and refit */
                random_boxes(boxes, n, 2);
                wc_bvh_refit(&b, boxes);
            }
            /* masked: only every third primitive (pass 0) or none but the last (pass 1) */
            unsigned char* mask = calloc((size_t)b.n_nodes + 1, 1);
            for (int i = 0; i < n; ++i) mask[b.leaf_of[i]] = pass == 0 ? i % 3 == 0 : i == n - 1;
            wc_bvh_mask_up(&b, mask);
            for (int q = 0; q < 100; ++q) {
                int masked = q >= 50;
                double box[6];
                random_boxes(box, 1, 1.5);
                wc_box_inflate(box, 0.2);
                h.n = 0;
                if (masked) wc_bvh_query_masked(&b, box, mask, collect, &h);
                else wc_bvh_query(&b, box, collect, &h);
                qsort(h.list, (size_t)h.n, sizeof(int), cmp_int);
                int k = 0;
                for (int i = 0; i < n; ++i)
                    if (wc_box_overlap(boxes + 6 * i, box) && (!masked || mask[b.leaf_of[i]])) {
                        if (k >= h.n || h.list[k] != i) ++mismatches;
                        ++k;
                    }
                if (k != h.n) ++mismatches;
            }
            free(mask);
        }
        CHECK_EQ_INT(mismatches, 0);
        for (int i = 0; i < n; ++i) CHECK_EQ_INT(b.child[2 * b.leaf_of[i] + 1], i);
        wc_bvh_free(&b);
        free(h.list);
        free(boxes);
    }
    double bad[6] = {0, 0, 0, NAN, 1, 1};
    wc_bvh b;
    CHECK(wc_bvh_build(&b, bad, 1, NULL, NULL) == WC_ERROR_NONFINITE);
}

/* A walk's visits in order, and the plain preorder walk that tests every node after popping it. */
typedef struct walk_rec {
    int n, seq[1024], stop_after; /* stop_after > 0: the visit that returns 1 */
    const double* boxes;          /* near walks: each visit lowers *bound2 to its box's distance */
    const double* p;
    double bound2;
} walk_rec;

static int walk_visit(void* user, int prim) {
    walk_rec* w = (walk_rec*)user;
    if (w->n < 1024) w->seq[w->n] = prim;
    ++w->n;
    if (w->boxes) {
        double d2 = wc_box_dist2(w->boxes + 6 * prim, w->p) * 1.5 + 1e-4;
        if (d2 < w->bound2) w->bound2 = d2;
    }
    return w->stop_after > 0 && w->n == w->stop_after;
}

static int reference_walk(const wc_bvh* b, const double* box, const unsigned char* mask, walk_rec* w) {
    if (b->n_nodes == 0) return 0;
    int stack[WC_BVH_MAX_DEPTH + 2], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        const double* nb = b->box + 6 * node;
        if ((mask && !mask[node]) || !wc_box_overlap(nb, box) || (w->p && wc_box_dist2(nb, w->p) > w->bound2))
            continue;
        const int* ch = b->child + 2 * node;
        if (ch[0] < 0) {
            int r = walk_visit(w, ch[1]);
            if (r) return r;
        } else {
            stack[top++] = ch[1];
            stack[top++] = ch[0];
        }
    }
    return 0;
}

/* The box queries' walk (wc_bvh_query_masked: each child tested before the walk goes down to
 * it) against the walk it replaced (every node tested after it is popped), written out here: the same visits in
 * the same order, the same early stop and return value, for masks ORed up and for arbitrary ones
 * (a node's own byte decides, whatever its leaves'), on trees of 0-1,000 boxes as built and after
 * a deformation; and for ORed-up masks the visits are brute force's overlapping leaves in leaf
 * order (the trees' preorder). */
static void test_bvh_walk_order(void) {
    int sizes[] = {0, 1, 2, 3, 7, 100, 1000};
    int differ = 0, brute_differ = 0, stopped = 0;
    long long visits = 0;
    static walk_rec a, r;
    for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); ++si) {
        int n = sizes[si];
        double* boxes = malloc(sizeof(double) * 6 * (n + 1));
        random_boxes(boxes, n, 1);
        wc_bvh b;
        CHECK(wc_bvh_build(&b, boxes, n, NULL, NULL) == WC_OK);
        unsigned char* mask = calloc((size_t)b.n_nodes + 1, 1);
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1) {
                random_boxes(boxes, n, 2);
                wc_bvh_refit(&b, boxes);
            }
            for (int q = 0; q < 300; ++q) {
                int kind = q % 3; /* 0: no mask, 1: leaves at random ORed up, 2: every node at random */
                for (int k = 0; k < b.n_nodes; ++k) mask[k] = rnd() > 0.0;
                if (kind == 1) wc_bvh_mask_up(&b, mask);
                double box[6];
                random_boxes(box, 1, 1.5);
                wc_box_inflate(box, q % 2 ? 0.6 : 0.1);
                const unsigned char* mk = kind ? mask : NULL;
                int stop = q % 4 == 3 ? 1 + q % 5 : 0;
                a = (walk_rec){.stop_after = stop};
                r = (walk_rec){.stop_after = stop};
                int ra = kind ? wc_bvh_query_masked(&b, box, mk, walk_visit, &a) : wc_bvh_query(&b, box, walk_visit, &a);
                int rr = reference_walk(&b, box, mk, &r);
                if (ra != rr || a.n != r.n || memcmp(a.seq, r.seq, sizeof(int) * (size_t)(a.n < 1024 ? a.n : 1024)))
                    ++differ;
                stopped += ra != 0;
                visits += a.n;
                if (kind == 2 || stop) continue;
                int k = 0;
                for (int node = 0; node < b.n_nodes; ++node) {
                    if (b.child[2 * node] >= 0) continue;
                    int p = b.child[2 * node + 1];
                    if (!wc_box_overlap(boxes + 6 * p, box) || (mk && !mk[node])) continue;
                    if (k >= a.n || a.seq[k] != p) ++brute_differ;
                    ++k;
                }
                if (k != a.n) ++brute_differ;
            }
        }
        free(mask);
        wc_bvh_free(&b);
        free(boxes);
    }
    printf("  %lld visits, %d early stops\n", visits, stopped);
    CHECK(visits > 4000);
    CHECK(stopped > 100);
    CHECK_EQ_INT(differ, 0);
    CHECK_EQ_INT(brute_differ, 0);
}

/* The nearest-point walk's order (bvh.c traverse tests a node's mask and box before pushing it,
 * its bound when popping it) against the plain preorder walk that tests everything when a node is popped: the
 * same leaves in the same order, with masks, an early stop, and a bound the visits lower (the
 * nearest-point walk of wc_bvh_query_near). */
static void test_bvh_near_walk_order(void) {
    int sizes[] = {0, 1, 2, 5, 300};
    int mismatches = 0, visits = 0, cut = 0;
    static walk_rec a, r;
    for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); ++si) {
        int n = sizes[si];
        double* boxes = malloc(sizeof(double) * 6 * (n + 1));
        random_boxes(boxes, n, 1);
        wc_bvh b;
        CHECK(wc_bvh_build(&b, boxes, n, NULL, NULL) == WC_OK);
        random_boxes(boxes, n, 1.2); /* refitted over moved boxes: nodes overlap more */
        wc_bvh_refit(&b, boxes);
        unsigned char* mask = calloc((size_t)b.n_nodes + 1, 1);
        for (int i = 0; i < n; ++i) mask[b.leaf_of[i]] = i % 4 != 1;
        wc_bvh_mask_up(&b, mask);
        for (int q = 0; q < 400; ++q) {
            int kind = q % 4; /* 0 all, 1 masked, 2 stopped, 3 near with a falling bound */
            double box[6], p[3];
            random_boxes(box, 1, 1.2);
            wc_box_inflate(box, 0.3);
            for (int k = 0; k < 3; ++k) p[k] = 0.5 * (box[k] + box[3 + k]);
            a = (walk_rec){.stop_after = kind == 2 ? 3 : 0};
            if (kind == 3) {
                a.boxes = boxes;
                a.p = p;
                a.bound2 = HUGE_VAL;
            }
            r = a;
            int ra, rr;
            if (kind == 3) {
                ra = wc_bvh_query_near(&b, box, p, &a.bound2, walk_visit, &a);
            } else {
                const unsigned char* m = kind == 1 ? mask : NULL;
                ra = m ? wc_bvh_query_masked(&b, box, m, walk_visit, &a) : wc_bvh_query(&b, box, walk_visit, &a);
            }
            rr = reference_walk(&b, box, kind == 1 ? mask : NULL, &r);
            if (ra != rr || a.n != r.n || memcmp(a.seq, r.seq, sizeof(int) * (size_t)(a.n < 1024 ? a.n : 1024)))
                ++mismatches;
            visits += a.n;
            if (kind == 3) { /* the bound cut some leaves the box alone lets through */
                walk_rec all = {0};
                wc_bvh_query(&b, box, walk_visit, &all);
                cut += all.n - a.n;
            }
        }
        free(mask);
        wc_bvh_free(&b);
        free(boxes);
    }
    CHECK_EQ_INT(mismatches, 0);
    CHECK(visits > 1000);
    CHECK(cut > 100);
}

/* The cut for refits on threads (wc_bvh_split): every node in exactly one subtree range or among
 * the top nodes, and the subtrees swept in reverse order (any thread order), then the top nodes,
 * give the serial sweep's masks and boxes bit for bit, masked and not. */
static void test_bvh_split(void) {
    int sizes[] = {0, 1, 2, 3, 7, 100, 1000}, depths[] = {0, 1, 3, 5, 12};
    for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); ++si)
        for (size_t di = 0; di < sizeof(depths) / sizeof(depths[0]); ++di) {
            int n = sizes[si];
            double* boxes = malloc(sizeof(double) * 6 * (n + 1));
            random_boxes(boxes, n, 1);
            wc_bvh a, b;
            CHECK(wc_bvh_build(&a, boxes, n, NULL, NULL) == WC_OK);
            CHECK(wc_bvh_build(&b, boxes, n, NULL, NULL) == WC_OK);
            wc_bvh_split s;
            CHECK(wc_bvh_split_build(&s, &b, depths[di], NULL) == WC_OK);
            int* seen = calloc((size_t)b.n_nodes + 1, sizeof(int));
            for (int k = 0; k < s.n_sub; ++k)
                for (int v = s.sub[2 * k]; v < s.sub[2 * k + 1]; ++v) ++seen[v];
            for (int k = 0; k < s.n_top; ++k) {
                ++seen[s.top[k]];
                if (k > 0) CHECK(s.top[k] < s.top[k - 1]);
            }
            int wrong = 0;
            for (int v = 0; v < b.n_nodes; ++v) wrong += seen[v] != 1;
            CHECK_EQ_INT(wrong, 0);
            CHECK(s.n_sub <= 1 << depths[di]);
            random_boxes(boxes, n, 2);
            unsigned char* ma = calloc((size_t)b.n_nodes + 1, 1);
            unsigned char* mb = calloc((size_t)b.n_nodes + 1, 1);
            for (int i = 0; i < n; ++i) ma[a.leaf_of[i]] = mb[b.leaf_of[i]] = i % 5 == 1;
            for (int masked = 0; masked < 2; ++masked) {
                if (masked) {
                    random_boxes(boxes, n, 3);
                    wc_bvh_mask_up(&a, ma);
                    wc_bvh_refit_masked(&a, boxes, ma);
                } else
                    wc_bvh_refit(&a, boxes);
                for (int k = s.n_sub - 1; k >= 0; --k) {
                    if (masked) wc_bvh_mask_up_span(&b, mb, s.sub[2 * k], s.sub[2 * k + 1]);
                    wc_bvh_refit_span(&b, boxes, masked ? mb : NULL, s.sub[2 * k], s.sub[2 * k + 1]);
                }
                if (masked) wc_bvh_mask_up_top(&b, &s, mb);
                wc_bvh_refit_top(&b, &s, masked ? mb : NULL);
                CHECK(n == 0 || memcmp(a.box, b.box, sizeof(double) * 6 * (size_t)b.n_nodes) == 0);
                CHECK(n == 0 || memcmp(ma, mb, (size_t)b.n_nodes) == 0);
            }
            free(ma);
            free(mb);
            free(seen);
            wc_bvh_split_free(&s, NULL);
            wc_bvh_free(&a);
            wc_bvh_free(&b);
            free(boxes);
        }
}

/* A node's height by recursion from the root, against wc_bvh_heights' one sweep. */
static int height_of(const wc_bvh* b, int j) {
    const int* ch = b->child + 2 * j;
    if (ch[0] < 0) return 0;
    int l = height_of(b, ch[0]), r = height_of(b, ch[1]);
    return 1 + (l > r ? l : r);
}

static void test_bvh_heights(void) {
    int sizes[] = {0, 1, 2, 3, 7, 100, 1000};
    for (size_t si = 0; si < sizeof(sizes) / sizeof(sizes[0]); ++si) {
        int n = sizes[si];
        double* boxes = malloc(sizeof(double) * 6 * (n + 1));
        random_boxes(boxes, n, 1);
        wc_bvh b;
        CHECK(wc_bvh_build(&b, boxes, n, NULL, NULL) == WC_OK);
        int* h = malloc(sizeof(int) * ((size_t)b.n_nodes + 1));
        int top = wc_bvh_heights(&b, h), bad = 0, highest = -1;
        for (int j = 0; j < b.n_nodes; ++j) {
            bad += h[j] != height_of(&b, j);
            if (h[j] > highest) highest = h[j];
        }
        CHECK_EQ_INT(bad, 0);
        CHECK_EQ_INT(top, highest);
        CHECK_EQ_INT(top, n ? height_of(&b, 0) : -1);
        free(h);
        wc_bvh_free(&b);
        free(boxes);
    }
}

int main(void) {
    RUN_TEST(test_closest_on_triangle_brute);
    RUN_TEST(test_closest_on_segments_brute);
    RUN_TEST(test_cubic_roots);
    RUN_TEST(test_ccd_point_triangle);
    RUN_TEST(test_ccd_edge_edge);
    RUN_TEST(test_bvh_against_brute);
    RUN_TEST(test_bvh_walk_order);
    RUN_TEST(test_bvh_near_walk_order);
    RUN_TEST(test_bvh_split);
    RUN_TEST(test_bvh_heights);
    return TEST_SUMMARY();
}
