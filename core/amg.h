/* Smoothed-aggregation algebraic multigrid (Vanek, Mandel & Brezina 1996; for cloth: Tamstorf,
 * Jones & McCormick 2015) as PCG's preconditioner on the projected system
 *     P^ = S A S + a (I - S),   a_i = trace(A_ii) / 3,
 * which has the same solution in range(S) as B&W's filtered system (its null(S) part decouples;
 * the scale a_i keeps constrained rows as stiff as their neighbours, as Dirichlet rows in any
 * AMG). PCG filters what the V-cycle returns (c = S (M^-1 r + beta c)), so the preconditioner it
 * sees is S M^-1 S: symmetric, and positive definite on range(S).
 *
 * Near-null space (wc_amg_opts.rotations): the three translations per aggregate (0), or the six
 * rigid-body modes, 3 translations + 3 infinitesimal rotations (x_i - c) x e_k about the centroid
 * c (1, the default; amg_tent.c). With rotations every aggregate becomes TWO coarse 3-dof nodes
 * (2a: the first three orthonormal columns, 2a + 1: the last three), so every level stays the 3x3
 * BSR of bsr.h. The tentative prolongator is the Q of a QR per aggregate of its (3 n_agg) x 6
 * near-null block (modified Gram-Schmidt, each column twice); a column whose part orthogonal to
 * the earlier ones is below WC_AMG_DEPENDENT x its norm (a 1-node aggregate's rotations, a 2-node
 * or collinear one's rotation about its line) is dropped: that coarse unknown is "dead" (zero
 * Galerkin row and column; the setup puts the block's mean live diagonal there, so it decouples
 * and stays 0). The coarse near-null space is the R factor (the SA recursion B_l = P_tent R: node
 * 2a carries rows 0-2 of R_a, node 2a + 1 rows 3-5); coarse levels aggregate the PAIRS
 * (2a, 2a + 1) as one unit (a pair never splits; its two rows share their columns) and smooth
 * with a 6x6 block diagonal per pair (pair_blocks), whose translation-rotation coupling 3x3
 * blocks miss.
 * The rotations are taken about the CURRENT positions (current_positions; wc_amg.pos, the state's
 * x via wc_solver_set_positions): every setup redoes the QR, allocating nothing; a solver with no
 * positions (tests, benchmarks) uses the rest positions' P_tent built at wc_amg_create.
 *
 * Couplings outside the pattern (coupling.h: the self-contact pairs between layers that share no
 * spring; amg_cross.c, wc_amg_cross): the hierarchy carries them as one sparse vector per term and
 * level (or, on a small coarse level, one dense matrix), so every level's operator is the
 * Galerkin product of the whole system's, not of its pattern's.
 *
 * Built once per model (wc_amg_create, pattern only; the GPU backend uploads these flat arrays):
 *   - aggregates per level (greedy, Vanek's three phases) over the "strong" graph: on the finest
 *     level the stretch and shear springs (bend springs, two edges apart, are lumped onto the
 *     diagonal when the prolongator is smoothed), on coarse levels every block;
 *   - the smoothed prolongator's pattern (row i: the coarse nodes of the aggregates of i's strong
 *     neighbours and its own), its transpose, the pattern of T = P^ P and of the Galerkin
 *     operator P^T P^ P; with rotations the aggregates' node lists and P_tent about the rest
 *     positions.
 * Rebuilt by every solve (wc_amg_setup, no allocation): the projected fine operator, the block
 * diagonals' inverses, the largest eigenvalue of D^-1 P^ per level (Lanczos from a fixed start,
 * wc_amg_opts.power_iterations steps on the finest level and WC_AMG_COARSE_LANCZOS on the others,
 * times WC_AMG_SAFETY; amg_eigen.c; while wc_amg.hold_bounds is set, a setup may reuse the last
 * fresh estimates instead: wc_amg_opts.bound_reuse; while wc_amg.carry_bounds is, an earlier
 * substep's: wc_amg_opts.bound_carry), the smoothed prolongator
 * P = (I - omega_p D^-1 P^_F) P_tent (P^_F: weak blocks lumped onto the diagonal), the Galerkin
 * operators and the coarsest level's dense Cholesky factor.
 * Applied (wc_amg_apply): one symmetric V-cycle, Chebyshev smoothing (a degree-2 polynomial in
 * D^-1 A, the same before and after the coarse correction), an exact solve on the coarsest level;
 * the levels' operators and prolongators read from float copies made by the setup
 * (wc_amg_opts.single, amg_single.c), summed in double.
 * The eigenvalue must be estimated, not bounded (a Gershgorin bound leaves the smoother doing
 * nothing), and must not fall short (the Chebyshev smoother then amplifies the modes above its
 * bound and the V-cycle turns indefinite). Every kernel runs over rows (or pairs) in parallel with
 * no reduction, and the per-solve QR serially: the result does not depend on the thread count.
 * Why these choices, and what they cost: docs/design/multigrid.md. */
#ifndef WEFT_CORE_AMG_H
#define WEFT_CORE_AMG_H
#include "diag.h"
#include "filter.h"
#include "model.h"
#include "par.h"
#include "vec3.h"

#define WC_AMG_MAX_LEVELS 12
#define WC_AMG_COARSE_SWEEPS 4
#define WC_AMG_CHUNK 256        /* rows per partial sum */
#define WC_AMG_SAFETY 1.1       /* lambda_max estimate = this x the Lanczos Ritz value (or the power
                                   iterations' Rayleigh quotient): both are lower bounds */
