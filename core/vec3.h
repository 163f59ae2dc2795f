/* Inline 3-vector and 3x3-matrix helpers on plain double arrays (vectors double[3], matrices
 * double[9] row-major). Header-only so every kernel inlines them. */
#ifndef WEFT_CORE_VEC3_H
#define WEFT_CORE_VEC3_H
#include <math.h>
#include <string.h>

static inline void v3_set(double* o, double x, double y, double z) { o[0] = x; o[1] = y; o[2] = z; }
static inline void v3_copy(double* o, const double* a) { o[0] = a[0]; o[1] = a[1]; o[2] = a[2]; }
static inline void v3_zero(double* o) { o[0] = o[1] = o[2] = 0.0; }
/* exact equality (-0 == 0; NaN equals nothing) */
static inline int v3_equal(const double* a, const double* b) { return a[0] == b[0] && a[1] == b[1] && a[2] == b[2]; }
static inline void v3_add(double* o, const double* a, const double* b) {
    o[0] = a[0] + b[0]; o[1] = a[1] + b[1]; o[2] = a[2] + b[2];
}
static inline void v3_sub(double* o, const double* a, const double* b) {
    o[0] = a[0] - b[0]; o[1] = a[1] - b[1]; o[2] = a[2] - b[2];
}
static inline void v3_scale(double* o, const double* a, double s) { o[0] = a[0] * s; o[1] = a[1] * s; o[2] = a[2] * s; }
/* o += s * a */
static inline void v3_axpy(double* o, double s, const double* a) { o[0] += s * a[0]; o[1] += s * a[1]; o[2] += s * a[2]; }
static inline double v3_dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static inline double v3_norm(const double* a) { return sqrt(v3_dot(a, a)); }
static inline void v3_cross(double* o, const double* a, const double* b) {
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2], z = a[0] * b[1] - a[1] * b[0];
    o[0] = x; o[1] = y; o[2] = z;
}
static inline int v3_finite(const double* a) { return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]); }

/* The smallest delta with n1.delta = a1 (and n2.delta = a2 when two; unit normals, not parallel):
 * delta in span(n1, n2). */
static inline void v3_span2(const double* n1, double a1, const double* n2, double a2, int two, double* delta) {
    if (!two) {
        v3_scale(delta, n1, a1);
        return;
    }
    double c = v3_dot(n1, n2), g = 1.0 - c * c;
    double al = (a1 - c * a2) / g, be = (a2 - c * a1) / g;
    v3_scale(delta, n1, al);
    v3_axpy(delta, be, n2);
}

static inline void m3_zero(double* m) { memset(m, 0, 9 * sizeof(double)); }
static inline void m3_identity(double* m, double s) { m3_zero(m); m[0] = m[4] = m[8] = s; }
/* o = a b^T * s */
static inline void m3_outer(double* o, const double* a, const double* b, double s) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) o[3 * i + j] = s * a[i] * b[j];
}
/* o += s * a */
static inline void m3_axpy(double* o, double s, const double* a) {
    for (int i = 0; i < 9; ++i) o[i] += s * a[i];
}
/* o = m v (o may not alias v) */
static inline void m3_mulv(double* o, const double* m, const double* v) {
    o[0] = m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
    o[1] = m[3] * v[0] + m[4] * v[1] + m[5] * v[2];
    o[2] = m[6] * v[0] + m[7] * v[1] + m[8] * v[2];
}
/* o += m v */
static inline void m3_mulv_add(double* o, const double* m, const double* v) {
    o[0] += m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
    o[1] += m[3] * v[0] + m[4] * v[1] + m[5] * v[2];
    o[2] += m[6] * v[0] + m[7] * v[1] + m[8] * v[2];
}
/* o = a b (o may not alias a or b) */
static inline void m3_mul(double* o, const double* a, const double* b) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            o[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
}
/* Inverse of a 3x3 matrix; returns the determinant (0 and o untouched when singular). */
static inline double m3_inverse(double* o, const double* m) {
    double c0 = m[4] * m[8] - m[5] * m[7], c1 = m[5] * m[6] - m[3] * m[8], c2 = m[3] * m[7] - m[4] * m[6];
    double det = m[0] * c0 + m[1] * c1 + m[2] * c2;
    if (det == 0.0 || !isfinite(det)) return 0.0;
    double id = 1.0 / det;
    o[0] = c0 * id; o[1] = (m[2] * m[7] - m[1] * m[8]) * id; o[2] = (m[1] * m[5] - m[2] * m[4]) * id;
    o[3] = c1 * id; o[4] = (m[0] * m[8] - m[2] * m[6]) * id; o[5] = (m[2] * m[3] - m[0] * m[5]) * id;
    o[6] = c2 * id; o[7] = (m[1] * m[6] - m[0] * m[7]) * id; o[8] = (m[0] * m[4] - m[1] * m[3]) * id;
    return det;
}

#endif
