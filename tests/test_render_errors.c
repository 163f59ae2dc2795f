/* gpu/ renderer and context failures and modes: every bad input gives its status and a message
 * naming it with the picture untouched; PNG paths that cannot be written; WEFT_EGL_DEVICE
 * choices (bogus, out of range, software, surfaceless, an index); the host-context mode leaving
 * the host's GL state and EGL context as it found them; the per-context allocator. */
#define _POSIX_C_SOURCE 200809L   /* setenv for WEFT_EGL_DEVICE */
#include <EGL/egl.h>
#include <GL/glew.h>

#include "check.h"
#include "png_write.h"
#include "render_support.h"
#include "test_support.h"

static wg_gl_context* g_ctx;     /* headless, created in main */
static wg_renderer* g_r;         /* default samples */

static int untouched(const unsigned char* img, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (img[i] != 0xAB) return 0;
    return 1;
}

#define EXPECT_RENDER_ERROR(cam, meshes, nm, shapes, ns, status, words)                          \
    do {                                                                                       \
        char err_[512] = "";                                                                   \
        unsigned char* img_ = image_alloc(16, 16);                                             \
        wc_status st_ = wg_render(g_r, cam, meshes, nm, shapes, ns, img_, err_, sizeof err_); \
        CHECK_EQ_INT(st_, status);                                                             \
        CHECK(strstr(err_, words) != NULL);                                                    \
        CHECK(untouched(img_, 4 * 16 * 16));                                                   \
        if (!strstr(err_, words)) fprintf(stderr, "  message was: %s\n", err_);                \
        free(img_);                                                                            \
    } while (0)

static void test_render_errors(void) {
    quad_store q;
    wg_camera ok = front_camera(16, 16), c;
    wg_shape sphere = shape_at(WG_SHAPE_SPHERE, 0, 0, 0, 1.0f, 0);
    c = ok; c.width = 0;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_INVALID_ARGUMENT, "0 x 16");
    c = ok; c.height = -3;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_INVALID_ARGUMENT, "1..8192");
    c = ok; c.width = 8193;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_INVALID_ARGUMENT, "8193");
    c = ok; c.eye[1] = NAN;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_NONFINITE, "eye");
    c = ok; c.target[2] = INFINITY;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_NONFINITE, "target");
    c = ok; c.fov_y_deg = NAN;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_NONFINITE, "fov_y_deg");
    c = ok; c.fov_y_deg = 180.0f;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_INVALID_ARGUMENT, "(0, 180)");
    c = ok; c.up[0] = 0; c.up[1] = 0; c.up[2] = 2;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_INVALID_ARGUMENT, "parallel");
    c = ok; c.up[1] = 0;
    EXPECT_RENDER_ERROR(&c, NULL, 0, &sphere, 1, WC_ERROR_INVALID_ARGUMENT, "zero vector");

    wg_mesh m = quad_mesh(&q, 0, 0);
    q.tris[4] = 4;
    EXPECT_RENDER_ERROR(&ok, &m, 1, NULL, 0, WC_ERROR_OUT_OF_RANGE, "meshes[0].triangles[4] = 4");
    m = quad_mesh(&q, 0, 0);
    q.pos[7] = NAN;
    EXPECT_RENDER_ERROR(&ok, &m, 1, NULL, 0, WC_ERROR_NONFINITE, "meshes[0].positions[7]");
    m = quad_mesh(&q, 0, 1);
    q.nrm[2] = INFINITY;
    EXPECT_RENDER_ERROR(&ok, &m, 1, NULL, 0, WC_ERROR_NONFINITE, "normals");
    m = quad_mesh(&q, 0, 0);
    m.n_triangles = -1;
    EXPECT_RENDER_ERROR(&ok, &m, 1, NULL, 0, WC_ERROR_INVALID_ARGUMENT, "n_triangles = -1");
    m = quad_mesh(&q, 0, 0);
    m.positions = NULL;
    EXPECT_RENDER_ERROR(&ok, &m, 1, NULL, 0, WC_ERROR_INVALID_ARGUMENT, "positions is NULL");
    EXPECT_RENDER_ERROR(&ok, NULL, 2, NULL, 0, WC_ERROR_INVALID_ARGUMENT,
                        "n_meshes = 2 with meshes NULL");
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &sphere, -1, WC_ERROR_INVALID_ARGUMENT, "n_shapes = -1");

    wg_shape s = sphere;
    s.radius = 0;
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &s, 1, WC_ERROR_INVALID_ARGUMENT, "shapes[0].radius");
    s = sphere;
    s.type = (wg_shape_type)7;
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &s, 1, WC_ERROR_INVALID_ARGUMENT, "shapes[0].type = 7");
    s = sphere;
    s.transform[5] = 0;
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &s, 1, WC_ERROR_INVALID_ARGUMENT, "singular");
    s = sphere;
    s.transform[3] = 0.5f;
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &s, 1, WC_ERROR_INVALID_ARGUMENT, "last row");
    s = sphere;
    s.transform[13] = NAN;
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &s, 1, WC_ERROR_NONFINITE, "shapes[0]");
    s = shape_at(WG_SHAPE_CAPSULE, 0, 0, 0, 0.2f, -1.0f);
    EXPECT_RENDER_ERROR(&ok, NULL, 0, &s, 1, WC_ERROR_INVALID_ARGUMENT, "half_height");

    char err[256];
    CHECK_EQ_INT(wg_render(g_r, &ok, NULL, 0, &sphere, 1, NULL, err, sizeof err),
                 WC_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err, "rgba_out") != NULL);
    CHECK_EQ_INT(wg_render(NULL, &ok, NULL, 0, &sphere, 1, NULL, err, sizeof err),
                 WC_ERROR_INVALID_ARGUMENT);
    /* after all that, the renderer still works */
    unsigned char* img = image_alloc(16, 16);
    CHECK_EQ_INT(wg_render(g_r, &ok, NULL, 0, &sphere, 1, img, err, sizeof err), WC_OK);
    free(img);
    float bmin[3] = {0, 0, 0}, bmax[3] = {1, -1, 1};
    c = ok;
    CHECK_EQ_INT(wg_camera_frame_auto(&c, bmin, bmax, err, sizeof err),
                 WC_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err, "min > max") != NULL);
    wg_renderer_desc bad = {-1};
    wg_renderer* r = NULL;
    CHECK_EQ_INT(wg_renderer_create(g_ctx, &bad, &r, err, sizeof err), WC_ERROR_INVALID_ARGUMENT);
    CHECK(r == NULL && strstr(err, "samples") != NULL);
}

