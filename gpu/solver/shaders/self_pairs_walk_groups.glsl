#version 430 core
// The self pairs' candidates (wg_self_pairs.h): invocation q, a query of core's
// wc_self_pairs_find (a particle q < u_np against the triangle tree, else the edge q - u_np
// against the edges above it), walks the tree refitted by self_pairs_refit_groups.glsl (root
// node 0) with the box of its particles at x and x + 1.5 h v, grown by u_margin of its largest
// magnitude (float's rounding), and keeps every element whose leaf box meets it, that core's
// adjacency rules keep (no shared or sewn particle, not all four tangled at rest) and that is not
// surely farther than core's keep allows, 2 thickness + 1.5 h (the largest relative speed of a
// particle of each feature): a lower bound of the distance at x (self_walk_rules.glsl's support
// bound, less 1e-5 of the pair's extent for float's rounding) above that reach (grown by 1e-4)
// drops it. Each kept (q, element) takes a slot of the counter (image 1, r32i) and is written to
// image 0 (rgba32f: q, element) when the slot is below u_cap; past it it is only counted. The host tests each in double by core's rules (wc_self_pairs_from), in
// core's order: the list is core's when these hold every pair core's walk reaches.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D x;           // the substep's start positions
uniform sampler2D v;           // its start velocities
uniform int u_cap, u_motion, u_rules;
uniform float u_th, u_h15, u_margin;
layout(binding = 0, rgba32f) writeonly uniform image2D wg_img0;
layout(binding = 1, r32i) uniform iimage2D wg_img1;

#pragma weft include self_walk_rules

// 1 unless surely farther than core's keep: lb the support bound, ext the extent, the first
// split particles the first feature's. Core keeps a pair closer than th + thickness + 1.5 h a,
// th <= thickness, a its approach speed -n . (sum w_k v_k): its weights are a convex combination
// on each side (1 | barycentric; 1 - s, s | 1 - t, t), so a is at most the largest relative speed
// |v_i - v_j| of a particle of each side (grown for float's rounding)
bool near(float lb, float ext, ivec4 ids, int split) {
    vec3 w[4];
    float rel = 0.0, speed = 0.0;
    for (int k = 0; k < 4; ++k) {
        w[k] = ld(v, ids[k]).xyz;
        speed += length(w[k]);
    }
    for (int i = 0; i < split; ++i)
        for (int j = split; j < 4; ++j) rel = max(rel, length(w[i] - w[j]));
    float reach = (2.0 * u_th + u_h15 * (rel * 1.0001 + 1e-6 * speed) * float(u_motion)) * 1.0001;
    return !(lb - 1e-5 * ext > reach);
}

// the pair is a candidate: core's rules keep it (u_rules 0, a test's mutation: all kept) and it is
// not surely farther than core's keep
bool candidate(ivec4 ids, int split) {
    if (u_rules != 0 && adjacent(ids, split, true)) return false;
    float lb, ext;
    return !support_bound(x, ids, split, lb, ext) || near(lb, ext, ids, split);
}

void keep(int q, int prim) {
    int slot = imageAtomicAdd(wg_img1, ivec2(0), 1);
    if (slot < u_cap) imageStore(wg_img0, tc(slot), vec4(float(q), float(prim), 0.0, 0.0));
}

// self_walk_rules.glsl's walk meets a leaf: its pair kept when a candidate
void visit(int q, int prim, ivec4 ids, int split) {
    if (candidate(ids, split)) keep(q, prim);
}

// deeper than core's trees go: the host's walk (the slot past u_cap)
bool too_deep() {
    imageAtomicAdd(wg_img1, ivec2(0), u_cap + 1);
    return true;
}

void main() {
    int q = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (q >= u_n) return;
    ivec2 pq = query_particles(q);
    vec3 blo = vec3(3.0e38), bhi = vec3(-3.0e38);
    float mag = 0.0;
    for (int k = 0; k < 2; ++k) {
        if (pq[k] < 0) continue;
        vec3 p0 = ld(x, pq[k]).xyz, dp = u_h15 * ld(v, pq[k]).xyz;
        vec3 p1 = u_motion != 0 ? p0 + dp : p0;
        blo = min(blo, min(p0, p1));
        bhi = max(bhi, max(p0, p1));
        vec3 a = max(abs(p0), abs(p1)) + abs(dp);
        mag = max(mag, max(max(a.x, a.y), a.z));
    }
    blo -= mag * u_margin;
    bhi += mag * u_margin;
    walk(q, blo, bhi);
}
