#version 430 core
// pcg_direction.glsl with the scalars step before it folded in (compute passes, when the update
// left few partials): every group of 256 finishes the update's u_dots_n partials of (r.z, r.r)
// (group_sum.glsl: every group gets the same sums), applies
// pcg_scalars_rules.glsl's mode 2 (beta, the iteration count, the stop tests), and group 0
// writes the scalars (images 1..3); then each invocation's texel of c = S (t + beta c), c kept
// once the solve is done (image 0; zeros past u_n, to the texture's end u_texels).
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include pcg_scalars_rules
#pragma weft include group_sum
uniform sampler2D t;        // the preconditioned residual
uniform sampler2D c;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D scalars0;
uniform sampler2D scalars1;
uniform sampler2D scalars2;
uniform sampler2D dots;     // the update's partials, xy summing to (r.z, r.r)
uniform int u_dots_n;
uniform int u_texels;
layout(binding = 0) writeonly uniform image2D wg_img0;
layout(binding = 1) writeonly uniform image2D wg_img1;
layout(binding = 2) writeonly uniform image2D wg_img2;
layout(binding = 3) writeonly uniform image2D wg_img3;

void main() {
    int lt = int(gl_LocalInvocationID.x);
    int group = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    int i = 256 * group + lt;
    vec2 dr = partials_sum(dots, u_dots_n).xy;
    vec4 s0 = texelFetch(scalars0, ivec2(0), 0), s1 = texelFetch(scalars1, ivec2(0), 0), s2 = texelFetch(scalars2, ivec2(0), 0);
    pcg_scalars_rules(s0, s1, s2, 0.0, dr);
    if (group == 0 && lt == 0) {
        imageStore(wg_img1, ivec2(0), s0);
        imageStore(wg_img2, ivec2(0), s1);
        imageStore(wg_img3, ivec2(0), s2);
    }
    if (i >= u_texels) return;
    vec4 o = vec4(0.0);
    if (i < u_n) {
        vec3 cp = ld(c, i).xyz;
        o = vec4(s1.x != 0.0 ? cp : filter_apply(ld(S0, i), ld(S1, i), ld(t, i).xyz + s0.z * cp), 0.0);
    }
    imageStore(wg_img0, tc(i), o);
}
