/* Rigid transforms (xform.h). */
#include "xform.h"
#include "vec3.h"

void wc_xform_identity(wc_xform* o) {
    m3_identity(o->R, 1.0);
    v3_zero(o->t);
}

void wc_xform_from_floats(wc_xform* o, const float* m) {
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) o->R[3 * r + c] = (double)m[4 * c + r];
        o->t[r] = (double)m[12 + r];
    }
}

void wc_xform_point(const wc_xform* x, const double* p, double* out) {
    double o[3];
    m3_mulv(o, x->R, p);
    v3_add(out, o, x->t);
}

void wc_xform_vector(const wc_xform* x, const double* v, double* out) {
    double o[3];
    m3_mulv(o, x->R, v);
    v3_copy(out, o);
}

void wc_xform_inverse(const wc_xform* x, wc_xform* out) {
    wc_xform r;
    if (m3_inverse(r.R, x->R) == 0.0) {
        wc_xform_identity(out);
        return;
    }
    double t[3];
    m3_mulv(t, r.R, x->t);
    v3_scale(r.t, t, -1.0);
    *out = r;
}

int wc_rotation_fraction(const double* R, double c, double* Rc) {
    /* sin(angle) axis = skew part, cos(angle) = (trace - 1) / 2 */
    double w[3] = {0.5 * (R[7] - R[5]), 0.5 * (R[2] - R[6]), 0.5 * (R[3] - R[1])};
    double s = v3_norm(w), co = 0.5 * (R[0] + R[4] + R[8] - 1.0);
    double angle = atan2(s, co);
    m3_identity(Rc, 1.0);
    if (angle == 0.0 || c == 0.0) return 0;
    if (c == 1.0) {   /* the whole rotation: R itself, so a carry by it matches the host's matrices exactly */
        for (int i = 0; i < 9; ++i) Rc[i] = R[i];
        return 1;
    }
    double axis[3];
    if (s > 1e-6) {
        v3_scale(axis, w, 1.0 / s);
    } else {
        /* angle near pi: R ~ 2 a a^T - I; the axis from the largest column of (R + I) / 2 */
        int k = 0;
        for (int i = 1; i < 3; ++i)
            if (R[4 * i] > R[4 * k]) k = i;
        double col[3] = {0.5 * (R[k] + (k == 0)), 0.5 * (R[3 + k] + (k == 1)), 0.5 * (R[6 + k] + (k == 2))};
        double n = v3_norm(col);
        if (!(n > 0.0)) return 0;
        v3_scale(axis, col, 1.0 / n);
        if (v3_dot(axis, w) < 0.0) v3_scale(axis, axis, -1.0);
    }
    double a = c * angle, sa = sin(a), ca1 = 1.0 - cos(a);
    double K[9] = {0, -axis[2], axis[1], axis[2], 0, -axis[0], -axis[1], axis[0], 0}, K2[9];
    m3_mul(K2, K, K);
    for (int i = 0; i < 9; ++i) Rc[i] += sa * K[i] + ca1 * K2[i];
    return 1;
}

void wc_rotate_points(double* x, int n, const double* R, const double* p0) {
    for (int i = 0; i < n; ++i) {
        double d[3], o[3];
        v3_sub(d, x + 3 * i, p0);
        m3_mulv(o, R, d);
        v3_add(x + 3 * i, p0, o);
    }
}

void wc_rotate_vectors(double* v, int n, const double* R) {
    for (int i = 0; i < n; ++i) {
        double o[3];
        m3_mulv(o, R, v + 3 * i);
        v3_copy(v + 3 * i, o);
    }
}
