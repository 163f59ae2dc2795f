#version 430 core
// The PCG scalars (pcg_scalars_rules.glsl) as one work group that first finishes its two
// reductions: `sum` and `dots` hold per-group partial sums (the fused SpMV's and update's,
// spmv_groups.glsl and pcg_update_groups.glsl, or a reduction's first level), item k at texel
// tc(k), u_sum_n and u_dots_n of them (0: not read). Each invocation sums a strided run, then a
// shared-memory tree; invocation 0 applies the rules and writes s0..s2 to images 0..2.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include pcg_scalars_rules
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
shared vec3 part[256];

void main() {
    int t = int(gl_LocalInvocationID.x);
    vec3 acc = vec3(0.0);
    for (int k = t; k < u_sum_n; k += 256) acc.x += ld(sum, k).w;
    for (int k = t; k < u_dots_n; k += 256) acc.yz += ld(dots, k).xy;
    part[t] = acc;
    memoryBarrierShared();
    barrier();
    for (int s = 128; s > 0; s >>= 1) {
        if (t < s) part[t] += part[t + s];
        memoryBarrierShared();
        barrier();
    }
    if (t != 0) return;
    vec4 s0 = texelFetch(scalars0, ivec2(0), 0), s1 = texelFetch(scalars1, ivec2(0), 0), s2 = texelFetch(scalars2, ivec2(0), 0);
    pcg_scalars_rules(s0, s1, s2, part[0].x, part[0].yz);
    imageStore(wg_img0, ivec2(0), s0);
    imageStore(wg_img1, ivec2(0), s1);
    imageStore(wg_img2, ivec2(0), s2);
}