#define WC_AMG_COARSE_POWER 30  /* lanczos 0: power iterations on the coarse levels (the finest takes
                                   wc_amg_opts.power_iterations): fewer fall short of lambda_max on
                                   the 6x6-pair levels; coarse levels are small, so 30 cost little */
#define WC_AMG_COARSE_LANCZOS 12 /* Lanczos steps on the coarse levels (the default estimator,
                                   amg_eigen.c): closer to lambda_max than WC_AMG_COARSE_POWER
                                   power iterations, at a fraction of their cost */
/* Seams (sew.h) between a vertex and a point of an edge couple three particles: for that
 * block, w^T D^-1 w = 3 where a spring's is 2, so D^-1 A has eigenvalues up to 3/2 of the spring
 * network's in modes local to the seams, which power iterations from a spread start
 * underestimate. With the power method (lanczos 0) the finest level's bound is raised by this
 * factor when the model has such seams; Lanczos (the default, amg_eigen.c) finds those modes. */
#define WC_AMG_SEAM_BOUND 1.5
/* The finest level's Lanczos steps (or power iterations) when it holds couplings (amg_cross.c):
 * a vertex-triangle term spreads over four particles, so D^-1 A has modes up to 4 where a spring
 * network's stop at 2, local to the contacts, which 6 steps from a spread start miss. */
#define WC_AMG_CROSS_LANCZOS 12
/* A coarse level with at most this many unknowns holds its couplings as one dense matrix
 * (wc_amg_cross.dense; 8 MB at most). */
#define WC_AMG_CROSS_DENSE_DOFS 1024
#define WC_AMG_MAX_LANCZOS 64   /* Lanczos steps at most (the tridiagonal's size) */
/* A near-null column whose part orthogonal to the aggregate's earlier columns is below this x
 * its own norm is dropped from the tentative prolongator (amg_tent.c). */
#define WC_AMG_DEPENDENT 1e-6

/* The setup's phases, timed per solve (wc_amg.phase_ms): the per-aggregate QR about the current
 * positions (amg_tent.c), the projected fine operator, the block-diagonal inverses, the power
 * iterations on the finest and on the coarse levels, the smoothed prolongators, T = A P, the
 * Galerkin products P^T T (with the dead unknowns' diagonal), the coarsest factor, the couplings
 * restricted level by level (amg_cross.c; the coarsest's dense part is in its factor's), the
 * V-cycle's float copies (amg_single.c) and merged operators (amg_merge.c). */
typedef enum wc_amg_phase {
    WC_AMG_PHASE_TENT,
    WC_AMG_PHASE_PROJECT,
    WC_AMG_PHASE_DIAGONAL,
    WC_AMG_PHASE_EIGEN_FINE,
    WC_AMG_PHASE_EIGEN_COARSE,
    WC_AMG_PHASE_PROLONG,
    WC_AMG_PHASE_AP,
    WC_AMG_PHASE_PTAP,
    WC_AMG_PHASE_COARSE_FACTOR,
    WC_AMG_PHASE_CROSS,
    WC_AMG_PHASE_SINGLE,
    WC_AMG_PHASES
} wc_amg_phase;
const char* wc_amg_phase_name(wc_amg_phase p);

