/* The GPU API tests' set-up (test_api_gpu*.c, host_context.h): contexts of one thread on a
 * backend, made with their status CHECKed or only tried, the probe for a GPU context, and the
 * sheet held by two adjacent corners that several of them hang.
 * Header-only, public header only. */
#ifndef WEFT_TESTS_API_GPU_SUPPORT_H
#define WEFT_TESTS_API_GPU_SUPPORT_H
#include <stdio.h>

#include "api_grid.h"
#include "check.h"
#include "weft/weft.h"

/* One thread on backend; the rest the defaults (the caller may set more before creating). */
static inline weft_context_def ap_context_def(weft_backend backend) {
    weft_context_def cd = weft_default_context_def();
    cd.threads = 1;
    cd.backend = backend;
    return cd;
}

/* The context of *cd, its status CHECKed to be want (one check); on a mismatch log's last
 * message on stderr (log NULL: nothing printed). NULL unless made. */
static inline weft_context* ap_create(const weft_context_def* cd, weft_status want, const ag_log* log) {
    weft_context* ctx = NULL;
    weft_status st = weft_context_create(WEFT_ABI, cd, &ctx);
    CHECK_EQ_INT(st, want);
    if (st != want && log) fprintf(stderr, "weft_context_create: %s\n", log->last);
    return ctx;
}

/* The context of *cd, not counted as a check: NULL when refused. */
static inline weft_context* ap_try_create(const weft_context_def* cd) {
    weft_context* ctx = NULL;
    if (weft_context_create(WEFT_ABI, cd, &ctx) != WEFT_OK) return NULL;
    return ctx;
}

/* A context of one thread on backend, its creation CHECKed (NULL when refused). */
static inline weft_context* ap_context(weft_backend backend) {
    weft_context_def cd = ap_context_def(backend);
    return ap_create(&cd, WEFT_OK, NULL);
}

/* The same, not counted as a check. */
static inline weft_context* ap_try_context(weft_backend backend) {
    weft_context_def cd = ap_context_def(backend);
    return ap_try_create(&cd);
}

/* 1 when a GPU context of one thread can be made here (made and destroyed, not counted). */
static inline int ap_gpu_here(void) {
    weft_context* probe = ap_try_context(WEFT_BACKEND_GPU);
    weft_context_destroy(probe);
    return probe != NULL;
}

/* The pins of ap_pinned_sheet_def: host vertices 0 and n - 1 (the corners of the first row of an
 * unsplit n x n grid), and their attachment. The cloth def points into it. */
typedef struct ap_pins {
    int v[2];
    weft_attachment_def att;
} ap_pins;

/* The grid m held by two adjacent corners (pins, filled here), at the defaults. Horizontal, it
 * swings down and hangs. */
static inline weft_cloth_def ap_corner_sheet_def(const ag_mesh* m, ap_pins* pins) {
    pins->v[0] = 0;
    pins->v[1] = m->n - 1;
    pins->att = weft_default_attachment_def();
    pins->att.vertices = pins->v;
    pins->att.n_vertices = 2;
    weft_cloth_def def = weft_default_cloth_def();
    def.mesh = ag_desc(m);
    def.attachments = &pins->att;
    def.n_attachments = 1;
    return def;
}

/* ap_corner_sheet_def with PCG and block Jacobi, Newton newton, line search line_search. */
static inline weft_cloth_def ap_pinned_sheet_def(const ag_mesh* m, ap_pins* pins, int newton, int line_search) {
    weft_cloth_def def = ap_corner_sheet_def(m, pins);
    def.solver = WEFT_SOLVER_PCG;
    def.preconditioner = WEFT_PRECOND_BLOCK_JACOBI;
    def.newton_iterations = newton;
    def.line_search = line_search;
    return def;
}

#endif
