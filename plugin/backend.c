/* The backend choice, in one place. A context runs every cloth on one backend, chosen at its
 * creation from def.backend: CPU is core's table (wc_cloth_cpu); GPU is gpu/'s (wg_cloth_backend,
 * built with WEFT_GPU), whose device (a GL context and the solver's programs) must work now;
 * AUTO takes the GPU only on a hardware device (a software rasteriser is slower than the CPU
 * solvers) and falls back to the CPU otherwise. The table and the device are the context's
 * (ctx->ops, ctx->device); every cloth gets them, and nothing else in the facade knows which
 * backend it has. */
#include <stdio.h>
#include "api_internal.h"

#ifdef WEFT_HAVE_GPU
#include "wg_backend.h"
#endif

/* The GPU's table, or NULL in a build without it. */
static const wc_cloth_backend* gpu_table(void) {
#ifdef WEFT_HAVE_GPU
    return &wg_cloth_backend;
#else
    return NULL;
#endif
}

weft_status wa_backend_choose(weft_context* ctx, char* why, size_t why_len) {
    const weft_context_def* def = &ctx->def;
    ctx->backend = WEFT_BACKEND_CPU;
    ctx->ops = &wc_cloth_cpu;
    ctx->device = NULL;
    if (def->backend == WEFT_BACKEND_CPU) {
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: CPU backend (asked for)");
        return WEFT_OK;
    }
    const int automatic = def->backend == WEFT_BACKEND_AUTO;
    const wc_cloth_backend* gpu = gpu_table();
    void* device = NULL;
    int software = 0;
    weft_status st = WEFT_ERROR_UNSUPPORTED;
    if (gpu) {
        wc_device_desc dd = {def->gl_mode == WEFT_GL_HOST_CURRENT, automatic, wa_core_log, ctx, ctx->alloc};
        st = wa_status(gpu->device_create(&dd, &device, &software, why, why_len));
    } else {
        snprintf(why, why_len, "this libweft.so was built without WEFT_GPU");
    }
    if (st != WEFT_OK && !automatic) return st;
    if (st == WEFT_OK && !software) {
        ctx->backend = WEFT_BACKEND_GPU;
        ctx->ops = gpu;
        ctx->device = device;
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: GPU backend (%s%s): %s",
               automatic ? "AUTO: hardware device" : "asked for",
               def->gl_mode == WEFT_GL_HOST_CURRENT ? ", host's GL context" : ", headless EGL", why);
    } else if (st == WEFT_OK) {
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: CPU backend (AUTO: the GPU device is a software rasteriser: %s)",
               why);
    } else {
        wa_log(ctx, WEFT_LOG_INFO, "weft_context_create: CPU backend (AUTO: no GPU backend: %s)", why);
    }
    return WEFT_OK;
}

void wa_backend_release(weft_context* ctx) {
    wc_diag d = wa_core_diag(ctx);
    if (ctx->ops->device_destroy(ctx->device, &d) != WC_OK)
        wa_log(ctx, WEFT_LOG_WARN, "weft_context_destroy: %s", d.message);
    ctx->device = NULL;
}

void* wa_backend_gl_context(const weft_context* ctx) {
#ifdef WEFT_HAVE_GPU
    if (ctx->ops == &wg_cloth_backend) return wg_backend_gl_context(ctx->device);
#else
    (void)ctx;
#endif
    return NULL;
}
