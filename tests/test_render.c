/* gpu/ preview renderer pictures on a real headless EGL context (llvmpipe where there is no
 * GPU), checked against an independent pinhole model: silhouettes of a sphere, a capsule and a
 * quad at their analytic pixel positions, the sky gradient, the checker of a plane found by
 * casting each pixel's ray, lit versus shadowed sides, front versus back colours; automatic
 * framing; the PNG read back through libpng; MSAA on and off, resizing. */
#include <EGL/egl.h>
#include <GL/glew.h>
#include <png.h>

#include "check.h"
#include "png_write.h"
#include "render_support.h"
#include "test_support.h"

static wg_gl_context* g_ctx;     /* headless, created in main */
static wg_renderer* g_r;         /* default samples */
static char g_log[4096];         /* every message the context logged */

static void capture_log(wc_log_level level, const char* message, void* user) {
    (void)user;
    size_t used = strlen(g_log);
    snprintf(g_log + used, sizeof g_log - used, "[%d] %s\n", (int)level, message);
}

/* ---- tests ---- */

static void test_context_info(void) {
    const char* d = wg_gl_context_description(g_ctx);
    printf("  device: %s\n", d);
    CHECK(strstr(d, "EGL") != NULL);
    CHECK(strstr(d, "OpenGL") != NULL);
    CHECK(strstr(g_log, "[1] weft gpu: using ") != NULL); /* INFO names the device */
    CHECK(!wg_gl_context_is_host(g_ctx));
    /* begin makes it current, end gives the thread back no context */
    char err[256];
    CHECK_EQ_INT(wg_gl_begin(g_ctx, err, sizeof err), WC_OK);
    CHECK(eglGetCurrentContext() != EGL_NO_CONTEXT);
    /* a core profile: asked of GL, not read from GL_VERSION (Mesa writes "Core Profile" there,
       NVIDIA's driver does not) */
    const char* version = (const char*)glGetString(GL_VERSION);
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    CHECK(version != NULL);
    CHECK((profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0);
    CHECK_EQ_INT(wg_gl_begin(g_ctx, err, sizeof err), WC_ERROR_CALL_ORDER);
    CHECK(strstr(err, "not nestable") != NULL);
    wg_gl_end(g_ctx);
    CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT);
}

static void check_sphere_silhouette(const unsigned char* img, const wg_camera* cam, double cx,
                                    double cy, double radius_px) {
    int inside_ok = 0, outside_ok = 0, n = 48;
    for (int k = 0; k < n; ++k) {
        double a = 2.0 * RS_PI * k / n;
        double ri = radius_px - 1.5, ro = radius_px + 1.5;
        int xi = (int)floor(cx + ri * cos(a)), yi = (int)floor(cy + ri * sin(a));
        int xo = (int)floor(cx + ro * cos(a)), yo = (int)floor(cy + ro * sin(a));
        /* pixel centres on the other side of the circle by more than a pixel's half-diagonal */
        double di = hypot(xi + 0.5 - cx, yi + 0.5 - cy), dout = hypot(xo + 0.5 - cx, yo + 0.5 - cy);
        if (di < radius_px - 0.75) inside_ok += !is_sky(img, cam->width, cam->height, xi, yi, 6);
        else ++inside_ok;
        if (dout > radius_px + 0.75) outside_ok += is_sky(img, cam->width, cam->height, xo, yo, 2);
        else ++outside_ok;
    }
    CHECK_EQ_INT(inside_ok, n);
    CHECK_EQ_INT(outside_ok, n);
}

