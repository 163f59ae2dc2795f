/* The GPU tests' device: a headless EGL context made current and the solver's device on it
 * (llvmpipe without a GPU), and their release; a layout and a runner on that device. */
#ifndef WEFT_TESTS_GPU_TEST_DEVICE_H
#define WEFT_TESTS_GPU_TEST_DEVICE_H

#include <stdio.h>
#include <string.h>

#include "egl_context.h"
#include "wg_device.h"
#include "wg_runner.h"

/* 1 with *gl current and *dev made (its renderer and kind of passes printed); 0 with the
 * reason on stderr and nothing left made */
static inline int tg_gpu_open(wg_gl_context** gl, wg_device** dev) {
    wg_gl_context_desc cd;
    memset(&cd, 0, sizeof cd);
    char err[1024];
    *gl = NULL;
    *dev = NULL;
    if (wg_gl_context_create(&cd, gl, err, sizeof err) != WC_OK) {
        fprintf(stderr, "no headless GL context: %s\n", err);
        return 0;
    }
    if (wg_gl_begin(*gl, err, sizeof err) != WC_OK) {
        fprintf(stderr, "wg_gl_begin: %s\n", err);
        wg_gl_context_destroy(*gl);
        *gl = NULL;
        return 0;
    }
    if (wg_device_create(*gl, dev, err, sizeof err) != WC_OK) {
        fprintf(stderr, "no GPU device: %s\n", err);
        wg_gl_end(*gl);
        wg_gl_context_destroy(*gl);
        *gl = NULL;
        return 0;
    }
    printf("device: %s (%s passes)\n", (*dev)->renderer, (*dev)->compute ? "compute" : "fragment");
    return 1;
}

static inline void tg_gpu_close(wg_gl_context* gl, wg_device* dev) {
    wg_device_destroy(dev);
    wg_gl_end(gl);
    wg_gl_context_destroy(gl);
}

/* The tests' layout (rows of 1,024 items) and a runner on dev over it: 1 when made; 0 with the
 * reason in err. The runner is set either way and tg_runner_close may follow either way. */
static inline int tg_runner_open(wg_device* dev, wg_layout* L, wg_runner* run, char* err, size_t err_len) {
    int made = wg_layout_init(L, 10, dev->max_texture_size, (wc_allocator){0}, err, err_len);
    wg_runner_init(run, dev, L);
    return made;
}

static inline void tg_runner_close(wg_runner* run, wg_layout* L) {
    wg_runner_destroy(run);
    wg_layout_destroy(L);
}

#endif
