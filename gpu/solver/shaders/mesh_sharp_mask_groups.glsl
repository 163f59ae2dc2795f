#version 430 core
// One height of a resident body's sharp mask (core/mesh_pairs.c sharp_update's node_mask and
// core/bvh.c wc_bvh_mask_up, bottom-up like mesh_refit_groups.glsl): invocation e takes node
// order[u_first + e] and writes its texel of the mask image, 1 above a non-degenerate triangle
// with a sharp vertex (mesh_sharp.glsl's, item u_nef + vertex), the only ones that give pairs:
// a leaf from its triangle, an inner node the larger of its children's (an earlier dispatch's).
// The pairs' walk (mesh_pairs_find_groups.glsl) skips the nodes at 0.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D order;       // node indices (x), grouped by height
uniform sampler2D mesh_node;   // 2 texels a node: (min, left child), (max, right child); a leaf: -1, triangle
uniform sampler2D mesh_tri;    // 3 a triangle: vertex indices, normal at start, at end
uniform sampler2D sharp;       // mesh_sharp.glsl's output
uniform int u_first, u_count, u_nef;
layout(binding = 0, rgba32f) uniform image2D wg_img0;

void main() {
    int e = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (e >= u_count) return;
    int j = int(ld(order, u_first + e).x);
    vec4 lo = ld(mesh_node, 2 * j), hi = ld(mesh_node, 2 * j + 1);
    float m;
    if (lo.w < 0.0) {
        int t = int(hi.w);
        ivec3 v = ivec3(ld(mesh_tri, 3 * t).xyz);
        bool live = ld(mesh_tri, 3 * t + 1).xyz != vec3(0.0);
        m = live && max(ld(sharp, u_nef + v.x).x, max(ld(sharp, u_nef + v.y).x, ld(sharp, u_nef + v.z).x)) > 0.0
                ? 1.0 : 0.0;
    } else {
        m = max(imageLoad(wg_img0, tc(int(lo.w))).x, imageLoad(wg_img0, tc(int(hi.w))).x);
    }
    imageStore(wg_img0, tc(j), vec4(m, 0.0, 0.0, 0.0));
}
