/* The GPU multigrid's records (wg_amg.h describes the hierarchy): its constants, one level's
 * textures, the system it is given, the packed forms of the one-group solves, the hierarchy, and
 * the few rules every file of it reads (wg_amg.c, wg_amg_smooth.c, wg_amg_cross.c, wg_amg_group.c). */
#ifndef WEFT_GPU_SOLVER_AMG_TYPES_H
#define WEFT_GPU_SOLVER_AMG_TYPES_H

#include "amg.h"
#include "model.h"
#include "wg_reduce.h"
#include "wg_ring.h"

#define WG_AMG_DENSE_NODES 32   /* coarsest level solved by a dense factor up to this many nodes
                                   (amg_factor_groups.glsl's DMAX = 3 x this); coarser stops there */
#define WG_AMG_SMOOTHED 1      /* the default prolongator: smoothed (wg_amg.smoothed) */
#define WG_AMG_ROTATIONS 1     /* the default near-null space with the smoothed prolongator:
                                   rotations (wg_amg.rotations) */
#define WG_AMG_CURRENT 0       /* the default with rotations: about the rest positions; 1 (opt-in,
                                   WEFT_GPU_AMG_CURRENT=1) about the current positions (wg_amg.current;
                                   docs/bench/gpu_amg_current.md: not the default until the dance's GPU
                                   check passes with it) */
#define WG_AMG_TENT_NODES 128  /* the current form's aggregates hold at most this many nodes
                                   (amg_tent_qr.glsl TQ_CAP: an invocation holds its columns);
                                   a hierarchy with a larger one takes the rest form */
#define WG_AMG_POWER 12         /* power iterations per level on a cold setup (from core's start
                                   vector: a frame's first, and after a rollback or a failed solve) */
#define WG_AMG_POWER_COARSE WC_AMG_COARSE_POWER /* on the coarse levels with the smoothed
                                   prolongator (core's for the power method, 30): 12 fell short of
                                   lambda_max there (test_gpu_amg, the stiff 64 x 64 sheet's level
                                   1: 0.992 x), where the levels are small; cold setups */
#define WG_AMG_POWER_WARM 3     /* on a warm setup (the frame's later ones), every level: from the
                                   last setup's iterate, normalised (wg_amg_setup; docs/bench/gpu_solve.md
                                   "Warm power steps") */
#define WG_AMG_WARM_FLOOR 0.97  /* a warm setup's Rayleigh quotient is taken no lower than this x
                                   the quotient of the frame's cold setup on the level (lvl_bound):
                                   3 steps from an iterate of another operator can fall far short
                                   of lambda_max (test_gpu_amg_cross: 0.73 x), and a Chebyshev
                                   interval below it breaks PCG down; one above it only smooths
                                   less */
#define WG_AMG_POWER_NORM 12    /* the power iterate rescaled to unit norm every this many steps
                                   (a reduction each; |v| grows by lambda_max a step: 100
                                   steps overflowed float) */
#define WG_AMG_PAIR_BOUND 1.15  /* a pair level's bound x this (rotations): the power iterations
                                   fall short of lambda_max there (core/amg.h WC_AMG_COARSE_POWER;
                                   test_gpu_amg, the stiff 64 x 64 sheet's level 1: 0.93 x after
                                   WG_AMG_POWER_COARSE steps); a bound above it only weakens the
                                   smoother a little, one below it makes the V-cycle indefinite */
#define WG_AMG_CROSS_BOUND 1.5   /* the finest level's bound x this while the pairs' terms are in
                                   the levels (wg_amg.cross_bound_scale): a vertex-triangle term
                                   spreads over four particles, so D^-1 A has modes up to 4 local to
                                   the contacts where a spring network's stop at 2, which the power
                                   iterations from a spread start underestimate (the suit's first
                                   frame: 3 solves not converged without it, 0 with it) */
