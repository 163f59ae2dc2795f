#version 430 core
// A reduction as compute shaders (built only where the passes are compute shaders, after
// common.glsl as every pass: wg_device.c): one or two dispatches of this program instead of
// reduce.glsl's 8 x 8 levels (wg_reduce.c). Work group k of u_groups combines the
// texels i = 256 k + t + 256 u_groups j of the whole w x h input (every texel, as reduce.glsl
// does: passes write zeros past their items), channel c summed (u_mode[c] 0) or maximised (1):
// first along each invocation's stride, then across the group in shared memory. It stores the
// group's result at texel (k, 0) of image 0, so with u_groups 1 texel (0, 0) holds the whole
// reduction. Neighbouring invocations read neighbouring texels (coalesced).
layout(local_size_x = 256, local_size_y = 1) in;
uniform sampler2D src;
uniform ivec2 u_in;
uniform ivec4 u_mode;
uniform int u_groups;
layout(binding = 0) writeonly uniform image2D wg_img0;
shared vec4 part[256];

// a selection, not a blend (see reduce.glsl: 0 inf = NaN in a float mix)
vec4 combine(vec4 a, vec4 b, bvec4 take_max) { return mix(a + b, max(a, b), take_max); }

void main() {
    bvec4 take_max = notEqual(u_mode, ivec4(0));
    int t = int(gl_LocalInvocationID.x);
    int k = int(gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x);   // 2D past max_groups_x
    if (k >= u_groups) return;   // a whole group: the surplus of a 2D dispatch
    int total = u_in.x * u_in.y, stride = 256 * u_groups;
    vec4 acc = vec4(0.0);
    for (int i = 256 * k + t; i < total; i += stride)
        acc = combine(acc, texelFetch(src, ivec2(i % u_in.x, i / u_in.x), 0), take_max);
    part[t] = acc;
    memoryBarrierShared();
    barrier();
    for (int s = 128; s > 0; s >>= 1) {
        if (t < s) part[t] = combine(part[t], part[t + s], take_max);
        memoryBarrierShared();
        barrier();
    }
    if (t == 0) imageStore(wg_img0, ivec2(k, 0), part[0]);
}
