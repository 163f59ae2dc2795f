/* The in-call flag: catches a host that breaks the threading contract (weft.h: one thread at a
 * time per context) by entering a context from a second thread while another is inside a call.
 *
 * Every entry point that takes a context starts with WA_CALL_GUARD(ctx): it claims the context
 * for the calling thread with one atomic compare-and-swap (released when the function returns,
 * by the cleanup attribute); a thread that finds the context claimed by another thread is
 * refused at once with WEFT_ERROR_CONCURRENT_CALL and touches nothing of the context (not even
 * its last error: that belongs to the thread inside). Nested calls on the same thread (a logger
 * or allocator callback calling back in, weft_render reading the vertices) pass. Cost: two
 * atomic operations per call, no lock, no wait.
 *
 * What it cannot catch: a call made after another thread destroyed the context (use after free,
 * as with free()), and the reads weft_context_last_error/last_status/backend, which take no
 * claim (they return pointers into the context). */
#ifndef WEFT_PLUGIN_CALL_GUARD_H
#define WEFT_PLUGIN_CALL_GUARD_H
#include "weft/weft.h"

typedef struct wa_call_token {
    weft_context* ctx;      /* NULL: nothing claimed (no context, or refused) */
    int refused;            /* 1: another thread is inside a call on ctx */
} wa_call_token;

/* Claim ctx for the calling thread (NULL ctx: nothing to claim, the call reports it). */
wa_call_token wa_call_enter(weft_context* ctx);
/* Release what enter claimed (the cleanup of WA_CALL_GUARD). */
void wa_call_leave(wa_call_token* t);
/* 1 when no other thread is inside a call on ctx (weft_context_destroy's check). */
int wa_call_idle(weft_context* ctx);

#define WA_CALL_GUARD(ctx)                                                                        \
    wa_call_token wa_call_token_ __attribute__((cleanup(wa_call_leave))) = wa_call_enter(ctx); \
    if (wa_call_token_.refused) return WEFT_ERROR_CONCURRENT_CALL

#endif