#define WG_AMG_CROSS_FINE_SHARE 0.25   /* the finest level's cross blocks go into its products
                                   where they are at least this share of its blocks (A's), and
                                   WG_AMG_CROSS_COARSE_SHARE on each coarser level, else that level
                                   leaves them out (wg_amg.cross_share): where layers touch only
                                   here and there they cost more than they save (the suit, shares
                                   0.10 / 0.43 / 0.82 by level: 3 % fewer iterations for ~15 % more
                                   user CPU; its coarse levels' terms alone save none), where
                                   they touch over much of the cloth they cut the iterations (two
                                   layers 0.93 / 1.39 / 1.47, the dance 0.55 / 1.35 / 1.57 / 1.53;
                                   docs/bench/gpu_amg_cross.md) */
#define WG_AMG_CROSS_COARSE_SHARE 1.0
#define WG_AMG_FOLD_RESIDUAL 4096 /* with the smoothed prolongator, a level of at most this many
                                   nodes restricts its residual without a pass of its own: each
                                   next-level node makes the rows r - A x its entries of P read
                                   (amg_restrict_res.glsl), a residual row made once per entry of P
                                   in it (about 5 with rotations), where a pass costs about 9 us
                                   whatever its size (docs/design/gpu_passes.md) */
#define WG_AMG_FOLD_COARSE_ROWS 1024 /* with the smoothed prolongator and a factored coarsest
                                   level, a level above it of at most this many nodes restricts
                                   its residual and solves the coarsest in one work group
                                   (amg_coarse_restrict_groups.glsl ROWS: its residual rows in
                                   shared memory) */
#define WG_AMG_SUB_ROWS 1024 /* with the smoothed prolongator, fused: the V-cycle from the first
                                   coarse level of at most this many nodes that has a level below
                                   it runs in one work group (amg_sub_groups.glsl), where every
                                   level from it down has at most WG_AMG_SUB_NODES */
#define WG_AMG_SUB_NODES 2048  /* amg_sub_groups.glsl: 1,024 invocations x R = 2 rows */
#define WG_AMG_COARSE_SWEEPS 8  /* block-Jacobi sweeps on a coarsest level too big for the factor
                                   (a mesh of many pieces that does not coarsen) */

typedef struct wg_amg_level {
    int n, nb;
    wg_tex rows;                /* nodes: (block start, end, diagonal block, aggregate or -1) */
    wg_tex cols;                /* level >= 1, blocks: (row, column, -, -) (level 0: the system's) */
    wg_tex a[3];                /* level >= 1, blocks: rows 0..2 of the level's operator (level 0:
                                   read from A and the filter, amg_level_inputs.glsl) */
    wg_tex dinv[3];             /* nodes: rows of the inverse diagonal block */
    wg_tex gal_range, gal_list; /* level >= 1, per block: the finer level's blocks summed into it */
    wg_tex mem_range, mem_list; /* level >= 1, per node: the finer level's nodes of its aggregate */
    wg_tex r, x[2], d[2];       /* V-cycle vectors (level 0's r is PCG's) */
    wg_tex v0, v[2], part;      /* power iterations: start (core's), iterates, (v.Av, v.Dv, v'.v') */
    wg_chain red;
    const wg_tex* bound;        /* the last setup's reduction of part (lvl_bound) */
    int v_last;                 /* v[v_last]: the last setup's last iterate (warm start) */
    int cold_last;              /* the last setup was cold: bound holds the floor's quotient */
    wg_tex cross_i;             /* the pairs' cross terms on the level (amg_level_inputs.glsl,
                                   wg_amg_cross.c): per node its cross blocks, per block its
                                   column and terms, the terms (pair slots) */
    wg_tex cross_a;             /* 3 per block: its rows (amg_cross_blocks.glsl, per setup) */
    int cross_nb;               /* this substep's cross blocks */
    int cross_bcap;             /* the room for them (wg_amg_cross.c BLOCKS_PER_PAIR) */
    int cross_use;              /* this substep: the level's products read its cross blocks
                                   (wg_amg.cross_share) */
    /* the smoothed prolongator to the next level (wg_amg.smoothed, wg_amg_smooth.c); the next
       level's gal_range / gal_list then list its products P^T T */
    int np, nt;                 /* P's entries, T = A P's */
    wg_tex p_ent, p_rows;       /* P's entries (row, column, own aggregate), each node's entries */
    wg_tex p_range, p_list;     /* each entry's blocks of A (amg_prolongator.glsl) */
    wg_tex p[3];                /* P's blocks, by rows (per setup) */
    wg_tex t_range, t_list;     /* each entry of T its products (block of A, entry of P) */
    wg_tex t[3];                /* T's blocks, by rows (per setup) */
    wg_tex pt_range, pt_list;   /* each next-level node's entries of P (entry, row) */
    wg_tex res;                 /* r - A x after the pre-smoothing (amg_residual.glsl) */
    wg_tex tent[3];             /* rotations: P_tent's blocks to the next level, by rows, texel
                                   2i + q: row i to coarse node 2 agg(i) + q (core's tent) */
    int pair;                   /* a pair level (rotations, levels >= 1): D^-1 is 6x6 per pair
                                   (2a, 2a + 1), dinv holds 2n texels, rows.w the block (i, i ^ 1)
                                   (amg_level_inputs.glsl u_pair) */
    /* rotations about the current positions (wg_amg.current; amg_tent_qr.glsl): per setup the
       QR of each aggregate of this level into tent (to the next level) and the next level's nn
       and nc */
    wg_tex tq_range, tq_list;   /* below the coarsest: each aggregate's nodes (core's agg_start /
                                   agg_node) */
    wg_tex tq_of;               /* below the coarsest: each node's aggregate */
    wg_tex nn[6];               /* levels >= 1: each node's near-null rows (core's nns: node 2a + q
                                   holds rows 3q..3q + 2 of aggregate a's R), about nc.xyz: row r,
                                   columns 3h..3h + 2 in nn[2 r + h].xyz */
    wg_tex nc;                  /* levels >= 1: (its aggregate's centre, its dead unknowns' bits) */
    wg_tex tq_t[6];             /* levels >= 1: node 2a + q's coefficients of Q's columns 3q + k
                                   on aggregate a's rows (ta in tq_t[2k].xyz, tb in tq_t[2k + 1]) */
} wg_amg_level;

/* The finest level's inputs: the cloth's system (its textures; the pointers stay valid and the
 * contacts may trade the values behind them between setups). */
typedef struct wg_amg_system {
    const wg_tex* block;        /* blocks: (row, column, -, -) */
    const wg_tex *a_lo, *a_hi;  /* A's symmetric blocks */
    const wg_tex *S0, *S1;      /* the filter */
    wg_ring* x;                 /* the state's positions (the rotations' about the current
                                   positions, wg_amg.current); NULL: the rest positions' P_tent */
} wg_amg_system;

/* The multigrid's levels from first down packed for one work group (wg_amg_group.c): the patterns
 * at creation, the values per setup, the V-cycle's coarse vectors read and written by the group
 * (pcg_group_amg.glsl's header gives the layouts). */
typedef struct wg_amg_pack {
    int first;                  /* the first level packed: 0 (PCG in one work group) or the cut */
    wg_tex i;                   /* the patterns */
    wg_tex fp;                  /* per setup: the smoothed levels' bounds, D^-1 (a pair level's
                                   6x6) and blocks, and the smoothed prolongator's blocks */
    wg_tex v;                   /* the coarse levels' V-cycle vectors (image 5) */
    int f[WC_AMG_MAX_LEVELS];   /* each level's offset in fp (-1: a dense coarsest level, or
                                   above first) */
    int p[WC_AMG_MAX_LEVELS];   /* each level's smoothed P's blocks in fp (-1: none) */
} wg_amg_pack;

typedef struct wg_amg {
    wg_runner* run;
    wg_amg_system sys;
    int n_levels;
    int dense;                  /* the coarsest level is factored (<= WG_AMG_DENSE_NODES nodes) */
    int sweeps;                 /* Chebyshev degree of the smoother (core's default, 2) */
    int fuse;                   /* 1 (the default): the V-cycle's fused passes (the first two
                                   smoothing steps in one; the residual in the restriction on a
                                   level of at most WG_AMG_FOLD_RESIDUAL nodes, and with the
                                   coarsest level's solve where WG_AMG_FOLD_COARSE_ROWS allows);
                                   0 (tests): a pass a step, the same arithmetic */
    double ratio;               /* its interval [bound / ratio, bound] (core's, 10) */
    int smoothed;               /* the prolongator is smoothed (core's P = (I - w D^-1 A_F) P_tent,
                                   w = prolong_weight / lambda_max bound: wg_amg_smooth.c), else
                                   P = P_tent (WEFT_GPU_AMG_SMOOTH=0) */
    double prolong_weight;      /* core's (4/3) where smoothed */
    int rotations;              /* the near-null space: the six rigid modes (about the current or
                                   the rest positions: current) (WG_AMG_ROTATIONS,
                                   WEFT_GPU_AMG_ROT), else the three
                                   translations; only with the smoothed prolongator */
    int current;                /* with rotations: about the current positions (WG_AMG_CURRENT,
                                   WEFT_GPU_AMG_CURRENT; the system's x), P_tent, R and the dead
                                   unknowns rebuilt by every setup on the device (amg_tent_qr.glsl,
                                   two passes a level), else core's about the rest positions,
                                   uploaded once */
    wg_chain cen_red;           /* current: the positions' sum (the centroid core's dead test
                                   measures its columns about) */
    double fine_bound_scale;    /* the finest level's bound x this: core's wc_amg.fine_bound_scale
                                   (WC_AMG_SEAM_BOUND where vertex-to-edge seams lift lambda_max in
                                   modes local to them, which the power iterations miss; else 1) */
    wg_amg_level lev[WC_AMG_MAX_LEVELS];
    wg_tex coarse_L;            /* 3n x 3n texels: the coarsest level's factor */
    const wg_tex* z;            /* the last V-cycle's result (level 0) */
    int warm;                   /* 1: the next setup's power steps start from the last setup's
                                   iterates (warm_steps of them); 0: cold (wg_amg_cold) */
    int warm_steps;             /* WG_AMG_POWER_WARM (tests: 0, every setup cold) */
    double warm_floor;          /* WG_AMG_WARM_FLOOR (tests: 0, no floor) */
    int cold_steps[2];          /* a cold setup's steps: finest level (and every level with P =
                                   P_tent), the smoothed P's coarse ones (WG_AMG_POWER, _COARSE) */
    long cold_setups, warm_setups;   /* a stat */
    /* PCG in one work group (wg_amg_group.c, pcg_group_amg.glsl), where every level has at most
       WG_GROUP_MAX_PARTICLES nodes (group.i.id 0 otherwise): every level packed */
    wg_amg_pack group;
    /* The coarse sub-cycle in one work group (amg_sub_groups.glsl; sub.i.id 0: none): the levels
       from the cut down packed (sub.first, wg_amg_sub_create) */
    wg_amg_pack sub;
    /* The self-contact pairs' cross terms (wg_amg_pairs_create, wg_amg_set_pairs): */
    int* node_of;               /* (n_levels x lev[0].n) each particle's node on each level */
    int cross_cap;              /* pairs the textures hold (0: the cloth has no pairs) */
    int cross_n;                /* this substep's pairs (0: none in the system) */
    int cross_skip;             /* tests: leave the terms out (the pattern's hierarchy alone) */
    double cross_bound_scale;   /* WG_AMG_CROSS_BOUND (tests: 1, core's power method) */
    double cross_share[2];      /* the finest level's and the coarser levels' least share of
                                   cross blocks to take them (WG_AMG_CROSS_*_SHARE; tests: 0,
                                   every level) */
    int cross_levels;           /* this substep: the levels that take their terms */
    const struct wg_pairs* pairs;
    wg_tex cross_u;             /* 4 per pair: each slot's (u, c) (amg_cross_terms.glsl) */
    int* cross_buf;             /* host: a level's cross_i (wg_amg_cross.c) */
    int* cross_cnt;             /* host: lev[0].n + 1 ints */
    int* cross_scratch;         /* host: lev[0].n + 96 cross_cap + 1 ints (wg_amg_cross.c) */
    long cross_dropped;         /* substeps whose terms needed more blocks than the room: left
                                   out of the levels (a stat) */
} wg_amg;

/* The pairs' cross blocks are in the hierarchy's products (wg_amg_cross.c). */
static inline int wg_amg_cross_on(const wg_amg* a) { return a->cross_n > 0 && a->cross_levels > 0 && !a->cross_skip; }
/* Level l's products take its cross blocks. */
static inline int wg_amg_cross_level(const wg_amg* a, int l) { return wg_amg_cross_on(a) && a->lev[l].cross_use; }
/* The factor the smoother and the prolongator's w take on level l's bound (lvl_bound's 1.1 x the
 * Rayleigh quotient): the finest level's seam and cross factors, WG_AMG_PAIR_BOUND on a pair level. */
static inline double wg_amg_bound_scale(const wg_amg* a, int l) {
    if (l > 0) return a->lev[l].pair ? WG_AMG_PAIR_BOUND : 1.0;
    return a->fine_bound_scale * (wg_amg_cross_level(a, 0) ? a->cross_bound_scale : 1.0);
}
#endif
