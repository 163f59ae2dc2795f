/* A state array in three textures of the same layout and format. [cur] is the state, [keep]
 * the substep's start (what a rollback returns to); a pass writes only into a slot that is
 * neither (wg_ring_other), so a substep keeps its result by moving cur and drops it by moving
 * cur back: a rollback moves no data. */
#ifndef WEFT_GPU_SOLVER_RING_H
#define WEFT_GPU_SOLVER_RING_H

#include "gl_texture.h"

typedef struct wg_ring {
    wg_tex t[3];
    int cur;                    /* the state now */
    int keep;                   /* the substep's start */
} wg_ring;

static inline wg_tex* wg_ring_cur(wg_ring* r) { return &r->t[r->cur]; }

/* A slot a pass may write: neither cur nor keep (k = 0, or 1 when cur == keep gives a second). */
static inline int wg_ring_other(const wg_ring* r, int k) {
    for (int j = 0; j < 3; ++j)
        if (j != r->cur && j != r->keep && k-- == 0) return j;
    return (r->cur + 1) % 3;
}

/* The substep starts from the state now (save), or goes back to its start (restore). */
static inline void wg_ring_save(wg_ring* r) { r->keep = r->cur; }
static inline void wg_ring_restore(wg_ring* r) { r->cur = r->keep; }

#endif
