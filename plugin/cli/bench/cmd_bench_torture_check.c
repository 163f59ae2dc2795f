/* The checks `weft bench torture` makes around every call of a case (see cmd_bench_torture.h):
 *   - a call that returns WEFT_OK leaves every output of weft_cloth_get_vertices (world and
 *     object space, positions and normals) and the frame statistics finite;
 *   - a call that returns anything else has a message (weft_context_last_error), and a refused
 *     call on an existing cloth leaves its vertices and its snapshot (weft_cloth_save) byte for
 *     byte as they were;
 *   - a call given a NaN or Inf (tc.poisoned) is refused.
 * A case stops at its first defect, and after a refused weft_cloth_create. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cmd_bench_torture_case.h"

void* tc_alloc(tc* t, size_t size) {
    if (t->n_allocs == TC_MAX_ALLOCS) return NULL;
    void* p = calloc(1, size ? size : 1);
    if (p) t->allocs[t->n_allocs++] = p;
    return p;
}

/* Record an outcome when it is worse than the one so far. */
void tc_mark(tc* t, int outcome, weft_status st, const char* where, const char* fmt, ...) {
    if (outcome >= TO_FIRST_DEFECT) t->stop = 1;
    if (outcome <= t->res->outcome) return;
    t->res->outcome = outcome;
    t->res->status = (int)st;
    snprintf(t->res->where, sizeof t->res->where, "%s", where);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(t->res->detail, sizeof t->res->detail, fmt, ap);
    va_end(ap);
}

static int all_finite(const float* a, size_t n, size_t* bad) {
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(a[i])) {
            *bad = i;
            return 0;
        }
    return 1;
}

/* Read the cloth's vertices (both spaces) and snapshot into set k. 0, or -1 (outcome recorded). */
static int tc_capture(tc* t, int k, const char* where) {
    static const char* const what[4] = {"world position", "world normal", "object position", "object normal"};
    weft_status st = WEFT_OK;
    int count = 0;
    for (int s = 0; s < 2 && st == WEFT_OK; ++s)
        st = weft_cloth_get_vertices(t->ctx, t->cloth, s ? WEFT_SPACE_OBJECT : WEFT_SPACE_WORLD, t->buf[k][2 * s],
                                     t->buf[k][2 * s + 1], t->n_host, &count);
    weft_cloth_info info;
    if (st == WEFT_OK) st = weft_cloth_get_info(t->ctx, t->cloth, &info);
    if (st == WEFT_OK && info.snapshot_size > t->snap_cap[k]) {
        free(t->snap[k]);
        t->snap[k] = malloc(info.snapshot_size);
        t->snap_cap[k] = t->snap[k] ? info.snapshot_size : 0;
    }
    if (st == WEFT_OK && !t->snap[k]) st = WEFT_ERROR_OUT_OF_MEMORY;
    if (st == WEFT_OK) st = weft_cloth_save(t->ctx, t->cloth, t->snap[k], info.snapshot_size);
    t->res->calls += 4;
    if (st != WEFT_OK) {
        tc_mark(t, TO_REJECTED, st, where, "reading the cloth back: %s", weft_context_last_error(t->ctx));
        t->stop = 1;
        return -1;
    }
    t->snap_size[k] = info.snapshot_size;
    for (int b = 0; b < 4; ++b) {
        size_t bad = 0;
        if (!all_finite(t->buf[k][b], 3 * (size_t)t->n_host, &bad)) {
            tc_mark(t, TO_NONFINITE, WEFT_OK, where, "%s of vertex %zu is %g", what[b], bad / 3,
                    (double)t->buf[k][b][bad]);
            return -1;
        }
    }
    if (!isfinite(info.total_mass)) tc_mark(t, TO_NONFINITE, WEFT_OK, where, "total mass %g", info.total_mass);
    return 0;
}

/* A call returned st: check the message, and that a refused call changed nothing (set 0 holds
 * the cloth from before the call when had_cloth). */
