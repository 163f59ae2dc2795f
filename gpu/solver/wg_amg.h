/* The multigrid preconditioner of the GPU's PCG (private to gpu/solver): aggregation multigrid
 * with the aggregates core builds (core/amg_build.c, wc_amg_create with wg_amg_opts()), its
 * near-null space the three translations per aggregate and, by default (smoothed, WG_AMG_SMOOTHED,
 * WEFT_GPU_AMG_SMOOTH), core's smoothed prolongator P = (I - w D^-1 A_F) P_tent, w = 4/3 over the
 * level's lambda_max bound (core/amg_setup.c): per solve and level one pass makes P's blocks, one
 * T = A P and one the next level's P^T T, each a gather from lists core's symbolic build gives
 * (wg_amg_smooth.c); the V-cycle restricts the residual through P^T and prolongs through P (a
 * pass each). With P = P_tent (smoothed 0: identity blocks, WEFT_GPU_AMG_SMOOTH=0)
 * every coarse operator is a plain sum of finer blocks (one gather pass a level) and the
 * prolongation folds into the smoother's first pass.
 * Rotations (rotations, WG_AMG_ROTATIONS, WEFT_GPU_AMG_ROT; with the smoothed P only): the six
 * rigid modes, two coarse nodes 2a, 2a + 1 an aggregate (core/amg.h), opt-in (current,
 * WG_AMG_CURRENT, WEFT_GPU_AMG_CURRENT=1) about the CURRENT positions as core's: every setup does
 * each aggregate's QR on the device (amg_tent_qr.glsl: two passes a level, the next level's
 * near-null rows R, centres and dead unknowns, then P_tent's blocks), each aggregate's rows about
 * its own centre (core's R up to an upper-triangular change of basis, the same Q); else about the
 * REST positions (the default), core's P_tent built once (its QR per aggregate) and its 3x3
 * blocks uploaded; the prolongator pass multiplies each block of A by the P_tent block of its column, and the
 * 3x3-block passes (T = A P, P^T T, the restriction and prolongation) run unchanged on the
 * doubled coarse nodes. The pair levels (every level below the finest) smooth with a 6x6 block
 * diagonal per pair, inverted per setup (amg_dinv.glsl) and read by the smoother, the power
 * iterations and the prolongator, whose node then also reads its pair's residual; a pair level's
 * bound takes WG_AMG_PAIR_BOUND; dead unknowns (1- or 2-node aggregates) get core's decoupled
 * diagonal in the Galerkin pass (amg_ptap.glsl). P = P_tent stays of translations. The
 * one-work-group PCG (wg_amg_group.c) runs whichever of the three forms the chain runs. The same method runs on the CPU with wg_amg_opts() (tests/test_gpu_amg.c
 * compares the two; tests/test_gpu_amg_smooth.c the levels themselves, test_gpu_amg_rot with
 * rotations).
 *
 * The finest level's operator, the projected S A S + a (I - S), is never stored: its passes read
 * A's symmetric blocks and the filter (amg_level_inputs.glsl), with the V-cycle's vectors kept in
 * range(S). Per solve (wg_amg_setup, passes only, nothing read back): each coarse level's Galerkin
 * products (the first from the projected blocks made on the fly), the block-diagonal inverses,
 * power iterations per level for lambda_max(D^-1 A) (WG_AMG_POWER from core's start vector at
 * a frame's first setup, WG_AMG_POWER_COARSE on a smoothed P's coarse levels; WG_AMG_POWER_WARM
 * from the last setup's iterate at the others, whose quotient is taken no lower than
 * WG_AMG_WARM_FLOOR x the frame's cold one; their Rayleigh quotient stays in a 1 x 1 texture
 * that the smoother reads; the finest level's bound also takes core's seam factor,
 * fine_bound_scale), and the coarsest level's dense Cholesky factor.
 * Per PCG iteration (wg_amg_apply): one V-cycle, Chebyshev smoothing of degree 2 before and
 * after the coarse correction (core/amg_cycle.c), one dense solve, passes fused where no global
 * barrier parts them (fuse; WEFT_GPU_AMG_FUSE=0: a pass a step, the same arithmetic): the
 * pre-smoothing's two steps in one pass (amg_smooth.glsl u_zero 2), the residual in the
 * restriction on a level of at most WG_AMG_FOLD_RESIDUAL nodes (amg_restrict_res.glsl), and that
 * restriction with the coarsest level's solve in one work group below one of at most
 * WG_AMG_FOLD_COARSE_ROWS (amg_coarse_restrict_groups.glsl): five passes a level (six on a larger
 * level, seven unfused; four with P = P_tent, five unfused); with the smoothed P, the V-cycle from
 * the first coarse level of at most WG_AMG_SUB_ROWS nodes down in one pass of one work group
 * (amg_sub_groups.glsl: the one-work-group PCG's V-cycle code on its packed levels, wg_amg.sub).
 *
 * The penalty pairs' cross terms (wg_pairs.h; core/amg_cross.c's couplings) are in every level
 * with P = P_tent (with the smoothed P, translations or rotations, in the finest level's only, the
 * coarse levels being the pattern's Galerkin products): there a pair's vector sum_k e_k u_k restricts to the same u_k at its slots' coarse
 * nodes, so per level lists uploaded per substep (wg_amg_set_pairs, wg_amg_cross.c: each pair of
 * nodes that two slots of a pair couple, and its terms) and one texture of the slots' filtered
 * u_k and c (a pass per setup) give each level's whole operator. Per setup one pass a level sums
 * the terms' off-diagonal parts c u_k u_j^T into 3x3 blocks per pair of nodes (A's diagonal
 * blocks hold the rest); the smoother's residuals, the restriction, D^-1, the power iterations
 * and the coarsest factor read those blocks: a few a node, where the slots of an aggregate's
 * pairs are hundreds. A level whose cross blocks are a small share of its blocks leaves them out
 * of its products (cross_share, decided on the host at each upload; no level in: no pass at all).
 *
 * Compute passes only (GL 4.3): the dense factor and solve are native compute shaders of one
 * work group. A cloth on fragment passes refuses the multigrid (wg_sim_create). The multigrid is
 * given the cloth's runner and the textures of its system (wg_amg_system) and knows nothing else
 * of the cloth. */