static void test_png_errors(void) {
    unsigned char rgba[4 * 4 * 4] = {0};
    char err[512];
    const char* path = "/nonexistent-weft-dir/out.png";
    CHECK_EQ_INT(wg_png_write(path, rgba, 4, 4, err, sizeof err), WC_ERROR_IO);
    CHECK(strstr(err, path) != NULL && strstr(err, "No such file") != NULL);
    /* a directory is not a file */
    CHECK_EQ_INT(wg_png_write(WEFT_TEST_TMPDIR, rgba, 4, 4, err, sizeof err), WC_ERROR_IO);
    CHECK(strstr(err, WEFT_TEST_TMPDIR) != NULL);
    CHECK_EQ_INT(wg_png_write(ts_tmp_path("never.png"), rgba, 0, 4, err, sizeof err),
                 WC_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(err, "0 x 4") != NULL);
    CHECK_EQ_INT(wg_png_write(ts_tmp_path("never.png"), NULL, 4, 4, err, sizeof err),
                 WC_ERROR_INVALID_ARGUMENT);
    FILE* f = fopen(ts_tmp_path("never.png"), "rb");
    CHECK(f == NULL);
    if (f) fclose(f);
}

static void test_device_choice(void) {
    char err[512];
    wg_gl_context* ctx = NULL;
    wg_gl_context_desc desc;
    memset(&desc, 0, sizeof desc);
    setenv("WEFT_EGL_DEVICE", "bogus", 1);
    CHECK_EQ_INT(wg_gl_context_create(&desc, &ctx, err, sizeof err), WC_ERROR_GPU);
    CHECK(ctx == NULL);
    CHECK(strstr(err, "WEFT_EGL_DEVICE='bogus'") != NULL && strstr(err, "surfaceless") != NULL);
    printf("  WEFT_EGL_DEVICE=bogus: %s\n", err);
    setenv("WEFT_EGL_DEVICE", "99", 1);
    CHECK_EQ_INT(wg_gl_context_create(&desc, &ctx, err, sizeof err), WC_ERROR_GPU);
    CHECK(strstr(err, "WEFT_EGL_DEVICE=99") != NULL);
    unsetenv("WEFT_EGL_DEVICE");
    /* the desc's override wins over the environment; each named way either works and renders or
     * says why not */
    const char* picks[3] = {"software", "surfaceless", "0"};
    for (int k = 0; k < 3; ++k) {
        desc.device = picks[k];
        wc_status st = wg_gl_context_create(&desc, &ctx, err, sizeof err);
        printf("  device '%s': %s\n", picks[k],
               st == WC_OK ? wg_gl_context_description(ctx) : err);
        CHECK(st == WC_OK || (st == WC_ERROR_GPU && err[0] != '\0'));
        if (st != WC_OK) continue;
        wg_renderer* r = NULL;
        CHECK_EQ_INT(wg_renderer_create(ctx, NULL, &r, err, sizeof err), WC_OK);
        wg_camera cam = front_camera(40, 30);
        wg_shape sphere = shape_at(WG_SHAPE_SPHERE, 0, 0, 0, 1.0f, 0);
        unsigned char* img = image_alloc(40, 30);
        CHECK_EQ_INT(wg_render(r, &cam, NULL, 0, &sphere, 1, img, err, sizeof err), WC_OK);
        CHECK(!is_sky(img, 40, 30, 20, 15, 6) && is_sky(img, 40, 30, 0, 0, 1));
        free(img);
        wg_renderer_destroy(r);
        wg_gl_context_destroy(ctx);
    }
}

