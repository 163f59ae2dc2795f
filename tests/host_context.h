/* The host-current tests' set-up (test_api_gpu_body_gl.c, test_api_gpu_body_newton.c,
 * test_api_gpu_body_pairs.c): a headless EGL context that the test program makes current as a host
 * application would, and the API's contexts of one thread; each step CHECKed. */
#ifndef WEFT_TESTS_HOST_CONTEXT_H
#define WEFT_TESTS_HOST_CONTEXT_H
#include <string.h>

#include "api_gpu_support.h"
#include "check.h"
#include "egl_context.h"
#include "weft/weft.h"

/* A host's headless context, current (NULL when none could be made). */
static inline wg_gl_context* hc_host_begin(void) {
    char err[512];
    wg_gl_context_desc hd;
    memset(&hd, 0, sizeof hd);
    wg_gl_context* host = NULL;
    CHECK_EQ_INT(wg_gl_context_create(&hd, &host, err, sizeof err), WEFT_OK);
    if (host) CHECK_EQ_INT(wg_gl_begin(host, err, sizeof err), WEFT_OK);
    return host;
}

/* A context of one thread on backend in GL mode mode (NULL when refused). */
static inline weft_context* hc_context(weft_backend backend, weft_gl_mode mode) {
    weft_context_def cd = ap_context_def(backend);
    cd.gl_mode = mode;
    return ap_create(&cd, WEFT_OK, NULL);
}

#endif