#ifndef WEFT_GPU_SOLVER_AMG_H
#define WEFT_GPU_SOLVER_AMG_H

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

/* The hierarchy core builds for the GPU, patterns only (values 0; a CPU run of the same method
 * sets values 1). */
wc_amg_opts wg_amg_opts(void);
/* The same for a smoothed prolongator (smoothed 1) or P = P_tent (0), translations only. */
wc_amg_opts wg_amg_opts_for(int smoothed);
/* The same with the near-null space chosen: rotations 1 (with smoothed only) or 0. Core's
 * P_tent about the rest positions is built either way (current_positions 0): the GPU's rest form,
 * and the patterns and lists of both. */
wc_amg_opts wg_amg_opts_form(int smoothed, int rotations);
/* The multigrid of model m's system: patterns and lists uploaded; 0 with err on failure. */
int wg_amg_create(wg_runner* r, const wc_model* m, const wg_amg_system* sys, wg_amg** out, char* err,
                  size_t err_len);
/* The same with the prolongator chosen: smoothed 1 or 0 (P = P_tent); wg_amg_create takes
 * WG_AMG_SMOOTHED. */
int wg_amg_create_with(wg_runner* r, const wc_model* m, const wg_amg_system* sys, int smoothed, wg_amg** out,
                       char* err, size_t err_len);
/* The same with the near-null space chosen too (rotations: with smoothed only, else ignored);
 * wg_amg_create_with takes WG_AMG_ROTATIONS. */
int wg_amg_create_form(wg_runner* r, const wc_model* m, const wg_amg_system* sys, int smoothed, int rotations,
                       wg_amg** out, char* err, size_t err_len);
