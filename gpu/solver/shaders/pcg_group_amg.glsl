#version 430 core
// PCG with the multigrid's V-cycle, a whole solve in one work group of 1,024 invocations
// (compute passes, a cloth of at most GRP_MAX particles: wg_solve.c solve_group): the solve is
// pcg_group_solve.glsl's, the preconditioner one V-cycle of wg_amg.c's (vcycle) per
// precondition(), in its order and with its arithmetic: amg_smooth_step.glsl's steps (Chebyshev
// of degree u_sweeps before and after the coarse correction, the prolongation added in the first
// step after it), the restriction summing each aggregate's residuals in its member list's order,
// or with the smoothed prolongator (u_smoothed; wg_amg.h smoothed, rotations) the residual
// restricted by P^T in amg_restrict_p.glsl's order and the correction prolonged by P's rows
// (amg_prolong.glsl) before the first step after it, a pair level's smoother taking its pair's
// 6x6 D^-1 (amg_level_inputs.glsl op_dinv_mul), and the coarsest level's dense solve (amg_coarse_inverse.glsl) or its u_coarse_sweeps block-Jacobi
// sweeps. The setup (wg_amg_setup) ran before as passes; amg_group_pack_groups.glsl copied each
// smoothed level's bound, D^-1 and blocks into fpack.
//
// Where the V-cycle's vectors live: the finest level's x (z, the preconditioned residual) and d
// in registers with PCG's vectors, x in shared memory when neighbours read it (the residual
// restricted goes through shared memory too); a coarser level's r, x, d and restricted residual
// in image 5 (coherent; every phase that writes them ends in memoryBarrierImage and barrier); the
// coarsest level's dense solve one node an invocation. Node I of every level is invocation
// I mod 1,024's.
//
// ipack (int4): per level l, texels 4 l = (rows, cols, members' ranges, members) offsets,
// 4 l + 1 = (fpack offset, image 5 offset, nodes, blocks), 4 l + 2 = (P's rows, P's columns
// offsets, a pair level, fpack offset of P's blocks) and 4 l + 3 = (P's entries, -, -, -); then,
// per coarse level, its rows (block start, end, diagonal, the block (i, i ^ 1) on a pair level,
// else the aggregate on the next level or -1), blocks (row, column), with P = P_tent each node's
// range of members and the members (nodes of the finer level) ascending; per level with a
// smoothed P, its rows (entries first, end), its entries (row, coarse node), each next-level
// node's range of entries and those (entry, row) (wg_amg_smooth.c's p_rows, p_ent, pt_range,
// pt_list). fpack (float4), per smoothed level from its offset: the smoother's bound (x), D^-1's
// rows 0..2 (n texels each; 2n on a pair level: node i's blocks 2i, 2i + 1), and on a coarse
// level its blocks' rows 0..2 (nb each); per level with a smoothed P from its own offset, P's
// blocks' rows 0..2 (np each). Image 5, per coarse level from its offset: r, x, d and the
// residual to restrict (n texels each).
layout(local_size_x = 1024, local_size_y = 1) in;
#pragma weft include pcg_scalars_rules
#pragma weft include project_row
#pragma weft include pcg_group_solve
#pragma weft include amg_blocks
#pragma weft include amg_smooth_step
#pragma weft include amg_coarse_inverse
#define GROUP_SCRATCH 5     // after the outputs 0..4
uniform isampler2D rows;    // the finest level's nodes (amg_level_inputs.glsl): w its aggregate
#pragma weft include amg_group_levels

vec3 xd[R];                 // the finest level's smoothing step d (xt holds its x)

// one smoothing step on the finest level (amg_smooth.glsl over it: the operator S (A x), the
// correction of N's x filtered as it is prolonged)
void smooth_fine(level L, level N, int step, bool zero, bool prolong) {
    if (!zero) {
        if (prolong)
            for (int k = 0; k < R; ++k)
                if (row(k) < u_n) {
                    int i = row(k);
                    xt[k] += filter_apply(ld(S0, i), ld(S1, i), prolong_row(L, N, i, ldi(rows, i).w));
                }
        share_rows(xt);
    }
    float bd = bound_of(L);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            int i = row(k);
            vec3 t = xr[k];
            if (!zero) t -= spmv_row(i);
            vec3 di = amg_smooth_step(step, bd, u_ratio, dinv_at(L, i) * t, xd[k]);
            xt[k] = (zero ? vec3(0.0) : xt[k]) + di;
            xd[k] = di;
        }
}

void smooth_level(int l, level L, level N, int step, bool zero, bool prolong) {
    if (l == 0) smooth_fine(L, N, step, zero, prolong);
    else smooth_coarse(L, N, step, zero, prolong);
}

// the coarsest level l's dense solve: node I's x from the inverse's row of blocks, by invocation I
// (the level has at most WG_AMG_DENSE_NODES nodes; on level 0, u_n: node I is row(0))
void coarsest_dense(int l, level L) {
    if (l > 0) {
        coarsest_dense_coarse(L);
        return;
    }
    share_rows(xr);
    vec3 x = vec3(0.0);
    if (T < L.n)
        for (int J = 0; J < L.n; ++J) x += coarse_inverse_block(T, J) * get(J);
    if (T < u_n) xt[0] = x;
}

void precondition_setup(int k, int i) {}

// the residual r - A x of level l's nodes (x its last smoothing step's) restricted into N's r
void restrict_into(int l, level L, level N) {
    if (l == 0) {   // through shared memory
        share_rows(xt);
        for (int k = 0; k < R; ++k)
            if (row(k) < u_n) xq[k] = xr[k] - spmv_row(row(k));
        share_rows(xq);
        if (u_smoothed != 0) {
            RESTRICT_P(L, N, get(i));
        } else {
            RESTRICT_INTO(N, get(i));
        }
    } else {
        restrict_coarse(L, N);
    }
}

// t = the V-cycle on r (wg_amg.c vcycle: amg_group_cycle from the finest level), and the group's
// (r.t, r.r)
vec2 precondition() {
    amg_group_cycle(0);
    vec2 acc = vec2(0.0);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) acc += vec2(dot(xr[k], xt[k]), dot(xr[k], xr[k]));
    return sum2(acc);
}

void main() { pcg_group_main(); }
