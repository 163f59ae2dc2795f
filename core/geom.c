#include "geom.h"

#include <math.h>

#include "vec3.h"

static double clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

static double closest_on_segment(const double* p, const double* a, const double* b, double* s) {
    double ab[3], ap[3];
    v3_sub(ab, b, a);
    v3_sub(ap, p, a);
    double l2 = v3_dot(ab, ab);
    double t = l2 > 0.0 ? clamp01(v3_dot(ap, ab) / l2) : 0.0;
    double d[3];
    v3_axpy(ap, -t, ab);
    v3_copy(d, ap);
    *s = t;
    return v3_dot(d, d);
}

/* Ericson, Real-Time Collision Detection, 5.1.5, by Voronoi regions; degenerate triangles fall
 * back to their three edges. */
double wc_closest_on_triangle(const double* p, const double* a, const double* b, const double* c, double* w,
                              double* q) {
    double ab[3], ac[3], ap[3], bp[3], cp[3], n[3];
    v3_sub(ab, b, a);
    v3_sub(ac, c, a);
    v3_cross(n, ab, ac);
    double wt[3];
    double nn = v3_dot(n, n), scale = v3_dot(ab, ab) * v3_dot(ac, ac);
    if (!(nn > 1e-24 * scale) || scale == 0.0) {
        /* degenerate: best of the three edges */
        double s, best, d;
        best = closest_on_segment(p, a, b, &s);
        wt[0] = 1.0 - s; wt[1] = s; wt[2] = 0.0;
        d = closest_on_segment(p, b, c, &s);
        if (d < best) { best = d; wt[0] = 0.0; wt[1] = 1.0 - s; wt[2] = s; }
        d = closest_on_segment(p, a, c, &s);
        if (d < best) { best = d; wt[0] = 1.0 - s; wt[1] = 0.0; wt[2] = s; }
        goto done;
    }
    v3_sub(ap, p, a);
    double d1 = v3_dot(ab, ap), d2 = v3_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) { wt[0] = 1; wt[1] = 0; wt[2] = 0; goto done; }
    v3_sub(bp, p, b);
    double d3 = v3_dot(ab, bp), d4 = v3_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) { wt[0] = 0; wt[1] = 1; wt[2] = 0; goto done; }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double v = d1 / (d1 - d3);
        wt[0] = 1 - v; wt[1] = v; wt[2] = 0; goto done;
    }
    v3_sub(cp, p, c);
    double d5 = v3_dot(ab, cp), d6 = v3_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) { wt[0] = 0; wt[1] = 0; wt[2] = 1; goto done; }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double v = d2 / (d2 - d6);
        wt[0] = 1 - v; wt[1] = 0; wt[2] = v; goto done;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        wt[0] = 0; wt[1] = 1 - v; wt[2] = v; goto done;
    }
    {
        double den = 1.0 / (va + vb + vc);
        wt[1] = vb * den;
        wt[2] = vc * den;
        wt[0] = 1.0 - wt[1] - wt[2];
    }
done:;
    double qq[3];
    for (int k = 0; k < 3; ++k) qq[k] = wt[0] * a[k] + wt[1] * b[k] + wt[2] * c[k];
    if (w) v3_copy(w, wt);
    if (q) v3_copy(q, qq);
    double d[3];
    v3_sub(d, p, qq);
    return v3_dot(d, d);
}

/* Ericson 5.1.9. */
double wc_closest_on_segments(const double* p0, const double* p1, const double* q0, const double* q1, double* s,
                              double* t) {
    double d1[3], d2[3], r[3];
    v3_sub(d1, p1, p0);
    v3_sub(d2, q1, q0);
    v3_sub(r, p0, q0);
    double a = v3_dot(d1, d1), e = v3_dot(d2, d2), f = v3_dot(d2, r);
    double ss, tt;
    double tiny = 1e-300;
    if (a <= tiny && e <= tiny) {
        ss = tt = 0.0;
    } else if (a <= tiny) {
        ss = 0.0;
        tt = clamp01(f / e);
    } else {
        double c = v3_dot(d1, r);
        if (e <= tiny) {
            tt = 0.0;
            ss = clamp01(-c / a);
        } else {
            double b = v3_dot(d1, d2), den = a * e - b * b;
            ss = den > 1e-14 * a * e ? clamp01((b * f - c * e) / den) : 0.0;
            tt = (b * ss + f) / e;
            if (tt < 0.0) {
                tt = 0.0;
                ss = clamp01(-c / a);
            } else if (tt > 1.0) {
                tt = 1.0;
                ss = clamp01((b - c) / a);
            }
        }
    }
    double cp[3], cq[3], d[3];
    for (int k = 0; k < 3; ++k) {
        cp[k] = p0[k] + ss * d1[k];
        cq[k] = q0[k] + tt * d2[k];
    }
    v3_sub(d, cp, cq);
    if (s) *s = ss;
    if (t) *t = tt;
    return v3_dot(d, d);
}

static double cubic(double c0, double c1, double c2, double c3, double t) { return ((c3 * t + c2) * t + c1) * t + c0; }

