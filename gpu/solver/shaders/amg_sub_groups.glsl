#version 430 core
// The multigrid's coarse sub-cycle in one work group of 1,024 invocations (the smoothed
// prolongator, fused: wg_amg.c vcycle at level u_cut, the first coarse level of at most
// WG_AMG_SUB_ROWS nodes with a level below it): the V-cycle from that level down to the coarsest
// and back, its smoothing, restrictions, coarsest solve, prolongations and post-smoothing, as
// pcg_group_amg.glsl runs them (amg_group_levels.glsl, the same code and order) where the chain
// takes five passes or more. Reads the level's r (the restriction pass above wrote it), copies it
// into the scratch, runs the cycle and writes the level's x into image 0 (the prolongation pass above
// reads it); the cycle's coarse vectors in image 1 (the scratch). The levels from u_cut down are packed as the group's (wg_amg_group.c: ipack at
// creation, fpack per setup). Node I of a level is invocation I mod 1,024's.
layout(local_size_x = 1024, local_size_y = 1) in;
#define G 1024
#define R 2                 // rows an invocation: WG_AMG_SUB_NODES = 2,048 nodes a level at most
#define GROUP_SCRATCH 1     // image 5 of amg_group_levels.glsl: after the output
int T;
int row(int k) { return T + G * k; }
#pragma weft include amg_blocks
#pragma weft include amg_smooth_step
#pragma weft include amg_coarse_inverse
#pragma weft include amg_group_levels
uniform sampler2D r;        // level u_cut's right-hand side
uniform int u_cut;
layout(binding = 0) writeonly uniform image2D wg_img0;

void smooth_level(int l, level L, level N, int step, bool zero, bool prolong) {
    smooth_coarse(L, N, step, zero, prolong);
}
void coarsest_dense(int l, level L) { coarsest_dense_coarse(L); }
void restrict_into(int l, level L, level N) { restrict_coarse(L, N); }

void main() {
    T = int(gl_LocalInvocationID.x);
    level C = lvl(u_cut);
    for (int k = 0; k < R; ++k)
        if (row(k) < C.n) sset(C, SR, row(k), ld(r, row(k)).xyz);
    sync_image();
    amg_group_cycle(u_cut);
    for (int k = 0; k < R; ++k)
        if (row(k) < C.n) imageStore(wg_img0, tc(row(k)), vec4(sget(C, SX, row(k)), 0.0));
}