typedef struct wc_amg_opts {
    int coarse_max;             /* nodes at which coarsening stops (dense Cholesky there): 96 */
    int sweeps;                 /* smoothing steps (matrix products) before and after the coarse
                                   correction: 2 */
    int chebyshev;              /* 1: the smoothing steps are a Chebyshev polynomial in D^-1 A on
                                   [lambda_max / chebyshev_ratio, lambda_max] (default); 0: weighted
                                   Jacobi */
    double chebyshev_ratio;     /* 10 */
    double smooth_weight;       /* smoother weight x 1 / lambda_max(D^-1 A): 1.0 */
    double prolong_weight;      /* prolongator smoothing weight x 1 / lambda_max (4/3; 0:
                                   unsmoothed aggregation) */
    int power_iterations;       /* the finest level's eigenvalue estimate: Lanczos steps or
                                   power iterations per solve (6) */
    int rotations;              /* 1: near-null space = 6 rigid-body modes per aggregate (two
                                   coarse nodes per aggregate, see above); 0: 3 translations */
    int pair_blocks;            /* with rotations: 1: the smoother's block diagonal on coarse
                                   levels is 6x6 per pair (2a, 2a + 1) (default); 0: 3x3 per node */
    int aggressive;             /* 1: the finest level's aggregates are aggregated once more
                                   (aggregates of aggregates, ~40-50 particles each); 0 (default) */
    int current_positions;      /* with rotations: 1 (default): every setup rebuilds P_tent and
                                   the R factors about wc_amg.pos when set; 0: rest positions only */
    int lanczos;                /* lambda_max(D^-1 A) per level (amg_eigen.c): 1 Lanczos (default), 0
                                   power iterations */
    int coarse_iterations;      /* the coarse levels' Lanczos steps or power iterations per solve;
                                   0 (default): WC_AMG_COARSE_LANCZOS, or WC_AMG_COARSE_POWER */
    int couplings;              /* 1 (default): the solver's couplings outside the pattern (coupling.h)
                                   are carried through the hierarchy (wc_amg_set_coupling,
                                   amg_cross.c); 0: the hierarchy is A's pattern's alone */
    int cross_dense_dofs;       /* a coarse level with at most this many unknowns holds its couplings
                                   as one dense matrix (wc_amg_cross.dense): WC_AMG_CROSS_DENSE_DOFS
                                   (0: term lists on every level, tests) */
    int bound_reuse;            /* while wc_amg.hold_bounds is set, up to this many setups in a row
                                   skip the eigenvalue estimates and take the last fresh setup's
                                   per level x bound_margin (the Galerkin products are still
                                   redone); 0: every setup estimates (see wc_amg.hold_bounds) */
    int bound_carry;            /* while wc_amg.carry_bounds is set (a substep's first solve), up
                                   to this many full setups in a row take the estimates of an
                                   earlier substep's fresh setup (as they are; the Newton solves
                                   that hold them x bound_margin) instead of estimating: one Lanczos run in bound_carry + 1 substeps (the
                                   estimates are state: wc_amg_bounds_get/set, the snapshots'
                                   history); 0: every substep's first solve estimates (7) */
    double bound_margin;        /* >= 1: a reused estimate x this (the matrix may have stiffened
                                   since; a bound above lambda_max only weakens the smoother) */
    int values;                 /* 1 (default): the arrays a setup and a V-cycle fill; 0: the
                                   patterns and aggregates only (wc_amg_setup and wc_amg_apply must
                                   not be called): what the GPU's multigrid uploads (gpu/solver/
                                   wg_amg.h), in a fraction of the memory and time */
    int single;                 /* 1 (default): the V-cycle reads single-precision copies of what it
                                   reads most, every level's operator and prolongator (made by each
                                   setup from its double values, which the setup itself and PCG's
                                   product keep using; amg_single.c), summing in double; 0: the
                                   double values. Rounding a symmetric operator entry by entry keeps
                                   it symmetric, so the V-cycle stays SPD. Half the V-cycle's bytes,
                                   a third less PCG time from 4k particles on
                                   (docs/bench/cpu_levers_sheet32.md) */
    int single_x;               /* 1 (default): with single, and where the CPU has AVX2 + FMA, the
                                   row products read the iterates rounded to float (wc_amg_level.xf,
                                   written beside x) and sum in float (wc_bsr_rows_fx): half the
                                   kernel's instructions; the V-cycle is then symmetric to float's
                                   rounding, not exactly (docs/bench/vcycle_float.md). 0: double
                                   iterates and sums */
    int single_setup;           /* 1 (default): with single, on the pair levels and where the CPU has
                                   AVX2 + FMA, the smoothed prolongator and the Galerkin products
                                   T = A P and P^T T in float from the float copies, 8 lanes
                                   (amg_setup_f.c): P and the next level's operator are made in float
                                   (the V-cycle's copies) and widened for the setup's double work; 0:
                                   in double, then rounded (docs/bench/amg_setup_float.md) */
    int smooth_vector;          /* 1 (default): the Chebyshev smoother's node updates in AVX2 where
                                   the CPU has it (amg_smooth.c; the scalar loops' bits); 0: the
                                   scalar loops */
} wc_amg_opts;

wc_amg_opts wc_default_amg_opts(void);

/* The couplings outside the pattern (coupling.h: the self-contact pairs) on one level of the
 * hierarchy (core/amg_cross.c). Level l's whole operator is F_l = B_l + sum_k c_k v_k v_k^T: B_l
 * the level's BSR operator (level 0: the projected A without the couplings' diagonal blocks;
 * below: the Galerkin products of B) and v_k one sparse vector per held term (level 0:
 * sum_a w_a S_a n over the term's particles, the filter applied as the projected operator applies
 * it; level l + 1: P_l^T v_k at level l). So F_{l+1} = P_l^T F_l P_l exactly: the multigrid of
 * the whole system, not of its pattern. The smoother's block diagonal is F's (B's plus dadd). A
 * term that does not fit in a level's entries is held by none below (wc_amg.cross_dropped). */
