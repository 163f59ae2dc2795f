/* 4x4 transforms in double, column-major like the public API's (element (row r, column c) at
 * m[4c + r], translation at 12, 13, 14): the little algebra scene motions and collider
 * placements need. */
#ifndef WEFT_CLI_SCENE_XFORM_H
#define WEFT_CLI_SCENE_XFORM_H

void xf_identity(double m[16]);
/* out = a b (out may alias neither). */
void xf_mul(const double a[16], const double b[16], double out[16]);
/* Translation by t. */
void xf_translation(const double t[3], double m[16]);
/* Rotation by angle (radians, right-handed) about the unit axis through the origin. */
void xf_axis_angle(const double axis[3], double angle, double m[16]);
/* A rotation taking +Y to the unit vector dir (the shortest one; +Y -> -Y turns about X). */
void xf_rotate_y_to(const double dir[3], double m[16]);
/* out = m p for a point (m affine). out may alias p. */
void xf_apply(const double m[16], const double p[3], double out[3]);
/* Split an affine m into rigid x uniform scale (m = rigid diag(s, s, s, 1)) when it is one:
 * returns 1 and fills rigid and *scale (> 0), else 0 (reflection, shear, non-uniform scale, or
 * a last row other than 0 0 0 1). Relative tolerance 1e-9. */
int xf_split_uniform_scale(const double m[16], double rigid[16], double* scale);
/* Double to the API's float layout. */
void xf_to_float(const double m[16], float out[16]);

#endif
