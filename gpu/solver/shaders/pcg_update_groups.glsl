#version 430 core
// pcg_update.glsl with its reduction's first level folded in (compute passes, block Jacobi):
// one invocation a texel, 256 a group; images 0..2 = dv, r, t (zeros past u_n, to the texture's
// end u_texels), and the group's sums (r.t, r.r) at texel tc(group) of image 3, which the next
// scalars step finishes. The block-Jacobi z = D~^-1 r is applied in the same pass.
// With u_fold, the scalars step before it (alpha, pcg_scalars_rules.glsl's mode 1) is folded in
// too: every group finishes the SpMV's u_sum_n partials of c.q (group_sum.glsl: in one fixed
// order, so every group gets the same sum) and applies the rules; group 0 writes the scalars
// (images 4..6).
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include pcg_update_row
#pragma weft include pcg_scalars_rules
#pragma weft include group_sum
uniform sampler2D scalars2;
uniform sampler2D sum;      // u_fold: the SpMV's partials, w summing to c.q
uniform int u_fold;
uniform int u_sum_n;
uniform int u_texels;
layout(binding = 0) writeonly uniform image2D wg_img0;
layout(binding = 1) writeonly uniform image2D wg_img1;
layout(binding = 2) writeonly uniform image2D wg_img2;
layout(binding = 3) writeonly uniform image2D wg_img3;
layout(binding = 4) writeonly uniform image2D wg_img4;
layout(binding = 5) writeonly uniform image2D wg_img5;
layout(binding = 6) writeonly uniform image2D wg_img6;

void main() {
    int t = int(gl_LocalInvocationID.x);
    int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    int i = 256 * group + t;
    vec4 s0 = texelFetch(scalars0, ivec2(0), 0), s1 = texelFetch(scalars1, ivec2(0), 0);
    if (u_fold != 0) {   // a uniform: the whole group takes the barriers, or none of it
        vec4 s2 = texelFetch(scalars2, ivec2(0), 0);
        pcg_scalars_rules(s0, s1, s2, partials_sum(sum, u_sum_n).w, vec2(0.0));
        if (group == 0 && t == 0) {
            imageStore(wg_img4, ivec2(0), s0);
            imageStore(wg_img5, ivec2(0), s1);
            imageStore(wg_img6, ivec2(0), s2);
        }
    }
    vec3 dvi = vec3(0.0), ri = vec3(0.0), z = vec3(0.0);
    if (i < u_n) pcg_update_row(i, pcg_alpha(s0, s1), dvi, ri, z);
    if (i < u_texels) {
        imageStore(wg_img0, tc(i), vec4(dvi, 0.0));
        imageStore(wg_img1, tc(i), vec4(ri, 0.0));
        imageStore(wg_img2, tc(i), vec4(z, 0.0));
    }
    vec4 psum = group_sum(vec4(dot(ri, z), dot(ri, ri), 0.0, 0.0));
    if (t == 0) imageStore(wg_img3, tc(group), psum);
}
