#version 430 core
// One smoothed level of the multigrid packed for pcg_group_amg.glsl, per solve after the setup:
// from texel u_off of image 0 (its fpack), the smoother's bound (lvl_bound of the power
// iterations' reduction times u_bound_scale: wg_amg.c bound_scale, as amg_smooth.glsl takes it),
// the rows of D^-1 (u_dn texels each: a node's, or on a pair level node i's two blocks of its
// pair's 6x6 inverse, texels 2i and 2i + 1) and, with u_blocks, the rows of the level's blocks
// (u_nb each), copied as they are; and from texel u_poff, where u_np > 0 (the smoothed
// prolongator's level), the rows of P's blocks (u_np each). One invocation a texel of the longest,
// 256 a group.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include amg_blocks
uniform sampler2D dinv0;
uniform sampler2D dinv1;
uniform sampler2D dinv2;
uniform sampler2D a0;       // with u_blocks (a coarse level): its blocks' rows
uniform sampler2D a1;
uniform sampler2D a2;
uniform sampler2D pv0;      // with u_np > 0: P's blocks' rows
uniform sampler2D pv1;
uniform sampler2D pv2;
uniform sampler2D bound;
uniform int u_off;
uniform int u_dn;
uniform int u_nb;
uniform int u_blocks;
uniform int u_poff;
uniform int u_np;
uniform float u_bound_scale;
layout(binding = 0) writeonly uniform image2D wg_img0;

void main() {
    int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    int i = 256 * group + int(gl_LocalInvocationID.x);
    if (i == 0) imageStore(wg_img0, tc(u_off), vec4(u_bound_scale * lvl_bound(bound), 0.0, 0.0, 0.0));
    if (i < u_dn) {
        imageStore(wg_img0, tc(u_off + 1 + i), ld(dinv0, i));
        imageStore(wg_img0, tc(u_off + 1 + u_dn + i), ld(dinv1, i));
        imageStore(wg_img0, tc(u_off + 1 + 2 * u_dn + i), ld(dinv2, i));
    }
    if (u_blocks != 0 && i < u_nb) {
        int o = u_off + 1 + 3 * u_dn;
        imageStore(wg_img0, tc(o + i), ld(a0, i));
        imageStore(wg_img0, tc(o + u_nb + i), ld(a1, i));
        imageStore(wg_img0, tc(o + 2 * u_nb + i), ld(a2, i));
    }
    if (i < u_np) {
        imageStore(wg_img0, tc(u_poff + i), ld(pv0, i));
        imageStore(wg_img0, tc(u_poff + u_np + i), ld(pv1, i));
        imageStore(wg_img0, tc(u_poff + 2 * u_np + i), ld(pv2, i));
    }
}