/* wg_amg_smooth.c: the smoothed prolongator's lists and textures of every level from core's
 * hierarchy (built with wg_amg_opts_for(1)); 0 with err on failure. */
int wg_amg_smooth_create(wg_amg* a, const wc_amg* ca, char* err, size_t err_len);
void wg_amg_destroy(wg_amg* a);
/* Free the memory only (the GL context is gone). */
void wg_amg_forget(wg_amg* a);
size_t wg_amg_bytes(const wg_amg* a);
/* The factor the smoother and the prolongator's w take on level l's bound (lvl_bound's 1.1 x the
 * Rayleigh quotient): the finest level's seam and cross factors, WG_AMG_PAIR_BOUND on a pair level. */
double wg_amg_bound_scale(const wg_amg* a, int l);
/* The values for the prepared system (A, S). The bounds' power steps start from the last setup's
 * iterates (WG_AMG_POWER_WARM steps) unless wg_amg_cold was called since (WG_AMG_POWER steps from
 * core's start vector; the first setup is cold). */
void wg_amg_setup(wg_amg* a);
/* The next setup estimates the bounds afresh: the cloth calls it at every frame's start (so a
 * frame depends on its starting state alone: snapshots, teleports and resets stay exact), after a
 * substep's rollback and after a solve that did not converge. */
void wg_amg_cold(wg_amg* a);
/* z = M^-1 r (one V-cycle) into a->z (the hierarchy's own texture, valid until the next call),
 * and PCG's partial products (r.z, r.r) per particle into dot. */
void wg_amg_apply(wg_amg* a, const wg_tex* r, const wg_tex* dot);

/* The penalty pairs' terms in every level (wg_pairs.h: self-contact and mesh pairs alike, as
 * pairs_row.glsl multiplies them): room for cap pairs (at creation, where the cloth has pairs;
 * 0 with err on failure), then after each wg_pairs_find their nodes on every level up (p NULL or
 * with no pairs this substep: none); wg_amg_setup takes their filtered vectors and c. */
int wg_amg_pairs_create(wg_amg* a, int cap, char* err, size_t err_len);
void wg_amg_set_pairs(wg_amg* a, const struct wg_pairs* p);
/* Tests: level l's cross lists as wg_amg_set_pairs last uploaded them (host scratch, valid until
 * the next call; *texels of 4 ints; NULL where the terms are off). */
const int* wg_amg_debug_cross_lists(wg_amg* a, int l, int* texels);

/* PCG with the V-cycle in one work group (wg_amg_group.c), the chain's V-cycle in any of its
 * forms (P = P_tent, the smoothed P with translations or rotations). At creation under
 * WEFT_GPU_SOLVE=group (wg_amg_create), the packed patterns where every level fits the group's
 * rows (0 with err on failure); then, per solve after
 * wg_amg_setup, the levels' values packed (one pass a smoothed level), and the group's pass put
 * in use with the system's inputs sys and the multigrid's, its uniforms set: the caller sets
 * pcg_group_solve.glsl's and runs it with group_v as its read-write image 5. */
int wg_amg_group_create(wg_amg* a, const wc_amg* ca, char* err, size_t err_len);
int wg_amg_group_fits(const wg_amg* a);
void wg_amg_group_pack(wg_amg* a);
/* The coarse sub-cycle in one work group (amg_sub_groups.glsl): at creation, with the smoothed
 * prolongator, the cut (the first level >= 1 of at most WG_AMG_SUB_ROWS nodes with a level below,
 * every level from it at most WG_AMG_SUB_NODES) and its levels' patterns packed (none where no
 * level qualifies; 0 with err on failure); wg_amg_setup packs their values (one pass a smoothed
 * level from the cut) and the fused V-cycle runs from the cut in one pass (wg_amg.c vcycle). */
int wg_amg_sub_create(wg_amg* a, const wc_amg* ca, char* err, size_t err_len);
void wg_amg_pack_values(wg_amg* a, wg_amg_pack* k);
void wg_amg_group_use(wg_amg* a, const wg_pcg_group_in* sys);

#endif
