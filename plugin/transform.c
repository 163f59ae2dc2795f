/* Host transforms: 16 floats, column-major (element (row r, column c) at m[4c + r]), converted to
 * a double affine wa_xform. The rigidity check gates what hosts may pass (rotation + translation);
 * the maths then uses the matrix as given (exact affine inverse, not the transpose), so a binding
 * taken with a transform maps back exactly through the same transform. */
#include <math.h>
#include <stdio.h>
#include "api_internal.h"
#include "vec3.h"

void wa_xform_identity(wa_xform* o) {
    m3_identity(o->R, 1.0);
    v3_zero(o->t);
}

void wa_xform_from_floats(wa_xform* o, const float* m) {
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) o->R[3 * r + c] = (double)m[4 * c + r];
        o->t[r] = (double)m[12 + r];
    }
}

weft_status wa_check_transform(const float* m, char* why, size_t why_size) {
    for (int k = 0; k < 16; ++k)
        if (!isfinite(m[k])) {
            snprintf(why, why_size, "[%d] is %s", k, isnan(m[k]) ? "NaN" : "Inf");
            return WEFT_ERROR_NONFINITE;
        }
    /* last row: elements (3, c) at m[4c + 3] */
    if (fabsf(m[3]) > 1e-6f || fabsf(m[7]) > 1e-6f || fabsf(m[11]) > 1e-6f || fabsf(m[15] - 1.0f) > 1e-6f) {
        snprintf(why, why_size, " has last row (%g, %g, %g, %g), not (0, 0, 0, 1)", (double)m[3], (double)m[7],
                 (double)m[11], (double)m[15]);
        return WEFT_ERROR_INVALID_ARGUMENT;
    }
    wa_xform x;
    wa_xform_from_floats(&x, m);
    const double* R = x.R;
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                 R[2] * (R[3] * R[7] - R[4] * R[6]);
    double worst = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j] - (i == j ? 1.0 : 0.0);
            if (fabs(d) > worst) worst = fabs(d);
        }
    if (!(fabs(det - 1.0) < 1e-3) || !(worst < 1e-3)) {
        snprintf(why, why_size,
                 " is not rigid (det %.6g, max |R^T R - I| %.3g; tolerance 1e-3): scale the mesh instead", det, worst);
        return WEFT_ERROR_INVALID_ARGUMENT;
    }
    return WEFT_OK;
}

void wa_xform_point(const wa_xform* x, const double* p, double* out) {
    double o[3];
    m3_mulv(o, x->R, p);
    v3_add(out, o, x->t);
}

void wa_xform_vector(const wa_xform* x, const double* v, double* out) {
    double o[3];
    m3_mulv(o, x->R, v);
    v3_copy(out, o);
}

void wa_xform_inverse(const wa_xform* x, wa_xform* out) {
    wa_xform r;
    if (m3_inverse(r.R, x->R) == 0.0) {
        wa_xform_identity(out);
        return;
    }
    double t[3];
    m3_mulv(t, r.R, x->t);
    v3_scale(r.t, t, -1.0);
    *out = r;
}

int wa_rotation_fraction(const double* R, double c, double* Rc) {
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
