/* The in-call flag (see call_guard.h). A context's call_owner holds the address of the owning
 * thread's token (a thread-local byte: unique per live thread, no global state shared between
 * threads) or 0; call_depth counts nested calls of that thread and is touched by the owner only. */
#include "call_guard.h"
#include "api_internal.h"

static _Thread_local char thread_token;

static uintptr_t self(void) { return (uintptr_t)&thread_token; }

wa_call_token wa_call_enter(weft_context* ctx) {
    wa_call_token t = {NULL, 0};
    if (!ctx) return t;
    uintptr_t expected = 0, me = self();
    if (atomic_compare_exchange_strong_explicit(&ctx->call_owner, &expected, me, memory_order_acquire,
                                                memory_order_relaxed)) {
        ctx->call_depth = 1;
        t.ctx = ctx;
    } else if (expected == me) {
        ++ctx->call_depth;   /* nested on the owning thread */
        t.ctx = ctx;
    } else {
        t.refused = 1;
    }
    return t;
}

void wa_call_leave(wa_call_token* t) {
    if (!t->ctx) return;
    if (--t->ctx->call_depth == 0) atomic_store_explicit(&t->ctx->call_owner, 0, memory_order_release);
}

int wa_call_idle(weft_context* ctx) {
    uintptr_t owner = atomic_load_explicit(&ctx->call_owner, memory_order_acquire);
    return owner == 0 || owner == self();
}