int wc_cubic_roots01(double c0, double c1, double c2, double c3, double scale, double* roots) {
    double tol = 1e-12 * (scale > 0.0 ? scale : 1.0);
    if (fabs(c0) <= tol && fabs(c1) <= tol && fabs(c2) <= tol && fabs(c3) <= tol) return -1;
    /* split [0, 1] at the turning points (roots of c1 + 2 c2 t + 3 c3 t^2) */
    double cut[4];
    int nc = 0;
    cut[nc++] = 0.0;
    double qa = 3.0 * c3, qb = 2.0 * c2, qc = c1;
    double ext[2];
    int ne = 0;
    if (fabs(qa) > 1e-300) {
        double disc = qb * qb - 4.0 * qa * qc;
        if (disc >= 0.0) {
            double sq = sqrt(disc);
            double q = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));
            double r1 = q / qa, r2 = q != 0.0 ? qc / q : r1;
            ext[ne++] = r1 < r2 ? r1 : r2;
            ext[ne++] = r1 < r2 ? r2 : r1;
        }
    } else if (fabs(qb) > 1e-300) {
        ext[ne++] = -qc / qb;
    }
    for (int i = 0; i < ne; ++i)
        if (ext[i] > 0.0 && ext[i] < 1.0 && ext[i] > cut[nc - 1]) cut[nc++] = ext[i];
    cut[nc++] = 1.0;
    int nr = 0;
    for (int i = 0; i + 1 < nc; ++i) {
        double lo = cut[i], hi = cut[i + 1];
        double flo = cubic(c0, c1, c2, c3, lo), fhi = cubic(c0, c1, c2, c3, hi);
        double root;
        if (fabs(flo) <= tol) {
            root = lo;
        } else if (fabs(fhi) <= tol) {
            root = hi;
        } else if ((flo < 0.0) != (fhi < 0.0)) {
            for (int it = 0; it < 60 && hi - lo > 1e-12; ++it) {
                double mid = 0.5 * (lo + hi), fm = cubic(c0, c1, c2, c3, mid);
                if ((fm < 0.0) == (flo < 0.0)) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            root = 0.5 * (lo + hi);
        } else {
            continue;
        }
        if (nr == 0 || root > roots[nr - 1] + 1e-12) roots[nr++] = root;
    }
    return nr;
}

/* Coefficients of u(t) . (v(t) x w(t)) with u, v, w linear in t. Returns the scale of its terms. */
static double triple_cubic(const double* u0, const double* u1, const double* v0, const double* v1, const double* w0,
                           const double* w1, double* c) {
    double x[3];
    v3_cross(x, v0, w0);
    c[0] = v3_dot(u0, x);
    c[1] = v3_dot(u1, x);
    v3_cross(x, v1, w0);
    c[1] += v3_dot(u0, x);
    c[2] = v3_dot(u1, x);
    v3_cross(x, v0, w1);
    c[1] += v3_dot(u0, x);
    c[2] += v3_dot(u1, x);
    v3_cross(x, v1, w1);
    c[2] += v3_dot(u0, x);
    c[3] = v3_dot(u1, x);
    double lu = v3_norm(u0) + v3_norm(u1), lv = v3_norm(v0) + v3_norm(v1), lw = v3_norm(w0) + v3_norm(w1);
    return lu * lv * lw;
}

static void lerp(double* o, const double* a0, const double* a1, double t) {
    for (int k = 0; k < 3; ++k) o[k] = a0[k] + t * (a1[k] - a0[k]);
}

/* Times to test: the coplanarity roots, or the start and the end when always coplanar. */
static int candidate_times(const double* x0, const double* x1, const double* y0, const double* y1, const double* z0,
                           const double* z1, const double* o0, const double* o1, double* times) {
    double u0[3], u1[3], v0[3], v1[3], w0[3], w1[3], e[3];
    /* relative to o: u = x - o etc., each linear: start value and change over the substep */
    v3_sub(u0, x0, o0);
    v3_sub(v0, y0, o0);
    v3_sub(w0, z0, o0);
    v3_sub(e, x1, o1);
    v3_sub(u1, e, u0);
    v3_sub(e, y1, o1);
    v3_sub(v1, e, v0);
    v3_sub(e, z1, o1);
    v3_sub(w1, e, w0);
    double c[4];
    double scale = triple_cubic(u0, u1, v0, v1, w0, w1, c);
    int nr = wc_cubic_roots01(c[0], c[1], c[2], c[3], scale, times);
    if (nr < 0) {
        times[0] = 0.0;
        times[1] = 1.0;
        nr = 2;
    }
    return nr;
}

int wc_ccd_point_triangle(const double* p0, const double* a0, const double* b0, const double* c0, const double* p1,
                          const double* a1, const double* b1, const double* c1, double eta, double* t, double* w) {
    double times[4];
    int nr = candidate_times(p0, p1, b0, b1, c0, c1, a0, a1, times);
    for (int i = 0; i < nr; ++i) {
        double p[3], a[3], b[3], c[3];
        lerp(p, p0, p1, times[i]);
        lerp(a, a0, a1, times[i]);
        lerp(b, b0, b1, times[i]);
        lerp(c, c0, c1, times[i]);
        if (wc_closest_on_triangle(p, a, b, c, w, NULL) <= eta * eta) {
            *t = times[i];
            return 1;
        }
    }
    return 0;
}

int wc_ccd_edge_edge(const double* p0, const double* q0, const double* r0, const double* s0, const double* p1,
                     const double* q1, const double* r1, const double* s1, double eta, double* t, double* sa,
                     double* sb) {
    double times[4];
    int nr = candidate_times(q0, q1, r0, r1, s0, s1, p0, p1, times);
    for (int i = 0; i < nr; ++i) {
        double p[3], q[3], r[3], s[3];
        lerp(p, p0, p1, times[i]);
        lerp(q, q0, q1, times[i]);
        lerp(r, r0, r1, times[i]);
        lerp(s, s0, s1, times[i]);
        if (wc_closest_on_segments(p, q, r, s, sa, sb) <= eta * eta) {
            *t = times[i];
            return 1;
        }
    }
    return 0;
}
