#version 430 core
// The idle proof's pairs (wg_self_idle.h): invocation q, a query of core's stage (a particle
// q < u_np against the triangle tree, else the edge q - u_np against the edges above it), walks
// the tree refitted by self_idle_refit_groups.glsl (root node 0) with the box of its start
// positions grown by its largest displacement (and float ulps), and tests every pair whose leaf
// box meets it and that core's adjacency rules keep (no shared or sewn particle, not all four
// tangled at rest): the pair is idle when a lower bound L of its distance at the start (the
// support bound below, less u_mu and 4e-6 of its extent for float's rounding) is at least the
// thickness times (1 + u_rel) and L less its relative motion bound (the largest |d_i - d_j|
// over a particle of each feature, d = x - xs, grown for rounding) exceeds eta times (1 +
// u_rel): core's proximity pass then gives it no impulse (distance >= thickness) and its
// too_far skips the CCD (self_pass.c). Every other pair adds one to the counter (image 0, r32i).
// The support bound: for any unit u, |p - y| >= (p - y).u >= min over the corners of the
// difference set, so with u along the float closest points' difference the bound is within
// rounding of the distance; a degenerate or non-finite case gives no bound (the pair acts).
layout(local_size_x = 64, local_size_y = 1) in;
uniform sampler2D tnode;       // the triangle tree's nodes: (min, left), (max, right or element)
uniform sampler2D enode;       // the edge tree's
uniform sampler2D elem;        // (particles a, b, c or -1, -) the triangles, then the edges
uniform sampler2D x;           // the substep's end positions
uniform sampler2D xs;          // its start positions
uniform sampler2D part;        // a particle's (seam links first, end, tangled, -)
uniform sampler2D seam;        // the seam links (x)
uniform int u_np, u_nt, u_shared;
uniform float u_th, u_eta, u_rel, u_mu, u_ulp;
layout(binding = 0, r32i) uniform iimage2D wg_img0;

bool linked(int a, int b) {
    if (a == b) return u_shared != 0;
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

// the largest |d_i - d_j|, i of the first feature (ids[0, split)), j of the second
float max_rel(ivec4 ids, int split) {
    vec3 d[4];
    float m = 0.0;
    for (int k = 0; k < 4; ++k) d[k] = ld(x, ids[k]).xyz - ld(xs, ids[k]).xyz;
    for (int i = 0; i < split; ++i)
        for (int j = split; j < 4; ++j) m = max(m, length(d[i] - d[j]) + 2.4e-7 * (length(d[i]) + length(d[j])));
    return m * 1.00001;
}

// 1 when the pair may act: lb the support bound of its start distance, ext its extent
int acts(float lb, float ext, ivec4 ids, int split) {
    float L = lb - u_mu - u_ulp * 4e-6 * ext;
    if (!(L >= u_th * (1.0 + u_rel))) return 1;
    return L - max_rel(ids, split) > u_eta * (1.0 + u_rel) ? 0 : 1;
}

int vertex_tri(int i, int t) {
    vec4 tv = ld(elem, t);
    ivec4 ids = ivec4(i, int(tv.x), int(tv.y), int(tv.z));
    if (linked(i, ids.y) || linked(i, ids.z) || linked(i, ids.w)) return 0;
    if (tangled(ids.x) && tangled(ids.y) && tangled(ids.z) && tangled(ids.w)) return 0;
    vec3 p = ld(xs, i).xyz;
    vec3 a = ld(xs, ids.y).xyz - p, b = ld(xs, ids.z).xyz - p, c = ld(xs, ids.w).xyz - p;
    vec3 q = closest_tri(a, b, c);
    float l = length(q);
    if (!(l > 0.0)) return 1;
    vec3 u = -q / l;   // from the triangle towards p
    float lb = min(min(dot(-a, u), dot(-b, u)), dot(-c, u));
    return acts(lb, max(max(length(a), length(b)), length(c)), ids, 1);
}

int edge_edge(int e, int f) {
    vec4 ea = ld(elem, u_nt + e), eb = ld(elem, u_nt + f);
    ivec4 ids = ivec4(int(ea.x), int(ea.y), int(eb.x), int(eb.y));
    if (linked(ids.x, ids.z) || linked(ids.x, ids.w) || linked(ids.y, ids.z) || linked(ids.y, ids.w)) return 0;
    if (tangled(ids.x) && tangled(ids.y) && tangled(ids.z) && tangled(ids.w)) return 0;
    vec3 o = ld(xs, ids.x).xyz;
    vec3 p0 = vec3(0.0), p1 = ld(xs, ids.y).xyz - o, q0 = ld(xs, ids.z).xyz - o, q1 = ld(xs, ids.w).xyz - o;
    vec2 st = closest_seg(p0, p1, q0, q1);
    vec3 w = p1 * st.x - (q0 + (q1 - q0) * st.y);
    float l = length(w);
    if (!(l > 0.0)) return 1;
    vec3 u = w / l;   // from the second edge towards the first
    float lb = min(min(dot(p0 - q0, u), dot(p0 - q1, u)), min(dot(p1 - q0, u), dot(p1 - q1, u)));
    return acts(lb, max(max(length(p1), length(q0)), max(length(q1), length(p1 - q0))), ids, 2);
}

void main() {
    int q = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (q >= u_n) return;
    bool vq = q < u_np;
    int e = q - u_np;
    ivec2 pq = vq ? ivec2(q, -1) : ivec2(ld(elem, u_nt + e).xy);
    vec3 blo = vec3(3.0e38), bhi = vec3(-3.0e38);
    float delta = 0.0, mag = 0.0;
    for (int k = 0; k < 2; ++k) {
        if (pq[k] < 0) continue;
        vec3 p0 = ld(xs, pq[k]).xyz, p1 = ld(x, pq[k]).xyz;
        blo = min(blo, p0);
        bhi = max(bhi, p0);
        delta = max(delta, length(p1 - p0));
        mag = max(mag, max(max(abs(p0.x), abs(p0.y)), abs(p0.z)));
    }
    if (isnan(delta) || isinf(delta) || isnan(mag) || isinf(mag)) {   // no bound: core's stage decides
        imageAtomicAdd(wg_img0, ivec2(0), 1);
        return;
    }
    float pad = delta * 1.0001 + (mag + delta) * 9.6e-7;
    blo -= pad;
    bhi += pad;
    int count = 0;
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int j = stack[--top];
        vec4 lo = vq ? ld(tnode, 2 * j) : ld(enode, 2 * j), hi = vq ? ld(tnode, 2 * j + 1) : ld(enode, 2 * j + 1);
        if (any(greaterThan(lo.xyz, bhi)) || any(lessThan(hi.xyz, blo))) continue;
        if (lo.w >= 0.0) {
            if (top + 2 > 64) { count += 1; continue; }   // deeper than core's trees go: acts
            stack[top++] = int(hi.w);
            stack[top++] = int(lo.w);
            continue;
        }
        int prim = int(hi.w);
        if (vq) count += vertex_tri(q, prim);
        else if (prim > e) count += edge_edge(e, prim);
    }
    if (count > 0) imageAtomicAdd(wg_img0, ivec2(0), count);
}
