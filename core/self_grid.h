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

/* 0 when the grid is on and box meets no marked cell (no marked box overlaps it), else 1. */
int wc_self_grid_hits(const wc_self_grid* gr, const double* box);

#endif
