#include "triangulate.h"
#include <math.h>

static void sub3(const double* a, const double* b, double* r) {
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

static void cross3(const double* a, const double* b, double* r) {
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Newell's normal of the polygon (not normalised). */
static void newell_normal(const int* c, int k, const double* pos, double* n) {
    n[0] = n[1] = n[2] = 0.0;
    for (int i = 0; i < k; ++i) {
        const double* p = pos + 3 * c[i];
        const double* q = pos + 3 * c[(i + 1) % k];
        n[0] += (p[1] - q[1]) * (p[2] + q[2]);
        n[1] += (p[2] - q[2]) * (p[0] + q[0]);
        n[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
}

/* Twice the signed area of triangle (a, b, c) along n. */
static double signed_area(const double* pos, int a, int b, int c, const double* n) {
    double e1[3], e2[3], x[3];
    sub3(pos + 3 * b, pos + 3 * a, e1);
    sub3(pos + 3 * c, pos + 3 * a, e2);
    cross3(e1, e2, x);
    return dot3(x, n);
}

static double dist2(const double* pos, int a, int b) {
    double d[3];
    sub3(pos + 3 * a, pos + 3 * b, d);
    return dot3(d, d);
}

static void emit(int* tris, unsigned char* mask, int t, int a, int b, int c, unsigned char m) {
    tris[3 * t] = a;
    tris[3 * t + 1] = b;
    tris[3 * t + 2] = c;
    mask[t] = m;
}

/* Is point p inside or on triangle (a, b, c) (counter-clockwise about n)? A corner lying on the
 * candidate ear's new diagonal blocks it: clipping there would cover area outside the polygon. */
static int inside(const double* pos, int a, int b, int c, int p, const double* n) {
    return signed_area(pos, a, b, p, n) >= 0 && signed_area(pos, b, c, p, n) >= 0 &&
           signed_area(pos, c, a, p, n) >= 0;
}

static int is_polygon_side(int i, int j, int k) { return ((i + 1) % k) == j; }

int wc_triangulate_polygon(const int* corners, int k, const double* pos, int* tris,
                           unsigned char* side_mask, int* scratch) {
    const int* c = corners;
    if (k == 3) {
        emit(tris, side_mask, 0, c[0], c[1], c[2], 7);
        return 1;
    }
    double n[3];
    newell_normal(c, k, pos, n);
    if (k == 4) {
        /* diagonal 0-2: (0,1,2) + (0,2,3); diagonal 1-3: (1,2,3) + (1,3,0) */
        int ok02 = signed_area(pos, c[0], c[1], c[2], n) > 0 && signed_area(pos, c[0], c[2], c[3], n) > 0;
        int ok13 = signed_area(pos, c[1], c[2], c[3], n) > 0 && signed_area(pos, c[1], c[3], c[0], n) > 0;
        int use02 = ok02 && (!ok13 || dist2(pos, c[0], c[2]) <= dist2(pos, c[1], c[3]));
        if (!ok02 && !ok13) use02 = 1; /* degenerate or bow-tie quad: keep a deterministic split */
        if (use02) {
            emit(tris, side_mask, 0, c[0], c[1], c[2], 3);
            emit(tris, side_mask, 1, c[0], c[2], c[3], 6);
        } else {
            emit(tris, side_mask, 0, c[1], c[2], c[3], 3);
            emit(tris, side_mask, 1, c[1], c[3], c[0], 6);
        }
        return 2;
    }
    if (k > WC_EAR_CLIP_MAX) {
        for (int i = 1; i + 1 < k; ++i)
            emit(tris, side_mask, i - 1, c[0], c[i], c[i + 1],
                 (unsigned char)((i == 1 ? 1 : 0) | 2 | (i + 2 == k ? 4 : 0)));
        return k - 2;
    }
    /* Ear clipping over the remaining corners (indices into c). */
    int* idx = scratch;
    int m = k, t = 0;
    for (int i = 0; i < k; ++i) idx[i] = i;
    while (m > 3) { /* one corner clipped per pass */
        int found = -1;
        for (int i = 0; i < m && found < 0; ++i) {
            int ip = idx[(i + m - 1) % m], ic = idx[i], in = idx[(i + 1) % m];
            if (signed_area(pos, c[ip], c[ic], c[in], n) <= 0) continue; /* reflex or flat */
            int clear = 1;
            for (int j = 0; j < m && clear; ++j) {
                int o = idx[j];
                if (o == ip || o == ic || o == in) continue;
                if (c[o] == c[ip] || c[o] == c[ic] || c[o] == c[in]) continue;
                if (inside(pos, c[ip], c[ic], c[in], c[o], n)) clear = 0;
            }
            if (clear) found = i;
        }
        if (found < 0) found = 0; /* self-intersecting or degenerate: clip anyway */
        int ip = idx[(found + m - 1) % m], ic = idx[found], in = idx[(found + 1) % m];
        unsigned char mk = (unsigned char)((is_polygon_side(ip, ic, k) ? 1 : 0) |
                                           (is_polygon_side(ic, in, k) ? 2 : 0) |
                                           (is_polygon_side(in, ip, k) ? 4 : 0));
        emit(tris, side_mask, t++, c[ip], c[ic], c[in], mk);
        for (int j = found; j < m - 1; ++j) idx[j] = idx[j + 1];
        --m;
    }
    int a = idx[0], b = idx[1], d = idx[2];
    unsigned char mk = (unsigned char)((is_polygon_side(a, b, k) ? 1 : 0) |
                                       (is_polygon_side(b, d, k) ? 2 : 0) |
                                       (is_polygon_side(d, a, k) ? 4 : 0));
    emit(tris, side_mask, t++, c[a], c[b], c[d], mk);
    return t;
}
