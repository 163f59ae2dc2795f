#version 430 core
// One height of a self-collision tree's refit for the idle proof (wg_self_idle.h), bottom-up as
// mesh_refit_groups.glsl: invocation e takes node order[u_first + e] and rewrites its two texels
// (min, left child), (max, right child) in place. A leaf (left -1; right: its element, a triangle
// or an edge, elem[u_elem0 + element]) gets the box of its particles' START positions xs grown by
// the largest displacement |x - xs| of its particles plus u_pad (the proof's reach), widened by a
// few float ulps of the largest magnitude (the subtraction, the length, the additions); an inner
// node the union of its children's. So every end position, and every point of the linear motion
// between, lies in the leaf's box shrunk by u_pad.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D elem;        // (particles a, b, c or -1, -) a triangle, then an edge
uniform sampler2D x;           // the substep's end positions
uniform sampler2D xs;          // its start positions
uniform int u_elem0;
uniform float u_pad;

// the leaf box of element (tree_refit.glsl)
void leaf_box(int element, out vec3 bmin, out vec3 bmax) {
    vec4 q = ld(elem, u_elem0 + element);
    bmin = vec3(3.0e38);
    bmax = vec3(-3.0e38);
    float delta = 0.0, mag = 0.0;
    for (int c = 0; c < 3; ++c) {
        if (q[c] < 0.0) continue;
        vec3 p0 = ld(xs, int(q[c])).xyz, p1 = ld(x, int(q[c])).xyz;
        bmin = min(bmin, p0);
        bmax = max(bmax, p0);
        delta = max(delta, length(p1 - p0));
        mag = max(mag, max(max(abs(p0.x), abs(p0.y)), abs(p0.z)));
    }
    // a non-finite particle: an unbounded box (its pairs are tested and act)
    if (isnan(delta) || isinf(delta) || isnan(mag) || isinf(mag)) {
        bmin = vec3(-3.0e38);
        bmax = vec3(3.0e38);
    } else {
        float pad = delta * 1.0001 + u_pad + (mag + delta + u_pad) * 9.6e-7;
        bmin = bmin - pad;
        bmax = bmax + pad;
    }
}

#pragma weft include tree_refit
