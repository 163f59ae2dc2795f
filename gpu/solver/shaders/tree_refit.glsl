// One height of a tree's refit, bottom-up (an include of mesh_refit_groups.glsl,
// self_pairs_refit_groups.glsl and self_idle_refit_groups.glsl, not a pass; included last, it is
// their main): invocation e takes node order[u_first + e] (e < u_count) and rewrites its two
// texels of the node image (image 0: (min, left child), (max, right child)) in place, keeping
// the children. A leaf (left -1; right: its element) gets the includer's leaf_box(element,
// bmin, bmax); an inner node the union of its children's boxes, refitted by an earlier dispatch.
// The includer defines leaf_box before it.
uniform sampler2D order;       // node indices (x), grouped by height
uniform int u_first, u_count;
layout(binding = 0, rgba32f) uniform image2D wg_img0;

void main() {
    int e = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (e >= u_count) return;
    int j = int(ld(order, u_first + e).x);
    vec4 lo = imageLoad(wg_img0, tc(2 * j)), hi = imageLoad(wg_img0, tc(2 * j + 1));
    vec3 bmin, bmax;
    if (lo.w < 0.0) {
        leaf_box(int(hi.w), bmin, bmax);
    } else {
        vec4 l0 = imageLoad(wg_img0, tc(2 * int(lo.w))), l1 = imageLoad(wg_img0, tc(2 * int(lo.w) + 1));
        vec4 r0 = imageLoad(wg_img0, tc(2 * int(hi.w))), r1 = imageLoad(wg_img0, tc(2 * int(hi.w) + 1));
        bmin = min(l0.xyz, r0.xyz);
        bmax = max(l1.xyz, r1.xyz);
    }
    imageStore(wg_img0, tc(2 * j), vec4(bmin, lo.w));
    imageStore(wg_img0, tc(2 * j + 1), vec4(bmax, hi.w));
}
