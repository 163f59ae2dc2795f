/* The GPU backend of `weft bench`: one headless GL context (gpu/gl/egl_context.h: a GPU device
 * where EGL finds one, else Mesa's llvmpipe) and one solver device per process, made on first
 * use, and wg_sims on it. Every GL call sits between wg_gl_begin and wg_gl_end. Without gpu/
 * (WEFT_GPU=OFF) every entry point refuses with a message saying so. */
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd_bench.h"

#ifdef WEFT_HAVE_GPU
#include "egl_context.h"
#include "wg_device.h"
#include "wg_sim.h"

static wg_gl_context* g_gl;
static wg_device* g_dev;

struct bench_gpu_sim {
    wg_sim* sim;
};

int bench_gpu_open(char* msg, size_t size) {
    if (g_dev) return 0;
    char err[512] = "";
    wg_gl_context_desc cd;
    memset(&cd, 0, sizeof cd);
    if (wg_gl_context_create(&cd, &g_gl, err, sizeof err) != WC_OK) {
        snprintf(msg, size, "--backend gpu: cannot create a headless GL context: %s", err);
        return -1;
    }
    if (wg_gl_begin(g_gl, err, sizeof err) != WC_OK) {
        snprintf(msg, size, "--backend gpu: cannot make the GL context current: %s", err);
        wg_gl_context_destroy(g_gl);
        g_gl = NULL;
        return -1;
    }
    wc_status st = wg_device_create(g_gl, &g_dev, err, sizeof err);
    wg_gl_end(g_gl);
    if (st != WC_OK) {
        snprintf(msg, size, "--backend gpu: the GPU solver cannot run on %s: %s", wg_gl_context_description(g_gl),
                 err);
        wg_gl_context_destroy(g_gl);
        g_gl = NULL;
        g_dev = NULL;
        return -1;
    }
    return 0;
}

const char* bench_gpu_description(void) { return g_gl ? wg_gl_context_description(g_gl) : ""; }

void bench_gpu_close(void) {
    if (!g_gl) return;
    char err[256];
    if (g_dev) {
        if (wg_gl_begin(g_gl, err, sizeof err) == WC_OK) {
            wg_device_destroy(g_dev);
            wg_gl_end(g_gl);
        } else {
            wg_device_forget(g_dev);
        }
    }
    wg_gl_context_destroy(g_gl);
    g_gl = NULL;
    g_dev = NULL;
}

/* wg_gl_begin, or a failed status in diag. */
static wc_status begin(wc_diag* diag) {
    char err[512];
    if (!g_dev) return wc_fail(diag, WC_ERROR_GPU, "bench: the GPU device is not open");
    if (wg_gl_begin(g_gl, err, sizeof err) != WC_OK) return wc_fail(diag, WC_ERROR_GPU, "bench: %s", err);
    return WC_OK;
}

wc_status bench_gpu_sim_create(const wc_state* s, bench_gpu_sim** out, wc_diag* diag) {
    *out = NULL;
    bench_gpu_sim* g = calloc(1, sizeof *g);
    if (!g) return wc_fail(diag, WC_ERROR_OUT_OF_MEMORY, "bench: out of memory");
    wc_status st = begin(diag);
    if (st == WC_OK) {
        st = wg_sim_create(g_dev, s, NULL, &g->sim, diag);
        wg_gl_end(g_gl);
    }
    if (st != WC_OK) {
        free(g);
        return st;
    }
    *out = g;
    return WC_OK;
}

wc_status bench_gpu_sim_step(bench_gpu_sim* g, wc_state* s, double dt, wc_step_stats* st, wc_diag* diag) {
    wc_status r = begin(diag);
    if (r != WC_OK) return r;
    r = wg_sim_step_frame(g->sim, s, dt, st, diag);
    wg_gl_end(g_gl);
    return r;
}

wc_status bench_gpu_sim_download(bench_gpu_sim* g, wc_state* s, wc_diag* diag) {
    wc_status r = begin(diag);
    if (r != WC_OK) return r;
    r = wg_sim_download(g->sim, s, diag);
    wg_gl_end(g_gl);
    return r;
}

void bench_gpu_sim_destroy(bench_gpu_sim* g) {
    if (!g) return;
    wc_diag d = {0};
    if (begin(&d) == WC_OK) {
        wg_sim_destroy(g->sim);
        wg_gl_end(g_gl);
    } else {
        wg_sim_forget(g->sim);
    }
    free(g);
}

#else /* no gpu/ in this build */

#define NO_GPU "--backend gpu: this weft was built without the GPU backend (WEFT_GPU=OFF)"

int bench_gpu_open(char* msg, size_t size) {
    snprintf(msg, size, "%s", NO_GPU);
    return -1;
}

const char* bench_gpu_description(void) { return ""; }

void bench_gpu_close(void) {}

wc_status bench_gpu_sim_create(const wc_state* s, bench_gpu_sim** out, wc_diag* diag) {
    (void)s;
    *out = NULL;
    return wc_fail(diag, WC_ERROR_UNSUPPORTED, "%s", NO_GPU);
}

wc_status bench_gpu_sim_step(bench_gpu_sim* g, wc_state* s, double dt, wc_step_stats* st, wc_diag* diag) {
    (void)g, (void)s, (void)dt, (void)st;
    return wc_fail(diag, WC_ERROR_UNSUPPORTED, "%s", NO_GPU);
}

wc_status bench_gpu_sim_download(bench_gpu_sim* g, wc_state* s, wc_diag* diag) {
    (void)g, (void)s;
    return wc_fail(diag, WC_ERROR_UNSUPPORTED, "%s", NO_GPU);
}

void bench_gpu_sim_destroy(bench_gpu_sim* g) { (void)g; }

#endif
