#version 430 core
// The self pairs' candidates (wg_self_pairs.h): invocation q, a query of core's
// wc_self_pairs_find (a particle q < u_np against the triangle tree, else the edge q - u_np
// against the edges above it), walks the tree refitted by self_pairs_refit_groups.glsl (root
// node 0) with the box of its particles at x and x + 1.5 h v, grown by u_margin of its largest
// magnitude (float's rounding), and keeps every element whose leaf box meets it, that core's
// adjacency rules keep (no shared or sewn particle, not all four tangled at rest) and that is not
// surely farther than core's keep allows, 2 thickness + 1.5 h (the largest relative speed of a
// particle of each feature): a lower bound of the distance at x (the support bound of the
// difference set along the float closest points' direction, less 1e-5 of the pair's extent for
// float's rounding) above that reach (grown by 1e-4) drops it. Each kept (q, element) takes a slot of the counter (image
// 1, r32i) and is written to image 0 (rgba32f: q, element) when the slot is below u_cap; past it
// it is only counted. The host tests each in double by core's rules (wc_self_pairs_from), in
// core's order: the list is core's when these hold every pair core's walk reaches.
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D tnode;       // the triangle tree's nodes: (min, left), (max, right or element)
uniform sampler2D enode;       // the edge tree's
uniform sampler2D elem;        // (particles a, b, c or -1, -) the triangles, then the edges
uniform sampler2D x;           // the substep's start positions
uniform sampler2D v;           // its start velocities
uniform sampler2D part;        // a particle's (seam links first, end, tangled, -)
uniform sampler2D seam;        // the seam links (x)
uniform int u_np, u_nt, u_cap, u_motion, u_rules;
uniform float u_th, u_h15, u_margin;
layout(binding = 0, rgba32f) writeonly uniform image2D wg_img0;
layout(binding = 1, r32i) uniform iimage2D wg_img1;

bool linked(int a, int b) {
    if (a == b) return true;
    vec4 r = ld(part, a);
    for (int k = int(r.x); k < int(r.y); ++k)
        if (int(ld(seam, k).x) == b) return true;
    return false;
}

bool tangled(int a) { return ld(part, a).z != 0.0; }

// core/geom.c's closest point of triangle (a, b, c) to the origin (Ericson's regions)
vec3 closest_tri(vec3 a, vec3 b, vec3 c) {
    vec3 ab = b - a, ac = c - a, ap = -a;
    float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return a;
    vec3 bp = -b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return b;
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + ab * (d1 / (d1 - d3));
    vec3 cp = -c;
    float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return c;
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + ac * (d2 / (d2 - d6));
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    float den = 1.0 / (va + vb + vc);
    return a + ab * (vb * den) + ac * (vc * den);
}

// the closest points' parameters of segments p0-p1, q0-q1 (core/geom.c wc_closest_on_segments)
vec2 closest_seg(vec3 p0, vec3 p1, vec3 q0, vec3 q1) {
    vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    float a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    if (a <= 0.0 && e <= 0.0) return vec2(0.0);
    if (a <= 0.0) return vec2(0.0, clamp(f / e, 0.0, 1.0));
    float c = dot(d1, r);
    if (e <= 0.0) return vec2(clamp(-c / a, 0.0, 1.0), 0.0);
    float b = dot(d1, d2), den = a * e - b * b;
    float s = den > 1e-12 * a * e ? clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
    float t = (b * s + f) / e;
    if (t < 0.0) { t = 0.0; s = clamp(-c / a, 0.0, 1.0); }
    else if (t > 1.0) { t = 1.0; s = clamp((b - c) / a, 0.0, 1.0); }
    return vec2(s, t);
}

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

bool vertex_tri(int i, int t) {
    vec4 tv = ld(elem, t);
    ivec4 ids = ivec4(i, int(tv.x), int(tv.y), int(tv.z));
    if (u_rules != 0) {
        if (linked(i, ids.y) || linked(i, ids.z) || linked(i, ids.w)) return false;
        if (tangled(ids.x) && tangled(ids.y) && tangled(ids.z) && tangled(ids.w)) return false;
    }
    vec3 p = ld(x, i).xyz;
    vec3 a = ld(x, ids.y).xyz - p, b = ld(x, ids.z).xyz - p, c = ld(x, ids.w).xyz - p;
    vec3 q = closest_tri(a, b, c);
    float l = length(q);
    if (!(l > 0.0)) return true;
    vec3 u = -q / l;   // from the triangle towards p
    float lb = min(min(dot(-a, u), dot(-b, u)), dot(-c, u));
    return near(lb, max(max(length(a), length(b)), length(c)), ids, 1);
}

bool edge_edge(int e, int f) {
    vec4 ea = ld(elem, u_nt + e), eb = ld(elem, u_nt + f);
    ivec4 ids = ivec4(int(ea.x), int(ea.y), int(eb.x), int(eb.y));
    if (u_rules != 0) {
        if (linked(ids.x, ids.z) || linked(ids.x, ids.w) || linked(ids.y, ids.z) || linked(ids.y, ids.w))
            return false;
        if (tangled(ids.x) && tangled(ids.y) && tangled(ids.z) && tangled(ids.w)) return false;
    }
    vec3 o = ld(x, ids.x).xyz;
    vec3 p0 = vec3(0.0), p1 = ld(x, ids.y).xyz - o, q0 = ld(x, ids.z).xyz - o, q1 = ld(x, ids.w).xyz - o;
    vec2 st = closest_seg(p0, p1, q0, q1);
    vec3 w = p1 * st.x - (q0 + (q1 - q0) * st.y);
    float l = length(w);
    if (!(l > 0.0)) return true;
    vec3 u = w / l;   // from the second edge towards the first
    float lb = min(min(dot(p0 - q0, u), dot(p0 - q1, u)), min(dot(p1 - q0, u), dot(p1 - q1, u)));
    return near(lb, max(max(length(p1), length(q0)), max(length(q1), length(p1 - q0))), ids, 2);
}

void keep(int q, int prim) {
    int slot = imageAtomicAdd(wg_img1, ivec2(0), 1);
    if (slot < u_cap) imageStore(wg_img0, tc(slot), vec4(float(q), float(prim), 0.0, 0.0));
}

void main() {
    int q = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (q >= u_n) return;
    bool vq = q < u_np;
    int e = q - u_np;
    ivec2 pq = vq ? ivec2(q, -1) : ivec2(ld(elem, u_nt + e).xy);
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
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int j = stack[--top];
        vec4 lo = vq ? ld(tnode, 2 * j) : ld(enode, 2 * j), hi = vq ? ld(tnode, 2 * j + 1) : ld(enode, 2 * j + 1);
        if (any(greaterThan(lo.xyz, bhi)) || any(lessThan(hi.xyz, blo))) continue;
        if (lo.w >= 0.0) {
            if (top + 2 > 64) {   // deeper than core's trees go: the host's walk (the slot past u_cap)
                imageAtomicAdd(wg_img1, ivec2(0), u_cap + 1);
                return;
            }
            stack[top++] = int(hi.w);
            stack[top++] = int(lo.w);
            continue;
        }
        int prim = int(hi.w);
        if (vq ? vertex_tri(q, prim) : prim > e && edge_edge(e, prim)) keep(q, prim);
    }
}