typedef struct wc_amg_cross {
    int cap_terms;              /* terms at most (wc_amg_set_coupling's capacity) */
    int cap_entries;            /* entries at most */
    int n_terms;                /* held by this level (a prefix of the level above's) */
    int n_entries;
    double* c;                  /* (cap_terms) */
    int* start;                 /* (cap_terms + 1) term k's entries */
    int* node;                  /* (cap_entries) */
    double* val;                /* (cap_entries x 3) */
    double* dense;              /* (3n x 3n) a small level (3n <= WC_AMG_CROSS_DENSE_DOFS, below level
                                   0): sum_k c_k v_k v_k^T summed, no entries (on a small level the
                                   terms' vectors hold more entries than the matrix); the levels
                                   below a dense one get theirs by the dense Galerkin product
                                   P^T X P */
    double* gal;                /* (3 n_above x 3n) that product's X P, when the level above is dense */
    int dense_sym;              /* 1: dense is symmetric to the bit (restrict_dense copies its upper
                                   triangle into the lower; not the Galerkin product's): its products
                                   read it by columns (wc_amg_cross_dense_rows) */
    double* dadd;               /* (n x 9 x group) the terms' part of the block diagonal, laid out as
                                   Dinv (a pair level: node i's blocks to i & ~1 and i | 1) */
    double* s;                  /* (cap_terms) a product's alpha c_k (v_k . x) */
    int* node_start;            /* (n + 1) list levels: each node's entries, in term order, for the */
    double* node_val;           /* (cap_entries x 3) products' gather (parallel, no reduction: the */
    int* entry_term;            /* (cap_entries) same result on any thread count), rebuilt per setup:
                                   the entries' values copied in node order, so that the gather
                                   reads them in sequence (only s is read at random) */
    int cap_blocks;             /* list levels below the finest: the summed form's blocks at most */
    int n_blocks;               /* > 0: this setup's terms also summed into one block-sparse matrix
                                   X = sum_k c_k v_k v_k^T (rows in blk_start, columns ascending),
                                   which the products read instead of the terms: where they overlap
                                   it is fewer operations and no scaling pass (the dance's second
                                   level: 171k blocks for 546k entries); 0: the terms (the finest
                                   level, or it did not fit, or would cost more) */
    int* blk_start;             /* (n + 1) */
    int* blk_col;               /* (cap_blocks) */
    double* blk_val;            /* (cap_blocks x 9) */
    int* blk_pos;               /* (WC_PAR_MAX_THREADS x n) per thread: -1, or a column's block in
                                   the row it sums (sum_blocks; 64 n ints: the dance's second
                                   level, 3.8k nodes, 1 MB beside its 36 MB of blocks) */
    int* blk_stage;             /* (cap_blocks) the rows' columns, ascending, each row where its
                                   thread claimed room (sum_blocks: found once, then copied into
                                   blk_col after the rows' prefix sum; 1.9 MB on the dance) */
    int* blk_stage_at;          /* (n) row i's columns' offset in blk_stage (-1: out of room) */
    int cap_merged;             /* the merged operator's blocks at most (0: never merged) */
    int m_blocks;               /* > 0: this setup's whole operator F = B + X as one float BSR
                                   matrix (amg_merge.c: m_start, m_col ascending, m_val_f, each
                                   block B_ik + X_ik summed in double, then rounded), which the
                                   V-cycle's residuals read in one pass of rows, no scaling pass
                                   and no barrier before it; 0: B's rows and X's products */
    int* m_start;               /* (n + 1) */
    int* m_col;                 /* (cap_merged) */
    float* m_val_f;             /* (cap_merged x 9 + WC_BSR_F_PAD) */
    int* m_pos;                 /* (WC_PAR_MAX_THREADS x n) level 0: per thread, -1 or a column's
                                   place in the row it merges */
    double* m_acc;              /* (WC_PAR_MAX_THREADS x WC_AMG_MERGE_ROW x 9) level 0: per thread,
                                   the row's blocks summed in double */
    double* y;                  /* (n x 3) the product X w in the eigenvalue estimate */
    double* acc;                /* (WC_PAR_MAX_THREADS x n x 3) the restriction's accumulator, one
                                   per thread, zero between terms */
    int* touched;               /* (WC_PAR_MAX_THREADS x n) also sum_blocks' row of columns */
    unsigned char* mark;        /* (WC_PAR_MAX_THREADS x n) */
    int* reach;                 /* (cap_terms) a list level below the finest: the nodes the
                                   restriction of the level above's term q touched (the room test) */
    int stage_terms;            /* a dense level below a list level: terms per batch of its
                                   restriction (restrict_dense; at most the room, stage_cap) */
    int stage_cap;              /* WC_AMG_CROSS_STAGE_ENTRIES / n, at least 1 */
    int* stage_n;               /* (2 x stage_cap) a batch's restricted terms: their nodes touched */
    int* stage_node;            /* (2 x stage_cap x n) their nodes, ascending, at n per term */
    double* stage_val;          /* (2 x stage_cap x n x 3) P^T v_q at those nodes (two batches:
                                   one staged while the threads add the other's rows) */
} wc_amg_cross;

/* 1: the level's products read its couplings as terms (scaled first: wc_amg_cross_scale, then
 * gathered per node); 0: as one dense matrix or as summed blocks. */
static inline int wc_amg_cross_as_terms(const wc_amg_cross* X) { return !X->dense && X->n_blocks == 0; }

