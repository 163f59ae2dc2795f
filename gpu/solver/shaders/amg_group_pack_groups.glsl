#version 430 core
// One smoothed level of the multigrid packed for pcg_group_amg.glsl, per solve after the setup:
// from texel u_off of image 0 (its fpack), the smoother's bound (lvl_bound of the power
// iterations' reduction times u_bound_scale: wg_amg.h fine_bound_scale on the finest level, 1
// elsewhere, as amg_smooth.glsl takes it), the rows of D^-1 (u_n texels each) and, with u_blocks, the rows of
// the level's blocks (u_nb each), copied as they are. One invocation a node or block, 256 a group.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include amg_blocks
uniform sampler2D dinv0;
uniform sampler2D dinv1;
uniform sampler2D dinv2;
uniform sampler2D a0;       // with u_blocks (a coarse level): its blocks' rows
uniform sampler2D a1;
uniform sampler2D a2;
uniform sampler2D bound;
uniform int u_off;
uniform int u_nb;
uniform int u_blocks;
uniform float u_bound_scale;
layout(binding = 0) writeonly uniform image2D wg_img0;

void main() {
    int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    int i = 256 * group + int(gl_LocalInvocationID.x);
    if (i == 0) imageStore(wg_img0, tc(u_off), vec4(u_bound_scale * lvl_bound(bound), 0.0, 0.0, 0.0));
    if (i < u_n) {
        imageStore(wg_img0, tc(u_off + 1 + i), ld(dinv0, i));
        imageStore(wg_img0, tc(u_off + 1 + u_n + i), ld(dinv1, i));
        imageStore(wg_img0, tc(u_off + 1 + 2 * u_n + i), ld(dinv2, i));
    }
    if (u_blocks != 0 && i < u_nb) {
        int o = u_off + 1 + 3 * u_n;
        imageStore(wg_img0, tc(o + i), ld(a0, i));
        imageStore(wg_img0, tc(o + u_nb + i), ld(a1, i));
        imageStore(wg_img0, tc(o + 2 * u_nb + i), ld(a2, i));
    }
}