static void test_sphere_sky_and_light(void) {
    wg_camera cam = front_camera(200, 150);
    wg_shape sphere = shape_at(WG_SHAPE_SPHERE, 0, 0, 0, 1.0f, 0);
    sphere.rgb[0] = sphere.rgb[1] = sphere.rgb[2] = 0.8f;
    unsigned char* img = image_alloc(cam.width, cam.height);
    char err[512];
    CHECK_EQ_INT(wg_render(g_r, &cam, NULL, 0, &sphere, 1, img, err, sizeof err), WC_OK);
    pinhole p;
    pinhole_of(&cam, &p);
    /* on-axis sphere: a circle of angular radius asin(r / d) */
    double radius_px = p.focal * tan(asin(1.0 / 5.0));
    check_sphere_silhouette(img, &cam, 100.0, 75.0, radius_px);
    /* the four corners are exactly the sky gradient */
    CHECK(is_sky(img, 200, 150, 0, 0, 1));
    CHECK(is_sky(img, 200, 150, 199, 0, 1));
    CHECK(is_sky(img, 200, 150, 0, 149, 1));
    CHECK(is_sky(img, 200, 150, 199, 149, 1));
    /* key light from the upper left: that side of the sphere is brighter than the lower right */
    int lit = 0, shadow = 0;
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            double o = 0.6 * radius_px / sqrt(2.0);
            lit += luma(px(img, 200, (int)(100 - o) + dx, (int)(75 - o) + dy));
            shadow += luma(px(img, 200, (int)(100 + o) + dx, (int)(75 + o) + dy));
        }
    printf("  sphere: lit side %d, shadow side %d (sum of 25 pixels' R+G+B)\n", lit, shadow);
    CHECK(lit > shadow + 25 * 60);
    /* a grey sphere stays grey: the lights are white */
    const unsigned char* c = px(img, 200, 100, 75);
    CHECK(abs(c[0] - c[1]) <= 1 && abs(c[1] - c[2]) <= 1);
    free(img);
}

/* Quad silhouette, plus the colour at its centre: base colour x one light factor. */
static void check_quad(const unsigned char* img, const wg_camera* cam, const float base[3]) {
    pinhole p;
    pinhole_of(cam, &p);
    double q0[3] = {QUAD_X0, QUAD_Y1, 0}, q1[3] = {QUAD_X1, QUAD_Y0, 0};
    double x0, y0, x1, y1;
    project(&p, q0, &x0, &y0); /* top left */
    project(&p, q1, &x1, &y1); /* bottom right */
    int w = cam->width, h = cam->height;
    int ym = (int)floor(0.5 * (y0 + y1)), xm = (int)floor(0.5 * (x0 + x1));
    CHECK(!is_sky(img, w, h, (int)floor(x0 + 1.5), ym, 6));
    CHECK(!is_sky(img, w, h, (int)floor(x1 - 1.5), ym, 6));
    CHECK(!is_sky(img, w, h, xm, (int)floor(y0 + 1.5), 6));
    CHECK(!is_sky(img, w, h, xm, (int)floor(y1 - 1.5), 6));
    CHECK(is_sky(img, w, h, (int)floor(x0 - 1.5), ym, 2));
    CHECK(is_sky(img, w, h, (int)floor(x1 + 1.5), ym, 2));
    CHECK(is_sky(img, w, h, xm, (int)floor(y0 - 1.5), 2));
    CHECK(is_sky(img, w, h, xm, (int)floor(y1 + 1.5), 2));
    /* every channel is base x the same light factor (flat quad, directional white lights) */
    const unsigned char* c = px(img, w, xm, ym);
    double light[3];
    for (int i = 0; i < 3; ++i) light[i] = c[i] / (255.0 * base[i]);
    for (int i = 0; i < 3; ++i) CHECK_NEAR(light[i], light[0], 2.0 / (255.0 * 0.2));
    CHECK(light[0] > 0.3 && light[0] < 1.3);
}

static void test_quad_front_and_back(void) {
    quad_store q;
    wg_camera cam = front_camera(200, 150);
    unsigned char* img = image_alloc(200, 150);
    unsigned char* img2 = image_alloc(200, 150);
    char err[512];
    for (int flipped = 0; flipped <= 1; ++flipped) {
        wg_mesh m = quad_mesh(&q, flipped, 0);
        CHECK_EQ_INT(wg_render(g_r, &cam, &m, 1, NULL, 0, img, err, sizeof err), WC_OK);
        /* front faces the camera when counter-clockwise: front_rgb, else back_rgb */
        check_quad(img, &cam, flipped ? m.back_rgb : m.front_rgb);
        pinhole p;
        pinhole_of(&cam, &p);
        double centre[3] = {0.5 * (QUAD_X0 + QUAD_X1), 0, 0}, x, y;
        project(&p, centre, &x, &y);
        const unsigned char* c = px(img, 200, (int)x, (int)y);
        if (flipped)
            CHECK(c[2] > c[0] + 60);
        else
            CHECK(c[0] > c[2] + 60);
        /* given normals (pointing to the front side) draw the same picture as computed ones */
        wg_mesh mn = quad_mesh(&q, flipped, 1);
        CHECK_EQ_INT(wg_render(g_r, &cam, &mn, 1, NULL, 0, img2, err, sizeof err), WC_OK);
        int maxdiff = 0;
        for (size_t i = 0; i < 4u * 200 * 150; ++i) {
            int d = abs((int)img[i] - (int)img2[i]);
            if (d > maxdiff) maxdiff = d;
        }
        CHECK(maxdiff <= 1);
    }
    free(img);
    free(img2);
}