typedef struct wc_amg_level {
    int n;                      /* nodes (3 unknowns each) */
    int n_blocks;
    const int* row_start;       /* (n + 1) BSR pattern; level 0 borrows the model's */
    const int* col;             /* (n_blocks) */
    const int* diag;            /* (n) */
    int *own_row_start, *own_col, *own_diag; /* storage of the pattern on coarse levels */
    unsigned char* strong;      /* (n_blocks) level 0: 1 for blocks of stretch/shear springs and
                                   the diagonal; NULL: every block is strong */
    double* val;                /* (n_blocks x 9) the level's operator */
    double* Dinv;               /* (n x 9 x group) inverse block diagonal: group 2: node i's 3 rows
                                   of its pair's 6x6 inverse (blocks to nodes i & ~1, i | 1) */
    double* DinvT;              /* (n x 12 x group) or NULL: Dinv's blocks by columns, 4 doubles a
                                   column (lane 3 zero), for the AVX2 smoother (amg_smooth.c) */
    int* pair_blk;              /* (n) group 2: block (i, i ^ 1) in row i (rows 2a and 2a + 1
                                   have the same columns) */
    int* mirror;                /* (n_blocks) group 2 with single_setup: the slot of block
                                   (col, row), each block's transpose (amg_setup_f.c's mirror) */
    double bound;               /* estimate of the largest eigenvalue of D^-1 A (per solve) */
    double estimate;            /* the last fresh estimate (before WC_AMG_SAFETY), what a setup
                                   that reuses bounds scales (wc_amg_opts.bound_reuse) */
    double* ev;                 /* (n x 3) the power iterations' vector */
    double* partial;            /* (ceil(n / 256) x 3) per-chunk partial sums (thread-count free) */
    double *x, *r, *t;          /* (n x 3) V-cycle vectors */
    double* ev_scratch;         /* (n x 3) Chebyshev smoothing's update direction */
    float* val_f;               /* (n_blocks x 9 + WC_BSR_F_PAD) with opts.single: val rounded */
    int f_fresh;                /* with single_setup: bit 0, val_f holds this setup's val; bit 1,
                                   p_val_f this setup's p_val (made by amg_setup_f.c; the float
                                   copies skip them and clear the bits) */
    float* xf;                  /* (n x 4) with opts.single_x: x rounded to float, the 4th float 0 */

    int group;                  /* nodes per aggregation unit: 2 on coarse levels with rotations
                                   (the pair 2a, 2a + 1 of one fine aggregate), else 1 */
    double* nns;                /* (n x 2 x 9) with rotations: each node's 3 x 6 near-null rows as
                                   two 3x3 blocks (translation columns, rotation columns); m on
                                   level 0, R factors' rows below; NULL without rotations */
    unsigned char* dead;        /* (n x 3) with rotations, levels >= 1: 1 for a dropped unknown */
    int unit_translations;      /* 1 when nns's translation columns are exactly e_0, e_1, e_2 at
                                   every node (wc_amg_rigid_modes, level 0): the QR skips their
                                   exactly-zero products (amg_tent.c) */

    /* the prolongator to level + 1 (none on the coarsest level) */
    int* agg;                   /* (n) aggregate of each node */
    int cpa;                    /* coarse nodes per aggregate: 2 with rotations, else 1; coarse
                                   node cpa x agg + q */
    int* agg_start;             /* (n_agg + 1) with rotations: the nodes of each aggregate */
    int* agg_node;              /* (n) */
    double* tent;               /* (n x cpa x 9) with rotations: P_tent's 3x3 blocks of row i, to
                                   coarse nodes cpa agg(i) + q; NULL: P_tent = identity blocks */
    float* tent_f;              /* (n x 18 + WC_BSR_F_PAD) with cpa 2 and single_setup: tent rounded
                                   by each QR (amg_tent.c), what amg_setup_f.c's P reads */
    int* p_start;               /* (n + 1) */
    int* p_col;                 /* (nnz_p) coarse nodes, ascending per row */
    int* p_self;                /* (n) entry of coarse node cpa agg(i) in row i */
    int* a_to_p;                /* (n_blocks) entry of cpa agg(col) in row i for strong blocks, -1
                                   weak (the entries of cpa agg(col) + q follow it) */
    double* p_val;              /* (nnz_p x 9) */
    float* p_val_f;             /* (nnz_p x 9 + WC_BSR_F_PAD) with opts.single: p_val rounded */
    int* pt_start;              /* (n_next + 1) transpose: for each coarse node the entries of P */
    int* pt_entry;              /* (nnz_p) entry index into p_col/p_val, rows ascending */
    int* pt_row;                /* (nnz_p) the fine row of that entry */
    int* t_start;               /* (n + 1) pattern of T = A P */
    int* t_col;                 /* (nnz_t) */
    double* t_val;              /* (nnz_t x 9) */
    float* t_val_f;             /* (nnz_t x 9 + WC_BSR_F_PAD) with single and cpa 2: T in float
                                   (single_setup) */
    /* with cpa 2, the Galerkin products as gathers (amg_build.c, galerkin_lists): each output slot
       pair's products listed in the order the row walks meet them, so a slot is summed in
       registers and stored once (no zeroing, no per-product load and store), bit for bit the
       sums of the walk; and T's slots that P^T T never reads are not computed */
    int* t_read;                /* (n) first slot of T's row i that P^T T reads: its columns from
                                   row i's first P column on (the upper half's products) */
    int* ap_start;              /* (nnz_t / 2 + 1) T's slot pair s / 2: its products ap_src[2 m..] */
    int* ap_src;                /* (2 x products) A's block k and P's entry e (the pair e, e + 1) */
    int* ptap_start;            /* (n_blocks of the next level / 2 + 1) the next level's slot pair
                                   s / 2 of a row 2a at a column >= 2a (other rows: empty): its
                                   products ptap_src[2 m..] */
    int* ptap_src;              /* (2 x products) P's entry of (i, 2a) (its pair: (i, 2a + 1)) and
                                   T's slot (i, J) of the products P(i, .)^T T(i, J), P^T's order */
    int* pr_start;              /* (nnz_p / 2 + 1) P's entry pair e / 2: the strong blocks k of A's
                                   row whose aggregate it is (a_to_p[k] = e), pr_src[m..] ascending:
                                   the smoothed prolongator's sums A_ik P_tent(k) (amg_setup.c) */
    int* pr_src;                /* (strong blocks) */
    wc_amg_cross* cross;        /* the couplings on this level (NULL: none set) */
} wc_amg_level;

