/* weft_context_step: many cloths of a context, each with its own frame, in one call.
 *
 * Each entry is checked as weft_cloth_step checks its arguments (the handle, then the frame:
 * cloth_frame.c's validation); one that fails is reported at its index (its status, the logger,
 * and the context's last error if it is the first) and left unchanged, a cloth named twice
 * included (the second time). The accepted ones become core's batch items (the context's scratch,
 * sized with its slots: nothing is allocated) and are stepped by core (core/cloth_batch.c: one
 * device group; on the CPU, cloths at once over the context's threads). A cloth may step on
 * another thread than the caller's, so what it logs meanwhile is kept per cloth (a few lines)
 * and passed to the host's logger afterwards, cloth by cloth in the array's order, from the
 * calling thread. */
#include <stdio.h>
#include <string.h>
#include "api_internal.h"
#include "call_guard.h"

static const char fn[] = "weft_context_step";

/* core's logger for one cloth of the batch: keeps what the context's logger would receive */
static void keep_line(wc_log_level level, const char* message, void* user) {
    wa_batch_log* log = user;
    const weft_context* ctx = log->ctx;
    if (level >= WC_LOG_ERROR) return;   /* failures come back as the cloth's status */
    weft_log_level l = wa_log_level(level);
    if (!ctx->def.log || l < ctx->def.log_level) return;
    if (log->n == WA_BATCH_LOG_LINES) {
        ++log->dropped;
        return;
    }
    log->level[log->n] = l;
    snprintf(log->line[log->n], sizeof log->line[0], "%s", message);
    ++log->n;
}

static void pass_on(weft_context* ctx, const wa_batch_log* log, int index) {
    for (int k = 0; k < log->n; ++k) wa_log(ctx, log->level[k], "%s: cloths[%d]: %s", fn, index, log->line[k]);
    if (log->dropped)
        wa_log(ctx, WEFT_LOG_WARN, "%s: cloths[%d]: %d more messages of its step were dropped", fn, index, log->dropped);
}

/* The first failure of the call (lowest index): its status and message become the context's. */
typedef struct first_failure {
    int index;                  /* -1: none yet */
    weft_status status;
    int count;
    char message[sizeof ((weft_context*)0)->last_error];
} first_failure;

/* Note a failure that wa_fail recorded for cloths[index]. */
static void note(first_failure* f, const weft_context* ctx, weft_status st, int index, weft_status* statuses) {
    if (statuses) statuses[index] = st;
    ++f->count;
    if (f->index >= 0 && f->index < index) return;
    f->index = index;
    f->status = st;
    snprintf(f->message, sizeof f->message, "%s", ctx->last_error);
}

/* The next call's mark for the slots (0 is never one: fresh slots hold it). */
static uint32_t next_call(weft_context* ctx) {
    if (++ctx->batch_calls == 0) {
        for (int s = 0; s < ctx->n_slots; ++s) ctx->slots[s].batch_call = 0;
        ctx->batch_calls = 1;
    }
    return ctx->batch_calls;
}

weft_status weft_context_step(weft_context* ctx, int n, const weft_cloth* cloths, const weft_frame* frames,
                              weft_frame_stats* stats, weft_status* statuses) {
    WA_CALL_GUARD(ctx);   /* threading contract: refused if another thread is inside (call_guard.h) */
    if (!ctx) return WEFT_ERROR_INVALID_ARGUMENT;
    if (n < 0) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: n = %d is negative", fn, n);
    if (n > 0 && !cloths) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: cloths is NULL (n = %d)", fn, n);
    if (n > 0 && !frames) return wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: frames is NULL (n = %d)", fn, n);
    const uint32_t call = next_call(ctx);
    first_failure first = {-1, WEFT_OK, 0, ""};
    char where[64], name[48];
    int m = 0;   /* items accepted */
    for (int i = 0; i < n; ++i) {
        snprintf(where, sizeof where, "%s: cloths[%d]", fn, i);
        wc_cloth* c = wa_lookup(ctx, cloths[i], where);
        if (!c) {
            note(&first, ctx, WEFT_ERROR_INVALID_HANDLE, i, statuses);
            continue;
        }
        wa_slot* slot = wa_slot_of(ctx, cloths[i]);
        if (slot->batch_call == call) {
            wa_fail(ctx, WEFT_ERROR_INVALID_ARGUMENT, "%s: cloths[%d] is cloths[%d] again (a cloth steps once a call)", fn,
                    i, slot->batch_index);
            note(&first, ctx, WEFT_ERROR_INVALID_ARGUMENT, i, statuses);
            continue;
        }
        snprintf(name, sizeof name, "frames[%d].", i);
        weft_status st = wa_validate_frame(ctx, c, &frames[i], fn, name);
        if (st != WEFT_OK) {
            note(&first, ctx, st, i, statuses);
            continue;
        }
        slot->batch_call = call;
        slot->batch_index = i;
        wa_batch_log* log = &ctx->batch_logs[m];
        log->ctx = ctx;
        log->n = log->dropped = 0;
        wc_cloth_batch_item* it = &ctx->batch_items[m++];
        memset(it, 0, sizeof *it);
        it->cloth = c;
        it->frame = wa_core_frame(&frames[i]);
        it->diag.log = keep_line;
        it->diag.log_user = log;
        it->index = i;
    }
    wc_diag d = wa_core_diag(ctx);
    wc_cloth_step_batch(ctx->batch_items, m, &d);   /* a group that cannot begin: every item's status */
    wc_cloth_batch_sort_by_index(ctx->batch_items, m);
    for (int k = 0; k < m; ++k) {
        const wc_cloth_batch_item* it = &ctx->batch_items[k];
        pass_on(ctx, it->diag.log_user, it->index);
        if (it->status != WC_OK) {
            snprintf(where, sizeof where, "%s: cloths[%d]", fn, it->index);
            note(&first, ctx, wa_fail_core(ctx, where, it->status, &it->diag), it->index, statuses);
            continue;
        }
        if (statuses) statuses[it->index] = WEFT_OK;
        if (stats) wa_fill_stats(&stats[it->index], &it->stats, it->cloth->state, it->ms);
    }
    if (first.index < 0) return wa_ok(ctx);
    /* the first failing cloth's message, as it was logged, and how many failed */
    if (first.count > 1)
        snprintf(ctx->last_error, sizeof ctx->last_error, "%.400s (%d of the %d cloths failed: see statuses)",
                 first.message, first.count, n);
    else
        snprintf(ctx->last_error, sizeof ctx->last_error, "%s", first.message);
    ctx->last_status = first.status;
    return first.status;
}
