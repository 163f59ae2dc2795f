/* weft_render through the public API (real EGL: llvmpipe without a GPU): a horizontal sheet over
 * a sphere seen from above shows the cloth's front colour at the centre and sky at the corners;
 * from below, the back colour; the PNG on disk is a PNG of the asked size; every bad argument is
 * refused with a status and a message, the cloth untouched; a bad EGL device is a GPU error. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>

#include "api_grid.h"
#include "check.h"

static weft_context* make_ctx(void) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    weft_context* ctx = NULL;
    CHECK_EQ_INT(weft_context_create(WEFT_ABI, &cd, &ctx), WEFT_OK);
    return ctx;
}

static weft_cloth make_cloth(weft_context* ctx, ag_mesh* m) {
    ag_grid(m, 16, 1.0, 0.5, 0, 0);
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(m);
    weft_collider_def sph = weft_default_collider_def();
    sph.type = WEFT_COLLIDER_SPHERE;
    sph.radius = 0.2;
    def.colliders = &sph;
    def.n_colliders = 1;
    weft_cloth cloth = {0};
    CHECK_EQ_INT(weft_cloth_create(ctx, &def, &cloth), WEFT_OK);
    return cloth;
}

/* Is pixel (x, y) close to the colour (r, g, b) up to a brightness factor (shading)? Compare hue
 * ratios: r/g and b/g of the pixel vs the tint. */
static int hue_like(const unsigned char* px, double r, double g, double b) {
    double pr = px[0] + 1.0, pg = px[1] + 1.0, pb = px[2] + 1.0;
    return fabs(pr / pg - r / g) < 0.35 * (r / g) && fabs(pb / pg - b / g) < 0.35 * (b / g);
}