typedef struct wc_amg {
    wc_allocator alloc;
    wc_amg_opts opts;
    int n_levels;
    wc_amg_level lev[WC_AMG_MAX_LEVELS];
    int coarse_dense;           /* 1: the coarsest level is solved by its dense Cholesky factor; 0
                                   (it could not be coarsened below 8 x coarse_max nodes: a cloud of
                                   disconnected pieces): COARSE_SWEEPS block-Jacobi sweeps */
    int coarse_dofs;            /* 3 x nodes of the coarsest level when dense, else 0 */
    double* coarse_L;           /* (coarse_dofs^2) dense Cholesky factor L L^T, stored as U = L^T
                                   in the upper triangle, row-major: L[i][k] = coarse_L[k d + i]
                                   for i >= k (amg_dense.c); below the diagonal is scratch */
    double* coarse_y;           /* (coarse_dofs) */
    double setup_ms;            /* of the last wc_amg_setup */
    double phase_ms[WC_AMG_PHASES]; /* CPU time (wc_cpu_ms: all threads, load-independent) per
                                   setup phase (wc_amg_phase), summed over every wc_amg_setup since
                                   creation (tests/bench/bench_amg_setup) */
    long setups;                /* wc_amg_setup calls since creation */
    double fine_bound_scale;    /* with the power method (lanczos 0), the finest level's lambda_max
                                   bound x this: WC_AMG_SEAM_BOUND
                                   with three-point seams (sew.h), else 1 */
    const struct wc_coupling* coupling; /* borrowed (wc_amg_set_coupling; NULL: none) */
    long cross_dropped;         /* terms left out of a coarse level (its entries were full), summed
                                   over every setup */
    int cross_terms[WC_AMG_MAX_LEVELS]; /* terms each level held at the last setup (a stat: fewer
                                   than the active terms where some did not fit) */
    int hold_bounds;            /* set by the caller around solves whose matrices are close (a
                                   substep's Newton solves after its first): while set, setups
                                   reuse the estimates (wc_amg_opts.bound_reuse); 0: every setup
                                   estimates afresh (or carries: carry_bounds) */
    int hold_coarse;            /* set by the caller around solves whose systems differ from the
                                   last one's in a few rows (a substep's friction passes: contacts
                                   that stop sticking): while set, a setup refreshes the finest
                                   level only (its projected operator, block diagonal and couplings,
                                   with the last fresh bound x bound_margin) and keeps the coarse
                                   levels and prolongators of the last full setup. The V-cycle stays
                                   SPD (a convergent smoother plus an SPD coarse correction), so PCG
                                   stays correct; a solve that fails on it is redone fresh */
    int coarse_kept;            /* 1: the last setup kept the coarse levels (hold_coarse) */
    long coarse_keeps;          /* setups that kept the coarse levels (a stat) */
    int bound_age;              /* setups that reused the estimates since the last fresh one */
    int carry_bounds;           /* set by the caller around a substep's first solve: its full setup
                                   may take the estimates of an earlier substep's fresh setup
                                   (wc_amg_opts.bound_carry), level by level, where est_valid and
                                   the level holds couplings (amg_cross.c) as it did then (a level
                                   that gained or lost them has other modes and Lanczos steps: it
                                   estimates afresh); the Newton solves that follow hold_bounds on
                                   what it took. Such a solve depends on the substep where the
                                   estimates were made: they are state (wc_amg_bounds_get) */
    int carry_age;              /* setups that carried the estimates since the last fresh one */
    int est_valid;              /* 1: every estimating level's `estimate` is a fresh setup's since
                                   the last wc_amg_bounds_invalidate */
    unsigned est_terms;         /* bit l: level l held couplings when it last estimated */
    long carried;               /* setups that carried the estimates (a stat) */
    int bounds_reused;          /* 1: the last setup reused the estimates */
    long bound_fallbacks;       /* solves that failed on reused bounds and were redone with a
                                   fresh setup (solve_pcg.c) */
    const double* pos;          /* (n x 3) m, borrowed: with rotations and current_positions, the
                                   positions every setup takes the rotations about (the state's
                                   x, wc_solver_set_positions); NULL: the rest positions' P_tent
                                   from wc_amg_create. What it yields (P_tent, R, dead) is derived
                                   per solve from the state: snapshots hold nothing of it */
    double* tent_pos;           /* (n x 3) with rotations and current_positions: the positions the
                                   current P_tent, R and dead were built from; a setup whose pos
                                   holds the same bits (a substep's Newton and friction solves
                                   share the substep's x) keeps them: the same function of the
                                   same input, so bit-identical to rebuilding */
    int tent_valid;             /* 1: tent_pos describes the current P_tent */
    long tent_kept;             /* setups that kept P_tent (a stat) */
} wc_amg;

/* The estimates a setup may carry to later substeps (carry_bounds), as state: get fills valid,
 * age, the estimating levels' terms mask and est[WC_AMG_MAX_LEVELS] (the levels' `estimate`, 0
 * past n_levels); set puts them back (the same hierarchy; valid 0 or a bad value: none, so the
 * next setup estimates); invalidate drops them (a rollback, a reset). */
typedef struct wc_amg_bounds {
    int valid, age;
    unsigned terms;
    double est[WC_AMG_MAX_LEVELS];
} wc_amg_bounds;
void wc_amg_bounds_get(const wc_amg* a, wc_amg_bounds* b);
void wc_amg_bounds_set(wc_amg* a, const wc_amg_bounds* b);
void wc_amg_bounds_invalidate(wc_amg* a);

/* The hierarchy's patterns for this model (no values). */
wc_status wc_amg_create(wc_amg** out, const wc_model* m, const wc_amg_opts* opts, const wc_allocator* alloc,
                          wc_diag* diag);
void wc_amg_destroy(wc_amg* a);

/* The values for one system: A (model pattern, n_blocks x 9) under filter f. */
void wc_amg_setup(wc_amg* a, const double* A, const wc_filter* f, wc_par* par);
/* z = M^-1 r (one V-cycle); r and z are (n x 3) and may not alias. */
void wc_amg_apply(wc_amg* a, const double* r, double* z, wc_par* par);