static void test_capsule_silhouette(void) {
    wg_camera cam = front_camera(200, 150);
    /* local Y onto world X: rotation of -90 degrees about Z */
    wg_shape cap = shape_at(WG_SHAPE_CAPSULE, 0, 0, 0, 0.3f, 0.5f);
    const float rot[16] = {0, -1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    memcpy(cap.transform, rot, sizeof rot);
    unsigned char* img = image_alloc(200, 150);
    char err[512];
    CHECK_EQ_INT(wg_render(g_r, &cam, NULL, 0, &cap, 1, img, err, sizeof err), WC_OK);
    pinhole p;
    pinhole_of(&cam, &p);
    /* tip: the end sphere (centre 0.5 m off the axis) seen at atan(0.5/5) + asin(r/|c|) */
    double ang = atan(0.5 / 5.0) + asin(0.3 / sqrt(0.25 + 25.0));
    double tip_r = 100.0 + p.focal * tan(ang), tip_l = 100.0 - p.focal * tan(ang);
    CHECK(!is_sky(img, 200, 150, (int)floor(tip_r - 1.5), 75, 6));
    CHECK(is_sky(img, 200, 150, (int)floor(tip_r + 1.5), 75, 2));
    CHECK(!is_sky(img, 200, 150, (int)floor(tip_l + 1.5), 75, 6));
    CHECK(is_sky(img, 200, 150, (int)floor(tip_l - 1.5), 75, 2));
    /* middle: the cylinder's outline at asin(r / d) above and below */
    double half = p.focal * tan(asin(0.3 / 5.0));
    CHECK(!is_sky(img, 200, 150, 100, (int)floor(75 - half + 1.5), 6));
    CHECK(is_sky(img, 200, 150, 100, (int)floor(75 - half - 1.5), 2));
    CHECK(!is_sky(img, 200, 150, 100, (int)floor(75 + half - 1.5), 6));
    CHECK(is_sky(img, 200, 150, 100, (int)floor(75 + half + 1.5), 2));
    free(img);
}

/* A plane alone: a 1 m half-size square around its origin with 0.2 m cells (documented rule:
 * largest 1/2/5 x 10^k <= half / 5). Each pixel's ray hits the plane at a known point. */
static void test_plane_checker(void) {
    wg_camera cam = {{0.3f, 1.6f, 2.4f}, {0.25f, -0.3f, 0.1f}, {0, 1, 0}, 50.0f, 240, 180};
    const float ox = 0.25f, oy = -0.3f, oz = 0.1f;
    wg_shape plane = shape_at(WG_SHAPE_PLANE, ox, oy, oz, 0, 0);
    unsigned char* img = image_alloc(240, 180);
    char err[512];
    CHECK_EQ_INT(wg_render(g_r, &cam, NULL, 0, &plane, 1, img, err, sizeof err), WC_OK);
    pinhole p;
    pinhole_of(&cam, &p);
    const double half = 1.0, cell = 0.2, margin = 0.15 * cell;
    int even[3] = {-1, -1, -1}, n_even = 0, n_odd = 0, n_sky = 0, bad = 0;
    int odd_sum[3] = {0, 0, 0}, even_sum[3] = {0, 0, 0};
    for (int j = 0; j < 180; ++j)
        for (int i = 0; i < 240; ++i) {
            double d[3];
            pixel_ray(&p, i, j, d);
            double t = (oy - p.eye[1]) / d[1];
            double lx = p.eye[0] + t * d[0] - ox, lz = p.eye[2] + t * d[2] - oz;
            if (t <= 0 || fabs(lx) > half + 0.05 || fabs(lz) > half + 0.05) {
                if (t <= 0 || fabs(lx) > half + 0.1 || fabs(lz) > half + 0.1) {
                    n_sky += 1;
                    bad += !is_sky(img, 240, 180, i, j, 2);
                }
                continue;
            }
            if (fabs(lx) > half - 0.05 || fabs(lz) > half - 0.05) continue;
            double fx = lx / cell - floor(lx / cell), fz = lz / cell - floor(lz / cell);
            if (fx * cell < margin || (1 - fx) * cell < margin || fz * cell < margin ||
                (1 - fz) * cell < margin)
                continue;
            int odd = ((long)floor(lx / cell) + (long)floor(lz / cell)) & 1;
            const unsigned char* c = px(img, 240, i, j);
            if (!odd) {
                if (even[0] < 0)
                    for (int k = 0; k < 3; ++k) even[k] = c[k];
                for (int k = 0; k < 3; ++k) bad += abs(c[k] - even[k]) > 1;
                for (int k = 0; k < 3; ++k) even_sum[k] += c[k];
                ++n_even;
            } else {
                for (int k = 0; k < 3; ++k) odd_sum[k] += c[k];
                ++n_odd;
            }
        }
    printf("  plane: %d even-cell, %d odd-cell, %d sky pixels checked\n", n_even, n_odd, n_sky);
    CHECK(n_even > 500 && n_odd > 500 && n_sky > 500);
    CHECK_EQ_INT(bad, 0);
    for (int k = 0; k < 3; ++k)
        CHECK_NEAR((double)odd_sum[k] / n_odd, 0.8 * even_sum[k] / n_even, 1.5);
    free(img);
}

/* The projected corners of any framed box stay inside the picture. */
static void test_auto_framing_math(void) {
    unsigned seed = 12345u;
    int outside = 0;
    double min_margin = 1e9;
    for (int trial = 0; trial < 200; ++trial) {
        float v[12];
        for (int i = 0; i < 12; ++i) {
            seed = seed * 1664525u + 1013904223u;
            v[i] = (float)((seed >> 8) / 16777216.0 * 2.0 - 1.0);
        }
        float bmin[3], bmax[3];
        for (int i = 0; i < 3; ++i) {
            bmin[i] = 10.0f * v[i];
            bmax[i] = bmin[i] + (trial % 7 == 0 ? 0.0f : 3.0f * (v[3 + i] + 1.0f));
        }
        wg_camera cam = {{0}, {0}, {v[6], v[7] + 1.5f, v[8]}, 20.0f + 60.0f * (v[9] + 1.0f),
                         64 + (int)(200 * (v[10] + 1)), 64 + (int)(200 * (v[11] + 1))};
        char err[256];
        CHECK_EQ_INT(wg_camera_frame_auto(&cam, bmin, bmax, err, sizeof err), WC_OK);
        pinhole p;
        pinhole_of(&cam, &p);
        for (int c = 0; c < 8; ++c) {
            double q[3] = {c & 1 ? bmax[0] : bmin[0], c & 2 ? bmax[1] : bmin[1],
                           c & 4 ? bmax[2] : bmin[2]};
            double x, y;
            project(&p, q, &x, &y);
            if (!(x > 0 && x < cam.width && y > 0 && y < cam.height)) ++outside;
            double m = fmin(fmin(x, cam.width - x), fmin(y, cam.height - y));
            if (m < min_margin) min_margin = m;
        }
    }
    CHECK_EQ_INT(outside, 0);
    printf("  auto framing: smallest margin %.1f px over 200 boxes\n", min_margin);
}

/* eye == target: a box-shaped mesh is framed with sky all around it. */
static void test_auto_framing_render(void) {
    float pos[24];
    for (int c = 0; c < 8; ++c) {
        pos[3 * c + 0] = 3.0f + (c & 1 ? 0.8f : 0.0f);
        pos[3 * c + 1] = -2.0f + (c & 2 ? 2.5f : 0.0f);
        pos[3 * c + 2] = 7.0f + (c & 4 ? 0.3f : 0.0f);
    }
    const int tris[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                          2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    wg_mesh box = {pos, NULL, 8, tris, 12, {0.7f, 0.6f, 0.3f}, {0.3f, 0.3f, 0.6f}};
    wg_camera cam = {{1, 1, 1}, {1, 1, 1}, {0, 1, 0}, 35.0f, 160, 100};
    unsigned char* img = image_alloc(160, 100);
    char err[512];
    CHECK_EQ_INT(wg_render(g_r, &cam, &box, 1, NULL, 0, img, err, sizeof err), WC_OK);
    int border_sky = 0, border = 0, inside = 0;
    for (int y = 0; y < 100; ++y)
        for (int x = 0; x < 160; ++x) {
            int edge = x < 2 || y < 2 || x >= 158 || y >= 98;
            int sky = is_sky(img, 160, 100, x, y, 2);
            if (edge) {
                ++border;
                border_sky += sky;
            } else {
                inside += !sky;
            }
        }
    CHECK_EQ_INT(border_sky, border);
    CHECK(inside > 160 * 100 / 20);
    free(img);
}

static void test_png_round_trip(void) {
    quad_store q;
    wg_camera cam = front_camera(64, 48);
    wg_shape sphere = shape_at(WG_SHAPE_SPHERE, 0.3f, 0, 0, 1.0f, 0);
    wg_mesh m = quad_mesh(&q, 0, 0);
    unsigned char* img = image_alloc(64, 48);
    char err[512];
    CHECK_EQ_INT(wg_render(g_r, &cam, &m, 1, &sphere, 1, img, err, sizeof err), WC_OK);
    const char* path = ts_tmp_path("render_round_trip.png");
    CHECK_EQ_INT(wg_png_write(path, img, 64, 48, err, sizeof err), WC_OK);
    png_image pi;
    memset(&pi, 0, sizeof pi);
    pi.version = PNG_IMAGE_VERSION;
    CHECK(png_image_begin_read_from_file(&pi, path) != 0);
    CHECK_EQ_INT(pi.width, 64);
    CHECK_EQ_INT(pi.height, 48);
    CHECK_EQ_INT(PNG_IMAGE_SAMPLE_CHANNELS(pi.format), 3); /* stored as RGB */
    pi.format = PNG_FORMAT_RGB;
    unsigned char* back = (unsigned char*)malloc(3 * 64 * 48);
    CHECK(png_image_finish_read(&pi, NULL, back, 0, NULL) != 0);
    int diff = 0;
    for (int i = 0; i < 64 * 48; ++i)
        for (int k = 0; k < 3; ++k) diff += back[3 * i + k] != img[4 * i + k];
    CHECK_EQ_INT(diff, 0);
    png_image_free(&pi);
    free(back);
    free(img);
}

/* Sample count: with and without MSAA the analytic silhouette holds; resizing in between. */
static void test_samples_and_resize(void) {
    char err[512];
    wg_renderer_desc d1 = {1};
    wg_renderer* r1 = NULL;
    CHECK_EQ_INT(wg_renderer_create(g_ctx, &d1, &r1, err, sizeof err), WC_OK);
    wg_shape sphere = shape_at(WG_SHAPE_SPHERE, 0, 0, 0, 1.0f, 0);
    unsigned char* a = image_alloc(200, 150);
    unsigned char* b = image_alloc(200, 150);
    unsigned char* small = image_alloc(50, 40);
    wg_camera cam = front_camera(200, 150), cam_small = front_camera(50, 40);
    CHECK_EQ_INT(wg_render(r1, &cam, NULL, 0, &sphere, 1, a, err, sizeof err), WC_OK);
    CHECK_EQ_INT(wg_renderer_samples(r1), 1);
    pinhole p;
    pinhole_of(&cam, &p);
    check_sphere_silhouette(a, &cam, 100.0, 75.0, p.focal * tan(asin(0.2)));
    CHECK_EQ_INT(wg_render(r1, &cam_small, NULL, 0, &sphere, 1, small, err, sizeof err), WC_OK);
    CHECK_EQ_INT(wg_render(r1, &cam, NULL, 0, &sphere, 1, b, err, sizeof err), WC_OK);
    CHECK(memcmp(a, b, 4 * 200 * 150) == 0); /* same picture after a resize and back */
    CHECK_EQ_INT(wg_render(g_r, &cam, NULL, 0, &sphere, 1, b, err, sizeof err), WC_OK);
    printf("  MSAA samples used by default: %d\n", wg_renderer_samples(g_r));
    CHECK(wg_renderer_samples(g_r) >= 1);
    wg_renderer_destroy(r1);
    free(a);
    free(b);
    free(small);
}
int main(void) {
    if (!rs_open(capture_log, &g_ctx, &g_r)) return 1;
    RUN_TEST(test_context_info);
    RUN_TEST(test_sphere_sky_and_light);
    RUN_TEST(test_quad_front_and_back);
    RUN_TEST(test_capsule_silhouette);
    RUN_TEST(test_plane_checker);
    RUN_TEST(test_auto_framing_math);
    RUN_TEST(test_auto_framing_render);
    RUN_TEST(test_png_round_trip);
    RUN_TEST(test_samples_and_resize);
    wg_renderer_destroy(g_r);
    wg_gl_context_destroy(g_ctx);
    return TEST_SUMMARY();
}
