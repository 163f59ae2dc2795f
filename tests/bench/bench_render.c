/* Preview renderer timing: a draped n x n cloth over a sphere on a floor plane, auto-framed.
 * Prints the first render (framebuffer allocation, first draw) and the median of --runs renders
 * for MSAA off and on; --png writes the last picture. Not a test: nothing here asserts a time. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "egl_context.h"
#include "png_write.h"
#include "render.h"

static double now_ms(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static int cmp_double(const void* a, const void* b) {
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* A tablecloth: on the sphere's cap inside its radius, hanging in folds outside, resting on the
 * floor where it would go through it. */
static void drape(int n, float sphere_r, float floor_y, float* pos, int* tris) {
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float x = -1.0f + 2.0f * i / (n - 1), z = -1.0f + 2.0f * j / (n - 1);
            float r = sqrtf(x * x + z * z), y;
            if (r < 0.8f * sphere_r) {
                y = sqrtf(sphere_r * sphere_r - r * r) + 0.01f;
            } else {
                float th = atan2f(z, x), out = r - 0.8f * sphere_r;
                y = sqrtf(sphere_r * sphere_r * 0.36f) + 0.01f - 1.4f * out;
                float fold = 0.06f * out * sinf(9.0f * th);
                x += fold * -sinf(th);
                z += fold * cosf(th);
                x *= 1.0f - 0.25f * out;
                z *= 1.0f - 0.25f * out;
            }
            if (y < floor_y + 0.005f) y = floor_y + 0.005f;
            float* p = &pos[3 * (i + n * j)];
            p[0] = x;
            p[1] = y;
            p[2] = z;
        }
    int* t = tris;
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            int a = i + n * j, b = a + 1, c = a + n + 1, d = a + n;
            /* counter-clockwise seen from +y: the top is the front */
            *t++ = a; *t++ = d; *t++ = c;
            *t++ = a; *t++ = c; *t++ = b;
        }
}

int main(int argc, char** argv) {
    int n = 100, runs = 20, w = 640, h = 480;
    const char* png = NULL;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--n") && i + 1 < argc) n = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc) runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 2 < argc) {
            w = atoi(argv[++i]);
            h = atoi(argv[++i]);
        }
        else if (!strcmp(argv[i], "--png") && i + 1 < argc) png = argv[++i];
        else {
            fprintf(stderr, "usage: bench_render [--n N] [--runs R] [--size W H] [--png FILE]\n");
            return 2;
        }
    }
    if (n < 2 || runs < 1 || runs > 10000) return 2;
    float* pos = (float*)malloc(sizeof(float) * 3 * (size_t)n * n);
    int* tris = (int*)malloc(sizeof(int) * 6 * (size_t)(n - 1) * (n - 1));
    unsigned char* img = (unsigned char*)malloc(4 * (size_t)w * h);
    double* ms = (double*)malloc(sizeof(double) * (size_t)runs);
    const float sphere_r = 0.5f, floor_y = -0.6f;
    drape(n, sphere_r, floor_y, pos, tris);
    wg_mesh cloth = {pos, NULL, n * n, tris, 2 * (n - 1) * (n - 1), {0.85f, 0.33f, 0.22f},
                     {0.25f, 0.45f, 0.80f}};
    wg_shape shapes[2];
    memset(shapes, 0, sizeof shapes);
    for (int k = 0; k < 2; ++k)
        shapes[k].transform[0] = shapes[k].transform[5] = shapes[k].transform[10] =
            shapes[k].transform[15] = 1.0f;
    shapes[0].type = WG_SHAPE_SPHERE;
    shapes[0].radius = sphere_r;
    shapes[1].type = WG_SHAPE_PLANE;
    shapes[1].transform[13] = floor_y;
    wg_camera cam = {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 40.0f, w, h};

    char err[1024];
    wg_gl_context_desc desc;
    memset(&desc, 0, sizeof desc);
    wg_gl_context* ctx = NULL;
    if (wg_gl_context_create(&desc, &ctx, err, sizeof err) != WC_OK) {
        fprintf(stderr, "bench_render: %s\n", err);
        return 1;
    }
    printf("device: %s\n", wg_gl_context_description(ctx));
    printf("scene: %d x %d cloth (%d triangles, normals computed), sphere, plane; %d x %d\n", n,
           n, cloth.n_triangles, w, h);
    int rc = 0;
    for (int samples = 1; samples <= 4 && rc == 0; samples += 3) {
        wg_renderer_desc rd = {samples};
        wg_renderer* r = NULL;
        double t0 = now_ms();
        if (wg_renderer_create(ctx, &rd, &r, err, sizeof err) != WC_OK) {
            fprintf(stderr, "bench_render: %s\n", err);
            rc = 1;
            break;
        }
        double t1 = now_ms();
        if (wg_render(r, &cam, &cloth, 1, shapes, 2, img, err, sizeof err) != WC_OK) {
            fprintf(stderr, "bench_render: %s\n", err);
            rc = 1;
        }
        double t2 = now_ms();
        for (int k = 0; k < runs && rc == 0; ++k) {
            double a = now_ms();
            if (wg_render(r, &cam, &cloth, 1, shapes, 2, img, err, sizeof err) != WC_OK) {
                fprintf(stderr, "bench_render: %s\n", err);
                rc = 1;
            }
            ms[k] = now_ms() - a;
        }
        if (rc == 0) {
            qsort(ms, (size_t)runs, sizeof *ms, cmp_double);
            printf("samples %d (used %d): create %.1f ms, first render %.1f ms, median of %d %.2f "
                   "ms (min %.2f, max %.2f)\n",
                   samples, wg_renderer_samples(r), t1 - t0, t2 - t1, runs, ms[runs / 2], ms[0],
                   ms[runs - 1]);
        }
        wg_renderer_destroy(r);
    }
    if (rc == 0 && png) {
        if (wg_png_write(png, img, w, h, err, sizeof err) != WC_OK) {
            fprintf(stderr, "bench_render: %s\n", err);
            rc = 1;
        } else {
            printf("wrote %s\n", png);
        }
    }
    wg_gl_context_destroy(ctx);
    free(pos);
    free(tris);
    free(img);
    free(ms);
    return rc;
}
