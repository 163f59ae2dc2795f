#version 430 core
// The PCG scalars (pcg_scalars_rules.glsl) as one work group that first finishes its two
// reductions: `sum` and `dots` hold per-group partial sums (the fused SpMV's and update's,
// spmv_groups.glsl and pcg_update_groups.glsl, or a reduction's first level), item k at texel
// tc(k), u_sum_n and u_dots_n of them (0: not read), summed by group_sum.glsl's partials_sum;
// invocation 0 applies the rules and writes s0..s2 to images 0..2.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include pcg_scalars_rules
#pragma weft include group_sum
uniform sampler2D scalars0;
uniform sampler2D scalars1;
uniform sampler2D sum;      // partials whose w sums to residual0^2 or cq
uniform sampler2D dots;     // partials whose xy sum to (delta, rr)
uniform sampler2D scalars2;
uniform int u_sum_n;
uniform int u_dots_n;
layout(binding = 0) writeonly uniform image2D wg_img0;
layout(binding = 1) writeonly uniform image2D wg_img1;
layout(binding = 2) writeonly uniform image2D wg_img2;

void main() {
    float sum_w = partials_sum(sum, u_sum_n).w;
    vec2 dr = partials_sum(dots, u_dots_n).xy;
    if (gl_LocalInvocationIndex != 0u) return;
    vec4 s0 = texelFetch(scalars0, ivec2(0), 0), s1 = texelFetch(scalars1, ivec2(0), 0), s2 = texelFetch(scalars2, ivec2(0), 0);
    pcg_scalars_rules(s0, s1, s2, sum_w, dr);
    imageStore(wg_img0, ivec2(0), s0);
    imageStore(wg_img1, ivec2(0), s1);
    imageStore(wg_img2, ivec2(0), s2);
}
