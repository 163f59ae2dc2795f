/* Camera arithmetic shared by render.c and camera.c (gpu/ internal). */
#ifndef WEFT_GPU_CAMERA_H
#define WEFT_GPU_CAMERA_H

#include "render.h"

/* Orthonormal camera frame: f forward (eye -> target), s right, u up (all unit). */
typedef struct wg_camera_basis {
    double eye[3], f[3], s[3], u[3];
} wg_camera_basis;

/* Size, fov and up of cam (not eye/target). */
wc_status wg_camera_check_lens(const wg_camera* cam, char* err, size_t err_len);
/* Lens checks plus eye/target: finite, distinct, up not parallel to the view. */
wc_status wg_camera_basis_of(const wg_camera* cam, wg_camera_basis* b, char* err, size_t err_len);

/* out = a * b (column-major 4x4). out may not alias a or b. */
void wg_mat4_mul(float out[16], const float a[16], const float b[16]);
/* Inverse transpose of the upper 3x3 of m (column-major 3x3 out); returns 0 when singular. */
int wg_normal_matrix(const float m[16], float out[9]);
/* p' = m p (point, w = 1). */
void wg_transform_point(const float m[16], const float p[3], float out[3]);

#endif
