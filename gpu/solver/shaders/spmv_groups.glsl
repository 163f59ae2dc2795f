#version 430 core
// spmv.glsl as a compute shader of its own (built only where the passes are compute shaders:
// wg_device.c; wg_spmv runs it there): the same q = A x (with u_filter, q = S (A x) and w = x.q),
// but 4 invocations a row (CSR-vector) instead of one. Lane l of row i takes the row's blocks
// start + l, start + l + 4, ...: neighbouring invocations read neighbouring blocks (coalesced),
// where one invocation a row reads blocks ~13 apart from its neighbours. The lanes' partial sums
// meet in shared memory; lane 0 writes the texel. Texels past u_n (to the texture's end, u_texels)
// are written as zeros, as every pass does. With u_partials (PCG: the first level of p.Ap folded
// in), the group's sum of w over its 64 rows goes to texel tc(group) of image 1, as (0, 0, 0, sum),
// which pcg_scalars_groups.glsl finishes.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include spmv_inputs
#pragma weft include pairs_row
#pragma weft include group_sum
uniform int u_texels;
uniform int u_partials;
layout(binding = 0) writeonly uniform image2D wg_img0;
layout(binding = 1) writeonly uniform image2D wg_img1;
shared vec3 part[256];

void main() {
    int t = int(gl_LocalInvocationID.x), lane = t & 3;
    int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    int i = (256 * group + t) >> 2;
    vec3 y = vec3(0.0);
    if (i < u_n) {
        ivec4 r = ldi(pblocks, i);
        for (int k = r.x + lane; k < r.y; k += 4) y += sym(ld(a_lo, k), ld(a_hi, k).xy) * ld(x, ldi(block, k).y).xyz;
        if (lane == 0) y += pairs_row(x, i);   // the penalty pairs' off-diagonal blocks
    }
    part[t] = y;
    memoryBarrierShared();
    barrier();
    vec4 o = vec4(0.0);
    if (lane == 0 && i < u_texels) {
        if (i < u_n) {
            y = (part[t] + part[t + 1]) + (part[t + 2] + part[t + 3]);
            if (u_filter != 0) {
                y = filter_apply(ld(S0, i), ld(S1, i), y);
                o = vec4(y, dot(ld(x, i).xyz, y));
            } else {
                o = vec4(y, 0.0);
            }
        }
        imageStore(wg_img0, tc(i), o);
    }
    if (u_partials != 0) {   // a uniform: the whole group takes the barriers below, or none of it
        vec4 psum = group_sum(vec4(0.0, 0.0, 0.0, o.w));   // o is zero but in lane 0 of a row
        if (t == 0) imageStore(wg_img1, tc(group), psum);
    }
}