/* The host's own context: rendering inside it leaves its GL state as it was, gives the same
 * picture as the headless path, and a headless render meanwhile hands the host's EGL context
 * back. */
static void test_host_context(void) {
    quad_store q;
    char err[512];
    wg_camera cam = front_camera(120, 90);
    wg_shape sphere = shape_at(WG_SHAPE_SPHERE, 0, 0, 0, 1.0f, 0);
    wg_mesh m = quad_mesh(&q, 0, 0);
    unsigned char* ref = image_alloc(120, 90);
    unsigned char* img = image_alloc(120, 90);
    CHECK_EQ_INT(wg_render(g_r, &cam, &m, 1, &sphere, 1, ref, err, sizeof err), WC_OK);

    /* the "host": g_ctx made current by hand, with state of its own */
    CHECK_EQ_INT(wg_gl_begin(g_ctx, err, sizeof err), WC_OK);
    EGLContext host_egl = eglGetCurrentContext();
    GLuint host_fbo = 0, host_rbo = 0, host_vao = 0;
    glGenRenderbuffers(1, &host_rbo);
    glBindRenderbuffer(GL_RENDERBUFFER, host_rbo);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 8, 8);
    glGenFramebuffers(1, &host_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, host_fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, host_rbo);
    glGenVertexArrays(1, &host_vao);
    glBindVertexArray(host_vao);
    glUseProgram(0);
    glViewport(3, 4, 50, 60);
    glEnable(GL_SCISSOR_TEST);
    glEnable(GL_BLEND);
    glEnable(GL_CULL_FACE);
    glDisable(GL_DEPTH_TEST);
    glClearColor(0.1f, 0.2f, 0.3f, 0.4f);
    glFrontFace(GL_CW);
    glDepthMask(GL_FALSE);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);

    wg_gl_context_desc hd;
    memset(&hd, 0, sizeof hd);
    hd.host_current = 1;
    wg_gl_context* host = NULL;
    CHECK_EQ_INT(wg_gl_context_create(&hd, &host, err, sizeof err), WC_OK);
    CHECK(wg_gl_context_is_host(host));
    CHECK(strstr(wg_gl_context_description(host), "host context") != NULL);
    wg_renderer* hr = NULL;
    CHECK_EQ_INT(wg_renderer_create(host, NULL, &hr, err, sizeof err), WC_OK);
    CHECK_EQ_INT(wg_render(hr, &cam, &m, 1, &sphere, 1, img, err, sizeof err), WC_OK);
    CHECK(memcmp(img, ref, 4 * 120 * 90) == 0);

    GLint v[4], i;
    GLboolean bmask;
    GLfloat cc[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &i);
    CHECK_EQ_INT(i, host_fbo);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &i);
    CHECK_EQ_INT(i, host_fbo);
    glGetIntegerv(GL_RENDERBUFFER_BINDING, &i);
    CHECK_EQ_INT(i, host_rbo);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &i);
    CHECK_EQ_INT(i, host_vao);
    glGetIntegerv(GL_CURRENT_PROGRAM, &i);
    CHECK_EQ_INT(i, 0);
    glGetIntegerv(GL_VIEWPORT, v);
    CHECK(v[0] == 3 && v[1] == 4 && v[2] == 50 && v[3] == 60);
    CHECK(glIsEnabled(GL_SCISSOR_TEST) && glIsEnabled(GL_BLEND) && glIsEnabled(GL_CULL_FACE));
    CHECK(!glIsEnabled(GL_DEPTH_TEST));
    glGetFloatv(GL_COLOR_CLEAR_VALUE, cc);
    CHECK(cc[0] == 0.1f && cc[1] == 0.2f && cc[2] == 0.3f && cc[3] == 0.4f);
    glGetIntegerv(GL_FRONT_FACE, &i);
    CHECK_EQ_INT(i, GL_CW);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &bmask);
    CHECK(bmask == GL_FALSE);
    glGetIntegerv(GL_PACK_ALIGNMENT, &i);
    CHECK_EQ_INT(i, 1);
    CHECK_EQ_INT(glGetError(), GL_NO_ERROR);

    /* a headless context rendering meanwhile gives the thread its EGL context back */
    wg_gl_context_desc other;
    memset(&other, 0, sizeof other);
    wg_gl_context* own = NULL;
    wg_renderer* own_r = NULL;
    CHECK_EQ_INT(wg_gl_context_create(&other, &own, err, sizeof err), WC_OK);
    CHECK(eglGetCurrentContext() == host_egl);
    CHECK_EQ_INT(wg_renderer_create(own, NULL, &own_r, err, sizeof err), WC_OK);
    CHECK_EQ_INT(wg_render(own_r, &cam, &m, 1, &sphere, 1, img, err, sizeof err), WC_OK);
    CHECK(eglGetCurrentContext() == host_egl);
    CHECK(memcmp(img, ref, 4 * 120 * 90) == 0);
    wg_renderer_destroy(own_r);
    wg_gl_context_destroy(own);
    CHECK(eglGetCurrentContext() == host_egl);

    wg_renderer_destroy(hr);
    wg_gl_context_destroy(host);
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteVertexArrays(1, &host_vao);
    glDeleteFramebuffers(1, &host_fbo);
    glDeleteRenderbuffers(1, &host_rbo);
    wg_gl_end(g_ctx);
    CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT);

    /* no host context current: a clear GPU error */
    CHECK_EQ_INT(wg_gl_context_create(&hd, &host, err, sizeof err), WC_ERROR_GPU);
    CHECK(host == NULL && strstr(err, "no OpenGL context is current") != NULL);
    free(ref);
    free(img);
}