/* Carry the couplings outside the pattern (coupling.h) through the hierarchy from the next setup
 * on (amg_cross.c): room for `capacity` active terms, allocated here (no allocation in a setup);
 * NULL detaches them (the multigrid of A's pattern alone). */
struct wc_coupling;
wc_status wc_amg_set_coupling(wc_amg* a, const struct wc_coupling* c, int capacity, wc_diag* diag);

/* Operator complexity (sum of blocks over levels / fine blocks) and grid complexity. */
double wc_amg_operator_complexity(const wc_amg* a);
double wc_amg_grid_complexity(const wc_amg* a);

/* ---- private to amg_*.c ---- */
/* Level 0's near-null rows (rest positions about their centroid), L's tentative prolongator
 * (QR per aggregate, amg.h) and N's near-null rows (the R factors) and dead unknowns; the
 * arrays are allocated by the caller. The aggregates on par's threads (NULL: serial). */
void wc_amg_tentative(wc_amg_level* L, wc_amg_level* N, int n_agg, wc_par* par);
/* The same, serial and one aggregate at a time (the reference the four-lane path is held to). */
void wc_amg_tentative_scalar(wc_amg_level* L, wc_amg_level* N, int n_agg);
void wc_amg_rigid_modes(wc_amg_level* L, const double* rest_pos);
/* The power iterations' start: pseudo-random signs and sizes, the same for every solve (so a
 * solve depends on its system only: snapshots restore bit-exactly). */
void wc_amg_start_vector(double* v, int n);
/* The same vector's rows [lo, hi) only (a thread's share). */
void wc_amg_start_vector_rows(double* v, int lo, int hi);
/* lambda_max(D^-1 A) of level L's values (amg_eigen.c): Lanczos (use_lanczos) or power
 * iterations, `steps` of them, from wc_amg_start_vector; a lower bound (0 when none was found).
 * Overwrites L's ev, x, t, ev_scratch and partial. */
double wc_amg_eigen_estimate(wc_amg_level* L, int steps, int use_lanczos, int pair_blocks, wc_par* par);
/* The couplings' values for one setup (amg_cross.c): level 0's from the coupling under filter f
 * (after project_fine: it also takes their diagonal blocks out of level 0's BSR values into
 * dadd), level l + 1's from level l's through P_l (after its prolongator), the coarsest's into its
 * dense matrix M (d x d, row-major); y += alpha X x on one level of n nodes (in parallel over
 * terms, then over nodes or rows; the same on any thread count). */
void wc_amg_cross_fine(wc_amg* a, const wc_filter* f);
void wc_amg_cross_restrict(wc_amg* a, int l, wc_par* par);
void wc_amg_cross_dense(const wc_amg_cross* X, double* M, int d);
void wc_amg_cross_mul_add(const wc_amg_cross* X, double alpha, const double* x, double* y, int n, wc_par* par);
/* Its two parts, for a caller's own parallel region (any split gives the same bits): a list
 * level's s_k = alpha c_k (v_k . x) for terms [q0, q1), then, once every term's s_k is in (a
 * barrier), y += X x on nodes [lo, hi) (a dense level: alpha X x directly, no first part). */
void wc_amg_cross_scale(const wc_amg_cross* X, double alpha, const double* x, int q0, int q1);
void wc_amg_cross_rows_add(const wc_amg_cross* X, double alpha, const double* x, double* y, int n, int lo, int hi);
/* A dense level's rows [r0, r1) of y += alpha X x (d = 3n unknowns), each a scalar sum over k
 * ascending: vec (wc_amg_cross_dense_vec(): AVX) reads a bit-symmetric X by columns, 16 rows at
 * a time, with the same bits as the scalar rows. */
int wc_amg_cross_dense_vec(void);
void wc_amg_cross_dense_rows(const wc_amg_cross* X, int d, double alpha, const double* x, double* y, int r0, int r1,
                             int vec);
void wc_amg_cross_destroy(wc_amg* a);
/* Row i's distinct term columns not yet marked -2 - i in pos, marked so (amg_cross.c). */
int wc_amg_cross_count_row(const wc_amg_cross* X, int i, int* pos);
/* The merged operator's longest row on level 0 (blocks; a longer row leaves the level unmerged). */
#define WC_AMG_MERGE_ROW 256
/* Level l's whole operator F = B + X merged into one float BSR matrix (amg_merge.c, after the
 * setup's float copies; wc_amg_cross.m_blocks); left unmerged (m_blocks 0) without the float
 * V-cycle, without terms, on a dense level, or when it does not fit. */
void wc_amg_cross_merge(wc_amg* a, int l, wc_par* par);
/* The coarsest level's dense factor (amg_dense.c): M (d x d, row-major) holds the operator on
 * entry, its lower triangle read; on return the factor, as coarse_L above. A pivot that is not
 * positive (below 1e-14 x the largest diagonal) gets 1 and its row and column of L are zeroed: that
 * unknown is decoupled. vec: the AVX path (wc_amg_dense_vec()), the same bits as the scalar one. */
int wc_amg_dense_vec(void);
void wc_amg_dense_factor(double* M, int d, int vec);
/* x = L^-T L^-1 r with the factor above; y: d doubles of scratch (r, y and x distinct) */
void wc_amg_dense_solve(const double* M, int d, const double* r, double* y, double* x, int vec);
/* With opts.single, the V-cycle's float copies of a setup's values (amg_single.c): every level's,
 * or level 0's operator only (fine_only: the coarse levels were kept). */
