#version 430 core
// One height of a resident body's BVH refit (core/bvh.c wc_bvh_refit, bottom-up: a node's
// children are refitted by an earlier dispatch): invocation e takes node order[u_first + e] and
// rewrites its two texels in the node image (min, left child), (max, right child) in place,
// keeping the children. A leaf (left -1; right: its triangle) gets its triangle's box over the
// substep's start and end positions, inflated by its mesh's thickness and widened by a few float
// ulps so that it holds the box core computes in double from the same frame positions; an inner
// node the union of its children's.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D tri_idx;     // (vertex indices, thickness) a triangle
uniform sampler2D vert;        // mesh_verts.glsl's output

// the leaf box of element (tree_refit.glsl)
void leaf_box(int element, out vec3 bmin, out vec3 bmax) {
    vec4 q = ld(tri_idx, element);
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
}

#pragma weft include tree_refit