/* Everything gpu/ allocates goes through the context's allocator and comes back. */
typedef struct counting {
    long live, total;
} counting;

static void* count_alloc(size_t n, void* user) {
    counting* c = (counting*)user;
    ++c->live;
    ++c->total;
    return malloc(n);
}

static void count_free(void* p, void* user) {
    --((counting*)user)->live;
    free(p);
}

static void test_allocator(void) {
    quad_store q;
    counting c = {0, 0};
    wg_gl_context_desc d;
    memset(&d, 0, sizeof d);
    d.allocator.alloc = count_alloc;
    d.allocator.free = count_free;
    d.allocator.user = &c;
    wg_gl_context* ctx = NULL;
    wg_renderer* r = NULL;
    char err[512];
    CHECK_EQ_INT(wg_gl_context_create(&d, &ctx, err, sizeof err), WC_OK);
    CHECK_EQ_INT(wg_renderer_create(ctx, NULL, &r, err, sizeof err), WC_OK);
    wg_camera cam = front_camera(64, 64);
    wg_mesh m = quad_mesh(&q, 0, 0);
    unsigned char* img = image_alloc(64, 64);
    CHECK_EQ_INT(wg_render(r, &cam, &m, 1, NULL, 0, img, err, sizeof err), WC_OK);
    free(img);
    wg_renderer_destroy(r);
    wg_gl_context_destroy(ctx);
    CHECK(c.total >= 3);
    CHECK_EQ_INT(c.live, 0);
    d.allocator.free = NULL;
    CHECK_EQ_INT(wg_gl_context_create(&d, &ctx, err, sizeof err), WC_ERROR_INVALID_ARGUMENT);
}
int main(void) {
    if (!rs_open(NULL, &g_ctx, &g_r)) return 1;
    RUN_TEST(test_render_errors);
    RUN_TEST(test_png_errors);
    RUN_TEST(test_device_choice);
    RUN_TEST(test_host_context);
    RUN_TEST(test_allocator);
    wg_renderer_destroy(g_r);
    wg_gl_context_destroy(g_ctx);
    return TEST_SUMMARY();
}
