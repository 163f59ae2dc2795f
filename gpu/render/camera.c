/* Camera: validation, view/projection matrices, scene bounds and automatic framing. */
#include "camera.h"

#include <math.h>
#include <string.h>

#include "gpu_error.h"

static const double kPi = 3.14159265358979323846;

static int finite3(const float v[3]) {
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double normalize3(double v[3]) {
    double n = sqrt(dot3(v, v));
    if (n > 0) {
        v[0] /= n;
        v[1] /= n;
        v[2] /= n;
    }
    return n;
}

wc_status wg_camera_check_lens(const wg_camera* cam, char* err, size_t err_len) {
    if (!cam) {
        wg_errorf(err, err_len, "camera is NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (cam->width < 1 || cam->width > WG_MAX_IMAGE_SIZE || cam->height < 1 ||
        cam->height > WG_MAX_IMAGE_SIZE) {
        wg_errorf(err, err_len, "camera size %d x %d: width and height must be in 1..%d",
                  cam->width, cam->height, WG_MAX_IMAGE_SIZE);
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (!isfinite(cam->fov_y_deg) || !finite3(cam->up)) {
        wg_errorf(err, err_len, "camera fov_y_deg or up is not finite (fov %g, up %g %g %g)",
                  (double)cam->fov_y_deg, (double)cam->up[0], (double)cam->up[1],
                  (double)cam->up[2]);
        return WC_ERROR_NONFINITE;
    }
    if (!(cam->fov_y_deg > 0.0f && cam->fov_y_deg < 180.0f)) {
        wg_errorf(err, err_len, "camera fov_y_deg = %g must be in (0, 180)",
                  (double)cam->fov_y_deg);
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (cam->up[0] == 0.0f && cam->up[1] == 0.0f && cam->up[2] == 0.0f) {
        wg_errorf(err, err_len, "camera up is the zero vector");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    return WC_OK;
}

wc_status wg_camera_basis_of(const wg_camera* cam, wg_camera_basis* b, char* err,
                               size_t err_len) {
    wc_status st = wg_camera_check_lens(cam, err, err_len);
    if (st != WC_OK) return st;
    if (!finite3(cam->eye) || !finite3(cam->target)) {
        wg_errorf(err, err_len, "camera eye (%g %g %g) or target (%g %g %g) is not finite",
                  (double)cam->eye[0], (double)cam->eye[1], (double)cam->eye[2],
                  (double)cam->target[0], (double)cam->target[1], (double)cam->target[2]);
        return WC_ERROR_NONFINITE;
    }
    double up[3];
    for (int i = 0; i < 3; ++i) {
        b->eye[i] = cam->eye[i];
        b->f[i] = (double)cam->target[i] - (double)cam->eye[i];
        up[i] = cam->up[i];
    }
    double dist = normalize3(b->f);
    if (!(dist > 0)) {
        wg_errorf(err, err_len, "camera eye and target are the same point");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    normalize3(up);
    cross3(b->f, up, b->s);
    if (normalize3(b->s) < 1e-6) {
        wg_errorf(err, err_len, "camera up (%g %g %g) is parallel to the view direction",
                  (double)cam->up[0], (double)cam->up[1], (double)cam->up[2]);
        return WC_ERROR_INVALID_ARGUMENT;
    }
    cross3(b->s, b->f, b->u);
    return WC_OK;
}

wc_status wg_camera_matrices(const wg_camera* cam, float znear, float zfar, float view[16],
                               float proj[16], char* err, size_t err_len) {
    wg_camera_basis b;
    wc_status st = wg_camera_basis_of(cam, &b, err, err_len);
    if (st != WC_OK) return st;
    if (!view || !proj) {
        wg_errorf(err, err_len, "wg_camera_matrices: view or proj is NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (!isfinite(znear) || !isfinite(zfar) || !(znear > 0.0f) || !(zfar > znear)) {
        wg_errorf(err, err_len, "near %g / far %g: need 0 < near < far", (double)znear,
                  (double)zfar);
        return WC_ERROR_INVALID_ARGUMENT;
    }
    memset(view, 0, 16 * sizeof(float));
    for (int i = 0; i < 3; ++i) {
        view[4 * i + 0] = (float)b.s[i];
        view[4 * i + 1] = (float)b.u[i];
        view[4 * i + 2] = (float)-b.f[i];
    }
    view[12] = (float)-dot3(b.s, b.eye);
    view[13] = (float)-dot3(b.u, b.eye);
    view[14] = (float)dot3(b.f, b.eye);
    view[15] = 1.0f;

    double t = 1.0 / tan(0.5 * (double)cam->fov_y_deg * kPi / 180.0);
    double aspect = (double)cam->width / (double)cam->height;
    double n = znear, fa = zfar;
    memset(proj, 0, 16 * sizeof(float));
    proj[0] = (float)(t / aspect);
    proj[5] = (float)t;
    proj[10] = (float)((fa + n) / (n - fa));
    proj[11] = -1.0f;
    proj[14] = (float)(2.0 * fa * n / (n - fa));
    return WC_OK;
}

/* Extent of a ball of radius r after the linear part of m, along world axis i: r |row i|. */
static float ball_extent(const float m[16], int i, float r) {
    double a = m[i], b = m[4 + i], c = m[8 + i];
    return (float)(r * sqrt(a * a + b * b + c * c));
}

static void grow(float bmin[3], float bmax[3], const float p[3], const float ext[3]) {
    for (int i = 0; i < 3; ++i) {
        if (p[i] - ext[i] < bmin[i]) bmin[i] = p[i] - ext[i];
        if (p[i] + ext[i] > bmax[i]) bmax[i] = p[i] + ext[i];
    }
}

int wg_scene_bounds(const wg_mesh* meshes, int n_meshes, const wg_shape* shapes, int n_shapes,
                    float bmin[3], float bmax[3]) {
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const float zero[3] = {0, 0, 0};
    int any = 0;
    for (int k = 0; k < n_meshes && meshes; ++k) {
        const wg_mesh* m = &meshes[k];
        /* only vertices some triangle uses would be tighter; all vertices are what hosts expect */
        for (int v = 0; v < m->n_vertices && m->positions; ++v) {
            grow(lo, hi, &m->positions[3 * v], zero);
            any = 1;
        }
    }
    for (int k = 0; k < n_shapes && shapes; ++k) {
        const wg_shape* s = &shapes[k];
        if (s->type != WG_SHAPE_SPHERE && s->type != WG_SHAPE_CAPSULE) continue;
        float ext[3];
        for (int i = 0; i < 3; ++i) ext[i] = ball_extent(s->transform, i, s->radius);
        float hh = s->type == WG_SHAPE_CAPSULE ? s->half_height : 0.0f;
        for (int end = -1; end <= 1; end += 2) {
            float local[3] = {0.0f, (float)end * hh, 0.0f}, world[3];
            wg_transform_point(s->transform, local, world);
            grow(lo, hi, world, ext);
        }
        any = 1;
    }
    if (!any) return 0;
    for (int i = 0; i < 3; ++i) {
        bmin[i] = lo[i];
        bmax[i] = hi[i];
    }
    return 1;
}

wc_status wg_camera_frame_auto(wg_camera* cam, const float bmin[3], const float bmax[3],
                                 char* err, size_t err_len) {
    wc_status st = wg_camera_check_lens(cam, err, err_len);
    if (st != WC_OK) return st;
    if (!bmin || !bmax) {
        wg_errorf(err, err_len, "wg_camera_frame_auto: box is NULL");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (!finite3(bmin) || !finite3(bmax)) {
        wg_errorf(err, err_len, "box to frame is not finite");
        return WC_ERROR_NONFINITE;
    }
    double c[3], half[3];
    for (int i = 0; i < 3; ++i) {
        if (bmin[i] > bmax[i]) {
            wg_errorf(err, err_len, "box to frame has min > max on axis %d (%g > %g)", i,
                      (double)bmin[i], (double)bmax[i]);
            return WC_ERROR_INVALID_ARGUMENT;
        }
        c[i] = 0.5 * ((double)bmin[i] + (double)bmax[i]);
        half[i] = 0.5 * ((double)bmax[i] - (double)bmin[i]);
    }
    double r = sqrt(dot3(half, half));
    if (!(r > 1e-9 * (1.0 + sqrt(dot3(c, c))))) r = 0.5 * sqrt(3.0); /* a point: a 1 m box */

    /* Viewing direction from the front-right and above, in the frame of up. */
    double u[3] = {cam->up[0], cam->up[1], cam->up[2]};
    normalize3(u);
    double a[3] = {0, 0, 1};
    if (fabs(u[2]) > 0.9) {
        a[0] = 1;
        a[2] = 0;
    }
    double z[3], x[3], dir[3];
    double au = dot3(a, u);
    for (int i = 0; i < 3; ++i) z[i] = a[i] - au * u[i];
    normalize3(z);
    cross3(u, z, x);
    for (int i = 0; i < 3; ++i) dir[i] = 0.5 * x[i] + 0.45 * u[i] + 1.0 * z[i];
    normalize3(dir);

    /* The bounding sphere inside the narrower of the two half-angles, with a margin. */
    double half_y = 0.5 * (double)cam->fov_y_deg * kPi / 180.0;
    double half_x = atan(tan(half_y) * (double)cam->width / (double)cam->height);
    double half_min = half_y < half_x ? half_y : half_x;
    double d = 1.08 * r / sin(half_min);
    for (int i = 0; i < 3; ++i) {
        cam->target[i] = (float)c[i];
        cam->eye[i] = (float)(c[i] + d * dir[i]);
    }
    return WC_OK;
}

void wg_mat4_mul(float out[16], const float a[16], const float b[16]) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += (double)a[4 * k + r] * (double)b[4 * c + k];
            out[4 * c + r] = (float)s;
        }
}

int wg_normal_matrix(const float m[16], float out[9]) {
    /* element (r, c) of the 3x3 is m[4c + r]; inverse transpose = cofactor matrix / det */
#define M(r, c) ((double)m[4 * (c) + (r)])
    double cof[3][3];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            cof[r][c] = M(r1, c1) * M(r2, c2) - M(r1, c2) * M(r2, c1);
        }
    double det = M(0, 0) * cof[0][0] + M(0, 1) * cof[0][1] + M(0, 2) * cof[0][2];
#undef M
    double scale = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) scale = fmax(scale, fabs((double)m[4 * j + i]));
    if (!(fabs(det) > 1e-12 * scale * scale * scale) || !isfinite(det)) return 0;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) out[3 * c + r] = (float)(cof[r][c] / det);
    return 1;
}

void wg_transform_point(const float m[16], const float p[3], float out[3]) {
    for (int r = 0; r < 3; ++r)
        out[r] = (float)((double)m[r] * p[0] + (double)m[4 + r] * p[1] + (double)m[8 + r] * p[2] +
                         (double)m[12 + r]);
}
