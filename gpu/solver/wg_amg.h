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

#include "wg_amg_types.h"

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

#endif
