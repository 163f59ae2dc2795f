/* The context's life: the def's defaults, weft_context_create (validation, the handle tag, the
 * backend choice: backend.c) and weft_context_destroy (its cloths, the renderer, the device). */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "api_internal.h"
#include "call_guard.h"

weft_context_def weft_default_context_def(void) {
    weft_context_def d;
    memset(&d, 0, sizeof d);
    d.backend = WEFT_BACKEND_AUTO;
    d.threads = 0;
    d.log_level = WEFT_LOG_WARN;
    d.gl_mode = WEFT_GL_HEADLESS;
    d.internal_cookie = WA_COOKIE_CONTEXT;
    return d;
}

static weft_status create_fail(const weft_context_def* def, weft_status st, const char* fmt, ...)
    __attribute__((format(printf, 3, 4)));
static weft_status create_fail(const weft_context_def* def, weft_status st, const char* fmt, ...) {
    if (def && def->log) {
        char msg[512];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        def->log(WEFT_LOG_ERROR, msg, def->log_user);
    }
    return st;
}

static uint32_t make_tag(const weft_context* ctx) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    uint64_t z = (uint64_t)(uintptr_t)ctx ^ ((uint64_t)ts.tv_nsec << 20) ^ (uint64_t)ts.tv_sec;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    uint32_t tag = (uint32_t)(z & 0xFFFFu);
    return tag ? tag : 0x5EED;
}

/* Errors of create go to def->log (there is no context to hold them). An ABI mismatch is
 * checked first and then the def is not read at all (its layout may be another ABI's). */
weft_status weft_context_create(int abi, const weft_context_def* def, weft_context** out) {
    if (out) *out = NULL;
    if (abi != WEFT_ABI) return WEFT_ERROR_ABI_MISMATCH;
    if (!def) return WEFT_ERROR_INVALID_ARGUMENT;
    /* a def that skipped weft_default_context_def() may hold a garbage logger: not called */
    if (def->internal_cookie != WA_COOKIE_CONTEXT) return WEFT_ERROR_INVALID_ARGUMENT;
    if (!out) return create_fail(def, WEFT_ERROR_INVALID_ARGUMENT, "weft_context_create: out is NULL");
    if ((unsigned)def->backend > WEFT_BACKEND_GPU)
        return create_fail(def, WEFT_ERROR_INVALID_ARGUMENT, "weft_context_create: def->backend %d is not a weft_backend",
                           (int)def->backend);
    if (def->threads < 0)
        return create_fail(def, WEFT_ERROR_INVALID_ARGUMENT, "weft_context_create: def->threads %d is negative",
                           def->threads);
    if ((unsigned)def->log_level > WEFT_LOG_ERROR)
        return create_fail(def, WEFT_ERROR_INVALID_ARGUMENT,
                           "weft_context_create: def->log_level %d is not a weft_log_level", (int)def->log_level);
    if ((unsigned)def->gl_mode > WEFT_GL_HOST_CURRENT)
        return create_fail(def, WEFT_ERROR_INVALID_ARGUMENT, "weft_context_create: def->gl_mode %d is not a weft_gl_mode",
                           (int)def->gl_mode);
    if ((def->allocator.alloc == NULL) != (def->allocator.free == NULL))
        return create_fail(def, WEFT_ERROR_INVALID_ARGUMENT,
                           "weft_context_create: def->allocator: alloc and free must both be set or both be NULL");
    wc_allocator a = {def->allocator.alloc, def->allocator.free, def->allocator.user};
    weft_context* ctx = WC_NEW(&a, weft_context, 1);
    if (!ctx) return create_fail(def, WEFT_ERROR_OUT_OF_MEMORY, "weft_context_create: out of memory");
    ctx->def = *def;
    ctx->alloc = a;
    ctx->last_status = WEFT_OK;
    ctx->last_error[0] = '\0';
    ctx->tag = make_tag(ctx);
    char why[512] = "";
    weft_status st = wa_backend_choose(ctx, why, sizeof why);
    if (st != WEFT_OK) {
        wc_free(&a, ctx);
        return create_fail(def, st, "weft_context_create: %s", why);
    }
    *out = ctx;
    return WEFT_OK;
}

void weft_context_destroy(weft_context* ctx) {
    if (!ctx) return;
    if (!wa_call_idle(ctx)) {   /* threading contract broken: leak the context rather than free it under a call */
        wa_log(ctx, WEFT_LOG_ERROR, "weft_context_destroy: another thread is inside a call on this context: "
               "not destroyed (threading contract, weft.h)");
        return;
    }
    for (int i = 0; i < ctx->n_slots; ++i)
        if (ctx->slots[i].cloth) wa_cloth_free(ctx, ctx->slots[i].cloth);
    wa_render_release(ctx);     /* the renderer before the GL context it may share with the device */
    wa_backend_release(ctx);
    wc_allocator a = ctx->alloc;
    wc_free(&a, ctx->slots);
    wc_free(&a, ctx->batch_items);
    wc_free(&a, ctx->batch_logs);
    wc_free(&a, ctx);
}

