/* The helpers every API file uses: core's statuses as the ABI's, the last error/status, the
 * logger bridges to core (wc_diag, wc_log_fn, also handed to gpu/), and the handle table.
 *
 * Handles: a weft_cloth id packs (from the high bits) a 16-bit context tag, a 4-bit type tag,
 * a 20-bit slot generation and a 24-bit slot index. The context tag comes from the context's
 * address and the clock at creation (no global counter: there is no global state), so a handle of
 * another context is refused w.h.p.; a destroyed cloth bumps its slot's generation, so stale
 * copies are refused; anything else that does not decode to a live slot is refused too. Zero is
 * never a valid id. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include "api_internal.h"

#define WA_TYPE_CLOTH 0xAu
#define WA_SLOT_BITS 24
#define WA_GEN_BITS 20
#define WA_MAX_SLOTS (1 << WA_SLOT_BITS)

weft_status wa_status(wc_status s) {
    switch (s) {
    case WC_OK: return WEFT_OK;
    case WC_ERROR_INVALID_ARGUMENT: return WEFT_ERROR_INVALID_ARGUMENT;
    case WC_ERROR_OUT_OF_MEMORY: return WEFT_ERROR_OUT_OF_MEMORY;
    case WC_ERROR_IO: return WEFT_ERROR_IO;
    case WC_ERROR_IMPORT: return WEFT_ERROR_IMPORT;
    case WC_ERROR_EMPTY_MESH: return WEFT_ERROR_EMPTY_MESH;
    case WC_ERROR_NONFINITE: return WEFT_ERROR_NONFINITE;
    case WC_ERROR_OUT_OF_RANGE: return WEFT_ERROR_OUT_OF_RANGE;
    case WC_ERROR_SOLVER_DIVERGED: return WEFT_ERROR_SOLVER_DIVERGED;
    case WC_ERROR_SOLVER_NOT_CONVERGED: return WEFT_ERROR_SOLVER_NOT_CONVERGED;
    case WC_ERROR_FACTORIZATION: return WEFT_ERROR_FACTORIZATION;
    case WC_ERROR_STEP_FAILED: return WEFT_ERROR_STEP_FAILED;
    case WC_ERROR_CALL_ORDER: return WEFT_ERROR_CALL_ORDER;
    case WC_ERROR_UNSUPPORTED: return WEFT_ERROR_UNSUPPORTED;
    case WC_ERROR_SNAPSHOT_MISMATCH: return WEFT_ERROR_SNAPSHOT_MISMATCH;
    case WC_ERROR_GPU: return WEFT_ERROR_GPU;
    }
    return WEFT_ERROR_INVALID_ARGUMENT;   /* not reached: every core status is listed */
}

weft_log_level wa_log_level(wc_log_level level) {
    switch (level) {
    case WC_LOG_DEBUG: return WEFT_LOG_DEBUG;
    case WC_LOG_INFO: return WEFT_LOG_INFO;
    case WC_LOG_WARN: return WEFT_LOG_WARN;
    case WC_LOG_ERROR: break;
    }
    return WEFT_LOG_ERROR;
}

void wa_core_log(wc_log_level level, const char* message, void* user) {
    weft_context* ctx = user;
    if (level >= WC_LOG_ERROR) return;   /* reported once, prefixed, through wa_fail */
    weft_log_level l = wa_log_level(level);
    if (ctx->def.log && l >= ctx->def.log_level) ctx->def.log(l, message, ctx->def.log_user);
}

/* The message of the last failed call: a later successful call leaves it in place (its status,
 * weft_context_last_status, says OK). */
const char* weft_context_last_error(const weft_context* ctx) {
    return ctx ? ctx->last_error : "weft_context_last_error: ctx is NULL";
}

weft_status weft_context_last_status(const weft_context* ctx) {
    return ctx ? ctx->last_status : WEFT_ERROR_INVALID_ARGUMENT;
}

weft_backend weft_context_backend(const weft_context* ctx) { return ctx ? ctx->backend : WEFT_BACKEND_AUTO; }

weft_status wa_fail(weft_context* ctx, weft_status status, const char* fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(ctx->last_error, sizeof ctx->last_error, fmt, ap);
    va_end(ap);
    ctx->last_status = status;
    if (ctx->def.log && ctx->def.log_level <= WEFT_LOG_ERROR) ctx->def.log(WEFT_LOG_ERROR, ctx->last_error, ctx->def.log_user);
    return status;
}

weft_status wa_fail_core(weft_context* ctx, const char* fn, wc_status st, const wc_diag* d) {
    return wa_fail(ctx, wa_status(st), "%s: %s", fn, d->message);
}

weft_status wa_ok(weft_context* ctx) {
    ctx->last_status = WEFT_OK;
    return WEFT_OK;
}

void wa_log(weft_context* ctx, weft_log_level level, const char* fmt, ...) {
    if (!ctx->def.log || level < ctx->def.log_level) return;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    ctx->def.log(level, msg, ctx->def.log_user);
}