static void tc_refused(tc* t, weft_status st, const char* where, int had_cloth) {
    const char* msg = weft_context_last_error(t->ctx);
    if (!msg || !msg[0]) {
        tc_mark(t, TO_EMPTY_MESSAGE, st, where, "%s without a message", weft_status_string(st));
        return;
    }
    if (had_cloth && tc_capture(t, 1, where) == 0) {
        int same = t->snap_size[0] == t->snap_size[1] && !memcmp(t->snap[0], t->snap[1], t->snap_size[0]);
        for (int b = 0; b < 4; ++b) same &= !memcmp(t->buf[0][b], t->buf[1][b], 3 * (size_t)t->n_host * sizeof(float));
        if (!same) {
            tc_mark(t, TO_STATE_CHANGED, st, where, "refused (%s) but the cloth changed: %s", weft_status_string(st), msg);
            return;
        }
    }
    tc_mark(t, st == WEFT_ERROR_STEP_FAILED ? TO_STEP_FAILED : TO_REJECTED, st, where, "%s", msg);
}

/* A call returned WEFT_OK: a poisoned one should not have. */
static void tc_accepted(tc* t, const char* where) {
    if (t->poisoned) tc_mark(t, TO_ACCEPTED, WEFT_OK, where, "a NaN/Inf input was accepted");
    t->poisoned = 0;
}

void tc_create_at(tc* t, const weft_cloth_def* def, const char* where) {
    weft_status st = weft_cloth_create(t->ctx, def, &t->cloth);
    ++t->res->calls;
    if (st != WEFT_OK) {
        if (t->cloth.id != 0) tc_mark(t, TO_STATE_CHANGED, st, where, "refused but the handle is not null");
        tc_refused(t, st, where, 0);
        t->cloth.id = 0;
        t->stop = 1;
        return;
    }
    tc_accepted(t, where);
    weft_cloth_info info;
    if (weft_cloth_get_info(t->ctx, t->cloth, &info) != WEFT_OK) {
        tc_mark(t, TO_REJECTED, weft_context_last_status(t->ctx), "info", "%s", weft_context_last_error(t->ctx));
        t->stop = 1;
        return;
    }
    t->n_host = t->res->vertices = info.n_vertices;
    for (int k = 0; k < 2; ++k)
        for (int b = 0; b < 4; ++b) t->buf[k][b] = tc_alloc(t, 3 * (size_t)info.n_vertices * sizeof(float));
    if (!t->buf[1][3]) {
        tc_mark(t, TO_REJECTED, WEFT_ERROR_OUT_OF_MEMORY, "create", "the case ran out of memory");
        t->stop = 1;
        return;
    }
    tc_capture(t, 0, where);
}

void tc_create(tc* t, const weft_cloth_def* def) { tc_create_at(t, def, "create"); }

void tc_step(tc* t, const weft_frame* fr, const char* where) {
    if (t->stop || tc_capture(t, 0, where) != 0) return;
    weft_frame_stats stats;
    weft_status st = weft_cloth_step(t->ctx, t->cloth, fr, &stats);
    ++t->res->calls;
    if (st != WEFT_OK) {
        tc_refused(t, st, where, 1);
        return;
    }
    ++t->res->frames;
    tc_accepted(t, where);
    const double v[4] = {stats.kinetic_energy, stats.max_strain, stats.residual, stats.time};
    static const char* const names[4] = {"kinetic_energy", "max_strain", "residual", "time"};
    for (int k = 0; k < 4; ++k)
        if (!isfinite(v[k])) tc_mark(t, TO_NONFINITE, WEFT_OK, where, "frame stats %s = %g", names[k], v[k]);
    tc_capture(t, 1, where);
}

void tc_set_attachments(tc* t, const weft_attachment_def* a, int n, const char* where) {
    if (t->stop || tc_capture(t, 0, where) != 0) return;
    weft_status st = weft_cloth_set_attachments(t->ctx, t->cloth, a, n);
    ++t->res->calls;
    if (st != WEFT_OK) {
        tc_refused(t, st, where, 1);
        return;
    }
    tc_accepted(t, where);
    t->n_att = n;
    for (int i = 0; i < n; ++i) {
        const float* m = a[i].bind_transform;
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) t->att[i].R[3 * r + c] = m[4 * c + r];
            t->att[i].t[r] = m[12 + r];
        }
    }
    tc_capture(t, 1, where);
}

