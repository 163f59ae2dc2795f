/* The 3x3 block-sparse pattern of the implicit system, fixed per model, and the per-row
 * neighbour lists that let every per-step kernel gather by rows (no atomics, no allocation).
 * Row i is particle i: its diagonal block and one block per particle that shares a spring with
 * it, columns ascending. The GPU backend uploads these same arrays.
 * Matrix values live outside the pattern: (n_blocks x 9) doubles, each block row-major. */
#ifndef WEFT_CORE_BSR_H
#define WEFT_CORE_BSR_H
#include "alloc.h"
#include "par.h"

typedef struct wc_bsr_pattern {
    int n_rows;                /* particles */
    int n_blocks;              /* stored blocks, diagonal included */
    int* row_start;            /* (n_rows + 1) blocks of row i: [row_start[i], row_start[i+1]) */
    int* col;                  /* (n_blocks) column (particle) of each block, ascending per row */
    int* diag;                 /* (n_rows) index of row i's diagonal block */
    int* transpose;            /* (n_blocks) index of block (j, i) for block (i, j) */

    /* springs incident to each row: for row i, entries [row_spring_start[i], row_spring_start[i+1]) */
    int* row_spring_start;     /* (n_rows + 1) */
    int* row_spring;           /* (2 n_springs) spring index */
    int* row_spring_block;     /* (2 n_springs) block (i, other end) of that spring in row i */
    signed char* row_spring_sign; /* (2 n_springs) +1 when i is the spring's end a, -1 for end b */

    /* triangles incident to each particle (for gathering per-triangle forces such as wind) */
    int* row_tri_start;        /* (n_rows + 1) */
    int* row_tri;              /* (3 n_tris) triangle index */
} wc_bsr_pattern;

struct wc_model;
/* Build the pattern from the model's springs and triangles. 0 on success, -1 out of memory. */
int wc_bsr_pattern_build(wc_bsr_pattern* p, const struct wc_model* m, const wc_allocator* a);
void wc_bsr_pattern_free(wc_bsr_pattern* p, const wc_allocator* a);

/* y = A x (rows in parallel). x and y are (n_rows x 3); y must not alias x. */
void wc_bsr_mul(const wc_bsr_pattern* p, const double* val, const double* x, double* y, wc_par* par);
/* y = b - A x. */
void wc_bsr_residual(const wc_bsr_pattern* p, const double* val, const double* b, const double* x,
                     double* y, wc_par* par);

#endif