wc_diag wa_core_diag(weft_context* ctx) {
    wc_diag d;
    memset(&d, 0, sizeof d);
    d.log = wa_core_log;
    d.log_user = ctx;
    return d;
}

/* ---- handle table ---------------------------------------------------------------------------- */

static uint64_t encode(const weft_context* ctx, int slot, uint32_t gen) {
    return ((uint64_t)ctx->tag << 48) | ((uint64_t)WA_TYPE_CLOTH << 44) |
           ((uint64_t)(gen & ((1u << WA_GEN_BITS) - 1)) << WA_SLOT_BITS) | (uint64_t)slot;
}

wc_cloth* wa_lookup(weft_context* ctx, weft_cloth h, const char* fn) {
    if (h.id == 0) {
        wa_fail(ctx, WEFT_ERROR_INVALID_HANDLE, "%s: cloth is the null handle", fn);
        return NULL;
    }
    uint32_t tag = (uint32_t)(h.id >> 48), type = (uint32_t)(h.id >> 44) & 0xFu;
    uint32_t gen = (uint32_t)(h.id >> WA_SLOT_BITS) & ((1u << WA_GEN_BITS) - 1);
    int slot = (int)(h.id & (WA_MAX_SLOTS - 1));
    if (tag != ctx->tag || type != WA_TYPE_CLOTH) {
        wa_fail(ctx, WEFT_ERROR_INVALID_HANDLE, "%s: cloth handle 0x%llx does not belong to this context", fn,
                (unsigned long long)h.id);
        return NULL;
    }
    if (slot >= ctx->n_slots || (ctx->slots[slot].generation & ((1u << WA_GEN_BITS) - 1)) != gen) {
        wa_fail(ctx, WEFT_ERROR_INVALID_HANDLE, "%s: cloth handle 0x%llx is stale (destroyed) or forged", fn,
                (unsigned long long)h.id);
        return NULL;
    }
    if (!ctx->slots[slot].cloth) {
        wa_fail(ctx, WEFT_ERROR_INVALID_HANDLE, "%s: cloth handle 0x%llx was destroyed", fn, (unsigned long long)h.id);
        return NULL;
    }
    return ctx->slots[slot].cloth;
}

int wa_register(weft_context* ctx, wc_cloth* c, weft_cloth* out) {
    int slot = -1;
    for (int i = 0; i < ctx->n_slots; ++i)
        if (!ctx->slots[i].cloth) {
            slot = i;
            break;
        }
    if (slot < 0) {
        if (ctx->n_slots == ctx->cap_slots) {
            int cap = ctx->cap_slots ? 2 * ctx->cap_slots : 8;
            if (cap > WA_MAX_SLOTS) return 0;
            wa_slot* s = WC_NEW(&ctx->alloc, wa_slot, (size_t)cap);
            /* weft_context_step's scratch: one item and one log per cloth the slots can hold */
            wc_cloth_batch_item* items = WC_NEW(&ctx->alloc, wc_cloth_batch_item, (size_t)cap);
            wa_batch_log* logs = WC_NEW(&ctx->alloc, wa_batch_log, (size_t)cap);
            if (!s || !items || !logs) {
                wc_free(&ctx->alloc, s);
                wc_free(&ctx->alloc, items);
                wc_free(&ctx->alloc, logs);
                return 0;
            }
            if (ctx->n_slots) memcpy(s, ctx->slots, (size_t)ctx->n_slots * sizeof(wa_slot));
            wc_free(&ctx->alloc, ctx->slots);
            wc_free(&ctx->alloc, ctx->batch_items);
            wc_free(&ctx->alloc, ctx->batch_logs);
            ctx->slots = s;
            ctx->batch_items = items;
            ctx->batch_logs = logs;
            ctx->cap_slots = cap;
        }
        slot = ctx->n_slots++;
        ctx->slots[slot].generation = 1;
    }
    ctx->slots[slot].cloth = c;
    out->id = encode(ctx, slot, ctx->slots[slot].generation);
    return 1;
}

wa_slot* wa_slot_of(weft_context* ctx, weft_cloth h) { return &ctx->slots[h.id & (WA_MAX_SLOTS - 1)]; }

void wa_unregister(weft_context* ctx, weft_cloth h) {
    int slot = (int)(h.id & (WA_MAX_SLOTS - 1));
    ctx->slots[slot].cloth = NULL;
    uint32_t g = (ctx->slots[slot].generation + 1) & ((1u << WA_GEN_BITS) - 1);
    ctx->slots[slot].generation = g ? g : 1;
}

void wa_cloth_free(weft_context* ctx, wc_cloth* c) {
    wc_diag d = wa_core_diag(ctx);
    if (wc_cloth_destroy(c, &d) != WC_OK) wa_log(ctx, WEFT_LOG_WARN, "weft_cloth_destroy: %s", d.message);
}