int main(void) {
    weft_context* ctx = make_ctx();
    ag_mesh m;
    weft_cloth cloth = make_cloth(ctx, &m);
    const int W = 160, H = 120;
    unsigned char* img = malloc((size_t)W * H * 4);

    /* from above: the sheet's front (counter-clockwise from +Y) fills the centre */
    weft_render_def rd = weft_default_render_def();
    rd.width = W;
    rd.height = H;
    rd.eye[1] = 3.0f;
    rd.up[1] = 0.0f;
    rd.up[2] = -1.0f;
    rd.fov_y_deg = 30.0f;
    rd.rgba = img;
    weft_status st = weft_render(ctx, cloth, &rd);
    CHECK_EQ_INT(st, WEFT_OK);
    if (st != WEFT_OK) fprintf(stderr, "%s\n", weft_context_last_error(ctx));
    const unsigned char* c = img + 4 * ((size_t)(H / 2) * W + W / 2);
    CHECK(hue_like(c, 0.80, 0.28, 0.22));          /* front: red */
    const unsigned char* corner = img;              /* sky: bluish, brighter than the cloth */
    CHECK(corner[2] > corner[0] && corner[2] > 150);
    CHECK_EQ_INT(img[3], 255);

    /* from below: the back (yellow); the sphere (grey) hides part of it, not the centre column's
     * far edge */
    rd.eye[1] = -3.0f;
    rd.up[2] = 1.0f;
    CHECK_EQ_INT(weft_render(ctx, cloth, &rd), WEFT_OK);
    int yellow = 0, grey = 0;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const unsigned char* p = img + 4 * ((size_t)y * W + x);
            yellow += hue_like(p, 0.95, 0.78, 0.45);
            grey += abs(p[0] - p[1]) < 12 && abs(p[1] - p[2]) < 14 && p[0] < 200 && p[0] > 20;
        }
    CHECK(yellow > W * H / 10);
    CHECK(grey > 200);                               /* the sphere is drawn */
    rd.draw_colliders = 0;
    CHECK_EQ_INT(weft_render(ctx, cloth, &rd), WEFT_OK);
    int grey2 = 0;
    for (int i = 0; i < W * H; ++i) {
        const unsigned char* p = img + 4 * (size_t)i;
        grey2 += abs(p[0] - p[1]) < 12 && abs(p[1] - p[2]) < 14 && p[0] < 200 && p[0] > 20;
    }
    CHECK(grey2 < grey / 4);
    rd.draw_colliders = 1;

    /* PNG on disk, auto framing */
    char path[512];
    snprintf(path, sizeof path, "%s/api_render.png", WEFT_TEST_TMPDIR);
    remove(path);
    weft_render_def auto_rd = weft_default_render_def();
    auto_rd.width = 64;
    auto_rd.height = 48;
    auto_rd.png_path = path;
    CHECK_EQ_INT(weft_render(ctx, cloth, &auto_rd), WEFT_OK);
    FILE* f = fopen(path, "rb");
    unsigned char hdr[24] = {0};
    CHECK(f && fread(hdr, 1, 24, f) == 24);
    if (f) fclose(f);
    CHECK(memcmp(hdr, "\x89PNG\r\n\x1a\n", 8) == 0);
    CHECK_EQ_INT((hdr[16] << 24) | (hdr[17] << 16) | (hdr[18] << 8) | hdr[19], 64);   /* IHDR width */
    CHECK_EQ_INT((hdr[20] << 24) | (hdr[21] << 16) | (hdr[22] << 8) | hdr[23], 48);

    /* bad calls: status, message, cloth unchanged */
    weft_cloth_info info;
    CHECK_EQ_INT(weft_cloth_get_info(ctx, cloth, &info), WEFT_OK);
    unsigned char* before = malloc(info.snapshot_size);
    unsigned char* after = malloc(info.snapshot_size);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, before, info.snapshot_size), WEFT_OK);
    struct { const char* what; weft_render_def d; weft_status want; const char* msg; } bad[12];
    int nb = 0;
    weft_render_def d0 = weft_default_render_def();
    d0.width = W;
    d0.height = H;
    d0.rgba = img;
    bad[nb].what = "no cookie"; bad[nb].d = d0; bad[nb].d.internal_cookie = 0;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "weft_default_render_def";
    bad[nb].what = "width 0"; bad[nb].d = d0; bad[nb].d.width = 0;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "width";
    bad[nb].what = "height 9000"; bad[nb].d = d0; bad[nb].d.height = 9000;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "height";
    bad[nb].what = "NaN eye"; bad[nb].d = d0; bad[nb].d.eye[0] = NAN;
    bad[nb].want = WEFT_ERROR_NONFINITE; bad[nb++].msg = "eye";
    bad[nb].what = "fov 180"; bad[nb].d = d0; bad[nb].d.fov_y_deg = 180.0f;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "fov_y_deg";
    bad[nb].what = "no output"; bad[nb].d = d0; bad[nb].d.rgba = NULL;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "nothing to write";
    bad[nb].what = "draw_colliders 2"; bad[nb].d = d0; bad[nb].d.draw_colliders = 2;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "draw_colliders";
    bad[nb].what = "up parallel to view"; bad[nb].d = d0; bad[nb].d.eye[1] = 2.0f;
    bad[nb].want = WEFT_ERROR_INVALID_ARGUMENT; bad[nb++].msg = "up";
    bad[nb].what = "unwritable PNG"; bad[nb].d = d0; bad[nb].d.png_path = "/nonexistent-dir/x.png";
    bad[nb].want = WEFT_ERROR_IO; bad[nb++].msg = "/nonexistent-dir/x.png";
    for (int i = 0; i < nb; ++i) {
        st = weft_render(ctx, cloth, &bad[i].d);
        CHECK_EQ_INT(st, bad[i].want);
        const char* e = weft_context_last_error(ctx);
        if (!strstr(e, bad[i].msg)) fprintf(stderr, "case '%s': message '%s' lacks '%s'\n", bad[i].what, e, bad[i].msg);
        CHECK(strstr(e, bad[i].msg) != NULL);
    }
    CHECK_EQ_INT(weft_render(ctx, cloth, NULL), WEFT_ERROR_INVALID_ARGUMENT);
    weft_cloth forged = cloth;
    forged.id ^= 1u << 20;
    CHECK_EQ_INT(weft_render(ctx, forged, &d0), WEFT_ERROR_INVALID_HANDLE);
    CHECK_EQ_INT(weft_render(NULL, cloth, &d0), WEFT_ERROR_INVALID_ARGUMENT);
    CHECK_EQ_INT(weft_cloth_save(ctx, cloth, after, info.snapshot_size), WEFT_OK);
    CHECK(memcmp(before, after, info.snapshot_size) == 0);

    /* a second context with a bogus EGL device: a GPU error naming it; the first context, which
     * already has its GL context, keeps rendering */
    setenv("WEFT_EGL_DEVICE", "bogus-device", 1);
    weft_context* ctx2 = make_ctx();
    ag_mesh m2;
    weft_cloth cloth2 = make_cloth(ctx2, &m2);
    CHECK_EQ_INT(weft_render(ctx2, cloth2, &d0), WEFT_ERROR_GPU);
    CHECK(strstr(weft_context_last_error(ctx2), "bogus-device") != NULL);
    CHECK_EQ_INT(weft_render(ctx, cloth, &d0), WEFT_OK);
    unsetenv("WEFT_EGL_DEVICE");
    CHECK_EQ_INT(weft_render(ctx2, cloth2, &d0), WEFT_OK);   /* a later call may still succeed */
    weft_context_destroy(ctx2);
    ag_free(&m2);

    free(before);
    free(after);
    free(img);
    weft_context_destroy(ctx);
    ag_free(&m);
    return TEST_SUMMARY();
}
