#version 430 core
// pcg_update.glsl with its reduction's first level folded in (compute passes, block Jacobi):
// one invocation a texel, 256 a group; images 0..2 = dv, r, t (zeros past u_n, to the texture's
// end u_texels), and the group's sums (r.t, r.r) at texel tc(group) of image 3, which
// pcg_scalars_groups.glsl finishes. The block-Jacobi z = D~^-1 r is applied in the same pass.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include pcg_update_row
uniform int u_texels;
layout(binding = 0) writeonly uniform image2D wg_img0;
layout(binding = 1) writeonly uniform image2D wg_img1;
layout(binding = 2) writeonly uniform image2D wg_img2;
layout(binding = 3) writeonly uniform image2D wg_img3;
shared vec2 part[256];

void main() {
    int t = int(gl_LocalInvocationID.x);
    int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    int i = 256 * group + t;
    vec3 dvi = vec3(0.0), ri = vec3(0.0), z = vec3(0.0);
    if (i < u_n) pcg_update_row(i, dvi, ri, z);
    if (i < u_texels) {
        imageStore(wg_img0, tc(i), vec4(dvi, 0.0));
        imageStore(wg_img1, tc(i), vec4(ri, 0.0));
        imageStore(wg_img2, tc(i), vec4(z, 0.0));
    }
    part[t] = vec2(dot(ri, z), dot(ri, ri));
    memoryBarrierShared();
    barrier();
    for (int s = 128; s > 0; s >>= 1) {
        if (t < s) part[t] += part[t + s];
        memoryBarrierShared();
        barrier();
    }
    if (t == 0) imageStore(wg_img3, tc(group), vec4(part[0], 0.0, 0.0));
}
