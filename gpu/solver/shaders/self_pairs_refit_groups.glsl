#version 430 core
// One height of a self-collision tree's refit for the self pairs' GPU finder (wg_self_pairs.h),
// bottom-up as self_idle_refit_groups.glsl (the same nodes, rewritten whole): invocation e takes
// node order[u_first + e] and rewrites its two texels (min, left child), (max, right child). A
// leaf (left -1; right: its element, elem[u_elem0 + element]) gets the box of its particles at
// x and at x + 1.5 h v (u_h15 = 1.5 h; u_motion 0, a test's mutation: x alone) grown by u_pad
// (the thickness, core's wc_self_refit) and by u_margin times the largest magnitude there (float's
// rounding of x + 1.5 h v and of the bounds, against core's double); an inner node the union of
// its children's. So the box holds core's leaf box.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D elem;        // (particles a, b, c or -1, -) a triangle, then an edge
uniform sampler2D x;           // the substep's start positions
uniform sampler2D v;           // its start velocities
uniform int u_elem0, u_motion;
uniform float u_h15, u_pad, u_margin;

// the leaf box of element (tree_refit.glsl)
void leaf_box(int element, out vec3 bmin, out vec3 bmax) {
    vec4 q = ld(elem, u_elem0 + element);
    bmin = vec3(3.0e38);
    bmax = vec3(-3.0e38);
    float mag = 0.0;
    for (int c = 0; c < 3; ++c) {
        if (q[c] < 0.0) continue;
        vec3 p0 = ld(x, int(q[c])).xyz, dp = u_h15 * ld(v, int(q[c])).xyz;
        vec3 p1 = u_motion != 0 ? p0 + dp : p0;
        bmin = min(bmin, min(p0, p1));
        bmax = max(bmax, max(p0, p1));
        vec3 a = max(abs(p0), abs(p1)) + abs(dp);
        mag = max(mag, max(max(a.x, a.y), a.z));
    }
    float pad = u_pad * 1.00001 + (mag + u_pad) * u_margin;
    if (isnan(mag) || isinf(mag)) pad = 3.0e38;   // a non-finite particle: an unbounded box
    bmin = bmin - pad;
    bmax = bmax + pad;
}

#pragma weft include tree_refit
