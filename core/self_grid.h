/* The dirty elements' grid: which cells of a coarse uniform grid the boxes of the dirty
 * triangles (or edges) meet, so that a clean query of the stage's later passes (self_pass.h),
 * which visits only dirty elements overlapping its box, can skip its tree walk when its box meets
 * no marked cell: it would visit nothing.
 *
 * Exact: a coordinate's cell is floor((v - lo) * inv) clamped to [0, g - 1], computed the same way
 * for the elements and the queries; each of those steps is monotone (correctly rounded operations
 * by a positive scale, the floor, the clamp), so two boxes that overlap (a common point on every
 * axis, wc_box_overlap's closed intervals) share a cell, whatever the rounding, and a position
 * outside the grid's box only lands in a border cell. A non-finite box or one spanning more than
 * WC_SELF_GRID_SPAN cells turns the grid off for the pass (every query walks its tree). */
#ifndef WEFT_CORE_SELF_GRID_H
#define WEFT_CORE_SELF_GRID_H
#include <stddef.h>

/* cells a side at most; a cloth of n triangles gets clamp(2 cbrt(n), 8, this) */
#define WC_SELF_GRID_MAX 64
/* an element's box meeting more cells than this turns the grid off for the pass */
#define WC_SELF_GRID_SPAN 512

typedef struct wc_self_grid {
    unsigned char* cell; /* (g^3) 1: a marked box meets the cell (allocated by the owner) */
    int g;               /* cells a side */
    int on;              /* 0: every query must walk (nothing marked yet, or a box too large) */
    double lo[3], inv[3];
} wc_self_grid;

/* Cells a side for a cloth of n_elements. */
int wc_self_grid_side(int n_elements);

/* Start a pass's grid over box (the tree's root box; 6 doubles): every cell clear. */
void wc_self_grid_reset(wc_self_grid* gr, const double* box);

/* Mark the cells box meets (turns the grid off when it cannot). */
void wc_self_grid_mark(wc_self_grid* gr, const double* box);

/* The cells [i0, i1] of the interval [a, b] on axis k; 0 when non-finite (inline: one test per
 * clean query of every later pass). */
static inline int wc_self_grid_cells(const wc_self_grid* gr, int k, double a, double b, int* i0, int* i1) {
    double ta = (a - gr->lo[k]) * gr->inv[k], tb = (b - gr->lo[k]) * gr->inv[k];
    if (!(ta == ta) || !(tb == tb)) return 0; /* NaN (infinities clamp) */
    double top = gr->g - 1;
    ta = ta < 0 ? 0 : (ta > top ? top : ta);
    tb = tb < 0 ? 0 : (tb > top ? top : tb);
    *i0 = (int)ta; /* >= 0: the truncation is the floor */
    *i1 = (int)tb;
    return 1;
}

/* 0 when the grid is on and box meets no marked cell (no marked box overlaps it), else 1. */
static inline int wc_self_grid_hits(const wc_self_grid* gr, const double* box) {
    if (!gr->on) return 1;
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k)
        if (!wc_self_grid_cells(gr, k, box[k], box[3 + k], lo + k, hi + k) || hi[k] < lo[k]) return 1;
    int g = gr->g;
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y) {
            const unsigned char* row = gr->cell + ((size_t)z * g + y) * g;
            for (int x = lo[0]; x <= hi[0]; ++x)
                if (row[x]) return 1;
        }
    return 0;
}

#endif
