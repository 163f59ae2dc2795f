/* Couplings of the implicit system that its block pattern has no room for: rank-one terms
 *   A += c (J^T J),   J = [w_1 n^T, ..., w_cnt n^T] on particles p_1 .. p_cnt (cnt <= 4),
 * between particles that share no spring (bsr.h: the pattern has blocks only for particles that
 * share one). Its user: the coupled penalty-pair lists (penalty_pairs.h), the self-contact pairs
 * (self_pairs.h): a cloth vertex against a triangle of another part of the same cloth, or two
 * edges, far apart on the mesh.
 *
 * Split: the terms' diagonal blocks c w_a^2 n n^T live in A itself (the owner adds them, so the
 * block-diagonal and multigrid preconditioners, and the direct solver's factor, see them); the
 * off-diagonal blocks c w_a w_b n n^T (a != b) only in products, through
 * wc_coupling_mul_offdiag_add, which the linear solvers (solve_kernels.h: wcs_mul, wcs_residual)
 * and the step's residuals add after the pattern's product. The sum is symmetric, and positive
 * semi-definite for c >= 0 (each whole term is), so the system stays SPD.
 *
 * A term with c = 0 is inactive (no product). wc_coupling_mul_offdiag_add is serial, in term
 * order; the row index below (wc_coupling_rows) runs the same product on threads with the same
 * bits. The list's capacity is fixed by its owner at creation. */
#ifndef WEFT_CORE_COUPLING_H
#define WEFT_CORE_COUPLING_H
#include "alloc.h"

typedef struct wc_coupling_term {
    int cnt;          /* particles, 2 to 4, distinct */
    int p[4];
    double w[4];      /* weights */
    double n[3];      /* unit direction */
    double c;         /* coefficient (>= 0; 0: inactive), in A's units (kg) */
} wc_coupling_term;

typedef struct wc_coupling {
    int n;                    /* terms */
    const wc_coupling_term* t;
} wc_coupling;

/* y += alpha (sum over active terms of their off-diagonal blocks) x (n x 3 arrays; c NULL: none). */
void wc_coupling_mul_offdiag_add(const wc_coupling* c, double alpha, const double* x, double* y);
/* Active terms (c > 0). */
int wc_coupling_active(const wc_coupling* c);

/* The product on threads. Pass 1 (wc_coupling_scale_terms, any split of the terms): each active
 * term's row factors alpha c w_a (sum_b w_b n.x_b - w_a n.x_a), the serial product's expression,
 * into coef[4 k + a]. Pass 2 (wc_coupling_rows_add, any split of the rows): y_i += coef n for
 * each slot of row i in ascending term order. Row i thus gets the serial product's additions, in
 * its order, with its values: y is bit-identical to wc_coupling_mul_offdiag_add's on any thread
 * count. The index depends on the terms' particles and on which are active, so it is rebuilt
 * (wc_coupling_rows_build, serial, no allocation) whenever those may have changed: the solver
 * does it at each solve's start. */
typedef struct wc_coupling_rows {
    int n_rows;       /* particles */
    int cap_terms;    /* terms the room holds */
    int* row_start;   /* (n_rows + 1) row i's slots: slot[row_start[i] .. row_start[i + 1]) */
    int* slot;        /* (4 cap_terms) 4 k + a: term k's particle a, rows ascending, then terms */
    double* coef;     /* (4 cap_terms) pass 1's factors, by 4 k + a */
} wc_coupling_rows;

/* Room for cap_terms >= 1 terms on n_rows >= 1 particles; NULL on out of memory. */
wc_coupling_rows* wc_coupling_rows_create(int n_rows, int cap_terms, const wc_allocator* a);
void wc_coupling_rows_destroy(wc_coupling_rows* r, const wc_allocator* a);
/* Indexes c's active terms. 0 (index unusable: use the serial product) when r or c is NULL, c
 * has more terms than the room or a particle outside [0, n_rows). */
int wc_coupling_rows_build(wc_coupling_rows* r, const wc_coupling* c);
/* Pass 1 for terms [k0, k1) (inactive ones skipped). */
void wc_coupling_scale_terms(const wc_coupling* c, wc_coupling_rows* r, double alpha, const double* x, int k0,
                             int k1);
/* Pass 2 for rows [i0, i1), after pass 1 of every term. */
void wc_coupling_rows_add(const wc_coupling* c, const wc_coupling_rows* r, double* y, int i0, int i1);

#endif
