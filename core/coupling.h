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
 * A term with c = 0 is inactive (no product). The product is serial, in term order: its result
 * does not depend on the thread count. The list's capacity is fixed by its owner at creation. */
#ifndef WEFT_CORE_COUPLING_H
#define WEFT_CORE_COUPLING_H

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

#endif