void wc_amg_single_copies(wc_amg* a, int fine_only, wc_par* par);
/* f = d rounded to float, n values, over par's threads (amg_single.c). */
void wc_amg_round(const double* d, float* f, size_t n, wc_par* par);
/* With single_setup, the Galerkin products of pair level L in float (amg_setup_f.c): 1 when it
 * ran (L->val_f and p_val_f made first unless fresh; N->val_f whole and symmetric, N->val its
 * widening, both bits of N->f_fresh's bit 0 set), 0 when this level or CPU does not take it (the
 * caller then runs the double products); its time goes to the phases AP (with the rounding of A
 * and P) and PTAP. The dead unknowns' diagonal is the caller's. */
/* With single_setup, level L's smoothed prolongator in float (amg_setup_f.c; L->val_f made first
 * unless fresh): p_val_f, and p_val its widening; 1 when it ran, 0 when the caller is to run the
 * double one (no P_tent, weight 0, no AVX2 + FMA). */
int wc_amg_prolongator_f(wc_amg* a, wc_amg_level* L, double w, wc_par* par);
int wc_amg_galerkin_f(wc_amg* a, wc_amg_level* L, wc_amg_level* N, wc_par* par);
/* Index of column c in BSR row [lo, hi) of col (ascending), -1 when absent. */
static inline int wc_amg_find(const int* col, int lo, int hi, int c) {
    int end = hi;
    while (lo < hi) {
        int mid = (lo + hi) >> 1;
        if (col[mid] < c) lo = mid + 1;
        else hi = mid;
    }
    return (lo < end && col[lo] == c) ? lo : -1;
}

/* dw += (D w)_i, D the smoother's block diagonal: the BSR diagonal block (and, on a pair level
 * with pair_blocks, the pair's other block) plus the couplings' part (wc_amg_cross.dadd). */
static inline void wc_amg_d_mulv_add(const wc_amg_level* L, int i, int pair_blocks, const double* w, double* dw) {
    m3_mulv_add(dw, L->val + 9 * (size_t)L->diag[i], w + 3 * (size_t)i);
    if (L->group == 2 && pair_blocks) m3_mulv_add(dw, L->val + 9 * (size_t)L->pair_blk[i], w + 3 * (size_t)(i ^ 1));
    if (!L->cross || L->cross->n_terms == 0) return;
    const double* Da = L->cross->dadd + 9 * (size_t)L->group * i;
    if (L->group == 1) {
        m3_mulv_add(dw, Da, w + 3 * (size_t)i);
    } else {
        m3_mulv_add(dw, Da + 9 * (i & 1), w + 3 * (size_t)i);
        if (pair_blocks) m3_mulv_add(dw, Da + 9 * ((i & 1) ^ 1), w + 3 * (size_t)(i ^ 1));
    }
}

/* The Chebyshev smoother's node updates on [lo, hi) (amg_smooth.c; amg_cycle.c's chebyshev_part
 * in the same operations and order): mode 0 d = c2 D^-1 t, x = d; mode 1 the same with x += d;
 * mode 2 d = c1 d + c2 D^-1 t, x += d; xf (or NULL) gets x rounded. Reads L->DinvT. */
typedef void (*wc_amg_cheb_nodes_fn)(const wc_amg_level* L, const double* t, double* d, double* x, float* xf, int lo,
                                     int hi, double c1, double c2, int mode);
/* The AVX2 kernel where the CPU has it, else NULL (the scalar loops). */
wc_amg_cheb_nodes_fn wc_amg_cheb_nodes_kernel(void);
/* The block diagonal's inverses (amg_pair_inverse.c). Di = Aii^-1, or its mean diagonal's inverse
 * when singular. wc_amg_inverse6: M^-1 in place, 0 (M spoilt) when a pivot is not above 1e-13 x
 * the largest diagonal entry or the inverse is not finite; _x4: four lane-interleaved matrices
 * (M[4 k + lane]) at once with the same bits per lane, a bit per lane that succeeded; _vec: 1
 * where the CPU runs _x4 in AVX2. Pairs lo..hi-1 of a pair level: L->Dinv from B (+ cross, the
 * couplings' part, or NULL), 6x6 with pair_blocks (vec: four at a time) else two 3x3. */
void wc_amg_block_inverse(double* Di, const double* Aii);
int wc_amg_inverse6(double* M);
unsigned wc_amg_inverse6_x4(double* M);
int wc_amg_inverse6_vec(void);
void wc_amg_pair_inverses(wc_amg_level* L, const double* cross, int pair_blocks, int vec, int lo, int hi);
/* L->DinvT's nodes [lo, hi) from L->Dinv (nothing when DinvT is NULL). */
void wc_amg_dinv_columns(wc_amg_level* L, int lo, int hi);

/* out = (D^-1 t)_i: 3x3 blocks, or node i's rows of its pair's 6x6 inverse (group 2). */
static inline void wc_amg_dinv(const wc_amg_level* L, int i, const double* t, double* out) {
    if (L->group == 1) {
        m3_mulv(out, L->Dinv + 9 * (size_t)i, t + 3 * (size_t)i);
        return;
    }
    int b = i & ~1;
    m3_mulv(out, L->Dinv + 18 * (size_t)i, t + 3 * (size_t)b);
    m3_mulv_add(out, L->Dinv + 18 * (size_t)i + 9, t + 3 * (size_t)b + 3);
}

#endif
