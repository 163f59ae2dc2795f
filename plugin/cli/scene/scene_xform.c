/* 4x4 column-major transforms (double). */
#include "scene_xform.h"

#include <math.h>
#include <string.h>

void xf_identity(double m[16]) {
    memset(m, 0, 16 * sizeof(double));
    m[0] = m[5] = m[10] = m[15] = 1.0;
}

void xf_mul(const double a[16], const double b[16], double out[16]) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            double s = 0.0;
            for (int k = 0; k < 4; ++k) s += a[4 * k + r] * b[4 * c + k];
            out[4 * c + r] = s;
        }
}

void xf_translation(const double t[3], double m[16]) {
    xf_identity(m);
    m[12] = t[0];
    m[13] = t[1];
    m[14] = t[2];
}

void xf_axis_angle(const double axis[3], double angle, double m[16]) {
    const double x = axis[0], y = axis[1], z = axis[2];
    const double c = cos(angle), s = sin(angle), k = 1.0 - c;
    xf_identity(m);
    m[0] = c + x * x * k;      /* column 0 */
    m[1] = y * x * k + z * s;
    m[2] = z * x * k - y * s;
    m[4] = x * y * k - z * s;  /* column 1 */
    m[5] = c + y * y * k;
    m[6] = z * y * k + x * s;
    m[8] = x * z * k + y * s;  /* column 2 */
    m[9] = y * z * k - x * s;
    m[10] = c + z * z * k;
}

/* Rotation taking +Y to the unit d, for d_y >= 0 (Rodrigues with axis Y x d, no cancellation). */
static void rotate_y_to_upper(const double d[3], double m[16]) {
    /* k = Y x d = (d_z, 0, -d_x); R = I + [k]x + [k]x^2 / (1 + d_y) */
    const double kx = d[2], kz = -d[0], f = 1.0 / (1.0 + d[1]);
    const double K[9] = {0, kz, 0, -kz, 0, kx, 0, -kx, 0};   /* [k]x, column-major 3x3 */
    double K2[9];
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) {
            double s = 0;
            for (int i = 0; i < 3; ++i) s += K[3 * i + r] * K[3 * c + i];
            K2[3 * c + r] = s;
        }
    xf_identity(m);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m[4 * c + r] += K[3 * c + r] + f * K2[3 * c + r];
}

void xf_rotate_y_to(const double dir[3], double m[16]) {
    if (dir[1] >= 0) {
        rotate_y_to_upper(dir, m);
        return;
    }
    /* R = R' Rx(pi) with R' taking +Y to -dir: R (+Y) = R' (-Y) = dir. */
    const double neg[3] = {-dir[0], -dir[1], -dir[2]};
    double r1[16], flip[16];   /* flip: half a turn about X */
    rotate_y_to_upper(neg, r1);
    xf_identity(flip);
    flip[5] = flip[10] = -1.0;
    xf_mul(r1, flip, m);
}

void xf_apply(const double m[16], const double p[3], double out[3]) {
    const double x = p[0], y = p[1], z = p[2];
    for (int r = 0; r < 3; ++r) out[r] = m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r];
}

int xf_split_uniform_scale(const double m[16], double rigid[16], double* scale) {
    if (m[3] != 0 || m[7] != 0 || m[11] != 0 || m[15] != 1) return 0;
    const double det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
                       m[8] * (m[1] * m[6] - m[5] * m[2]);
    if (!(det > 0) || !isfinite(det)) return 0;
    const double s = cbrt(det);
    memcpy(rigid, m, 16 * sizeof(double));
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) rigid[4 * c + r] = m[4 * c + r] / s;
    for (int a = 0; a < 3; ++a)        /* R^T R = I */
        for (int b = 0; b < 3; ++b) {
            double dot = 0;
            for (int r = 0; r < 3; ++r) dot += rigid[4 * a + r] * rigid[4 * b + r];
            if (fabs(dot - (a == b)) > 1e-9) return 0;
        }
    *scale = s;
    return 1;
}

void xf_to_float(const double m[16], float out[16]) {
    for (int i = 0; i < 16; ++i) out[i] = (float)m[i];
}
