#version 430 core
// One height of a resident body's BVH refit (core/bvh.c wc_bvh_refit, bottom-up: a node's
// children are refitted by an earlier dispatch): invocation e takes node order[u_first + e] and
// rewrites its two texels in the node image (min, left child), (max, right child) in place,
// keeping the children. A leaf (left -1; right: its triangle) gets its triangle's box over the
// substep's start and end positions, inflated by its mesh's thickness and widened by a few float
// ulps so that it holds the box core computes in double from the same frame positions; an inner
// node the union of its children's.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D order;       // node indices (x), grouped by height
uniform sampler2D tri_idx;     // (vertex indices, thickness) a triangle
uniform sampler2D vert;        // mesh_verts.glsl's output
uniform int u_first, u_count;
layout(binding = 0, rgba32f) uniform image2D wg_img0;

void main() {
    int e = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (e >= u_count) return;
    int j = int(ld(order, u_first + e).x);
    vec4 lo = imageLoad(wg_img0, tc(2 * j)), hi = imageLoad(wg_img0, tc(2 * j + 1));
    vec3 bmin, bmax;
    if (lo.w < 0.0) {
        vec4 q = ld(tri_idx, int(hi.w));
        ivec3 v = ivec3(q.xyz);
        bmin = vec3(3.0e38);
        bmax = vec3(-3.0e38);
        for (int c = 0; c < 3; ++c)
            for (int s = 0; s < 2; ++s) {
                vec3 p = ld(vert, 3 * v[c] + s).xyz;
                bmin = min(bmin, p);
                bmax = max(bmax, p);
            }
        // float's interpolation and the thickness's rounding: 8 ulps of the largest magnitude
        vec3 m = max(abs(bmin), abs(bmax)) + q.w;
        bmin = bmin - q.w - m * 9.6e-7;
        bmax = bmax + q.w + m * 9.6e-7;
    } else {
        vec4 l0 = imageLoad(wg_img0, tc(2 * int(lo.w))), l1 = imageLoad(wg_img0, tc(2 * int(lo.w) + 1));
        vec4 r0 = imageLoad(wg_img0, tc(2 * int(hi.w))), r1 = imageLoad(wg_img0, tc(2 * int(hi.w) + 1));
        bmin = min(l0.xyz, r0.xyz);
        bmax = max(l1.xyz, r1.xyz);
    }
    imageStore(wg_img0, tc(2 * j), vec4(bmin, lo.w));
    imageStore(wg_img0, tc(2 * j + 1), vec4(bmax, hi.w));
}
