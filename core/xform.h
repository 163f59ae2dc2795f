/* Rigid transforms of a host's scene in double: p' = R p + t, R row-major 3x3. Hosts give them
 * as 16 floats, column-major (element (row r, column c) at m[4c + r]); whoever takes them from a
 * host checks them (finite, last row (0, 0, 0, 1), R rigid within 1e-3). The maths uses the
 * matrix as given (exact affine inverse, not the transpose), so a point bound through a
 * transform maps back exactly through the same transform. */
#ifndef WEFT_CORE_XFORM_H
#define WEFT_CORE_XFORM_H

typedef struct wc_xform {
    double R[9];
    double t[3];
} wc_xform;

void wc_xform_identity(wc_xform* o);
/* From 16 floats, column-major; no checks. */
void wc_xform_from_floats(wc_xform* o, const float* m);
void wc_xform_point(const wc_xform* x, const double* p, double* out);    /* out = R p + t (out may be p) */
void wc_xform_vector(const wc_xform* x, const double* v, double* out);   /* out = R v (out may be v) */
/* Exact affine inverse (general 3x3 inverse, not the transpose); identity if singular. */
void wc_xform_inverse(const wc_xform* x, wc_xform* out);
/* Rotation by fraction c of the rotation in R (axis-angle, Rodrigues), into Rc (row-major 3x3);
 * c == 1 gives R itself (the host's matrix, rigid within 1e-3, not re-orthonormalised).
 * Returns 0 (and Rc = I) when R's rotation angle or c is 0, else 1. */
int wc_rotation_fraction(const double* R, double c, double* Rc);
/* x <- p0 + R (x - p0) for n points, and v <- R v for n vectors (n x 3 each, R row-major). */
void wc_rotate_points(double* x, int n, const double* R, const double* p0);
void wc_rotate_vectors(double* v, int n, const double* R);

#endif
