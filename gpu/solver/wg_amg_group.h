/* The multigrid's solves in one work group (wg_amg_group.c): PCG with the whole V-cycle in one
 * group, and the coarse sub-cycle in one group. */
#ifndef WEFT_GPU_SOLVER_AMG_GROUP_H
#define WEFT_GPU_SOLVER_AMG_GROUP_H

#include "wg_amg_types.h"

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
