#version 430 core
// A resident body's sharp-feature pairs (core/mesh_pairs.c wc_mesh_pairs_find and keep, in
// float), one invocation a cloth feature (cfeat: a cloth edge (a, b, -1, q) or triangle
// (a, b, c, q), q core's feature index): the body's refitted tree walked (root u_root) to the
// non-degenerate triangles whose leaf boxes meet the feature's box at the start and at its
// inertial end x + h v, inflated by u_r, as core's walk; against their sharp edges (a cloth edge)
// and sharp vertices, each once, the closest points interior to both features, within
// the contact distance, the normal cone, the cloth point and the feature's particles in front of
// the body, the ties decided by core's band (closest points nearer than it: the first reached
// triangle's normal, in core's walk's order; a point less than it behind: in front); the walk
// skips the subtrees without a live triangle with a sharp vertex, as core's does. A pair found goes to the slot an atomic counter (image 1, r32i) hands out: three
// texels (particles, q), (weights, off), (normal, body feature: an edge, or u_nef + a vertex);
// past u_cap it is only counted. Its order is the GPU's: the host sorts the pairs by (q, body
// feature). The particles' masses and k are the host's (wc_mesh_pairs_add_found).
layout(local_size_x = 64, local_size_y = 1) in;
#pragma weft include contact_geometry
#pragma weft include contact_query
uniform sampler2D x;           // the cloth at the substep's start
uniform sampler2D v;
uniform sampler2D cfeat;
uniform sampler2D bedge;       // mesh_sharp.glsl's
uniform sampler2D bvrow;
uniform sampler2D bvlist;
uniform sampler2D btri;        // (edges, leaf node) a triangle
uniform sampler2D sharp;       // mesh_sharp.glsl's output
uniform sampler2D mask;        // mesh_sharp_mask_groups.glsl's: 0 where no pair can be
uniform int u_root, u_cap, u_nef;
uniform float u_th, u_push, u_h, u_r;
layout(binding = 0, rgba32f) writeonly uniform image2D wg_img0;
layout(binding = 1, r32i) uniform iimage2D wg_img1;

const float INTERIOR = 1e-6;
const float TURN_COS = 0.9659;
const float PAIR_TIE_REL = 1e-5;   // core/mesh_pairs.c TIE_REL: the ties' band (tie_band)

float pair_tie_band(vec3 p) {
    vec3 a = abs(p);
    return PAIR_TIE_REL * max(u_th, max(a.x, max(a.y, a.z)));
}

int cnt;
ivec3 P;
int q_id;
vec3 blo, bhi;   // the feature's box

// core/geom.c wc_closest_on_segments: the parameters s on p0-p1, t on q0-q1
void closest_segments(vec3 p0, vec3 p1, vec3 q0, vec3 q1, out float ss, out float tt) {
    vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
    float a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    if (a <= 0.0 && e <= 0.0) { ss = tt = 0.0; return; }
    if (a <= 0.0) { ss = 0.0; tt = clamp(f / e, 0.0, 1.0); return; }
    float c = dot(d1, r);
    if (e <= 0.0) { tt = 0.0; ss = clamp(-c / a, 0.0, 1.0); return; }
    float b = dot(d1, d2), den = a * e - b * b;
    ss = den > 1e-14 * a * e ? clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
    tt = (b * ss + f) / e;
    if (tt < 0.0) { tt = 0.0; ss = clamp(-c / a, 0.0, 1.0); }
    else if (tt > 1.0) { tt = 1.0; ss = clamp((b - c) / a, 0.0, 1.0); }
}

// triangle t's leaf: the tree's nodes are in preorder, so core's walk (left child first) reaches
// the leaves in increasing index
int leaf_of(int t) { return int(ld(btri, t).w); }

// triangle t reached by the walk: not degenerate, its leaf box meets the feature's
bool reached(int t) {
    if (t < 0 || ld(mesh_tri, 3 * t + 1).xyz == vec3(0.0)) return false;
    int leaf = int(ld(btri, t).w);
    vec3 lo = ld(mesh_node, 2 * leaf).xyz, hi = ld(mesh_node, 2 * leaf + 1).xyz;
    return !(any(greaterThan(lo, bhi)) || any(lessThan(hi, blo)));
}

// the first of vertex r's triangles the walk reaches, in core's order (the smallest leaf; -1: none)
int vertex_reached(int r) {
    vec4 row = ld(bvrow, r);
    int first = -1, at = 0;
    for (int j = int(row.x); j < int(row.y); ++j) {
        int t = int(ld(bvlist, j).x);
        if (!reached(t)) continue;
        int l = leaf_of(t);
        if (first < 0 || l < at) first = t, at = l;
    }
    return first;
}

// p more than the ties' band behind the body
bool behind(vec3 p, float reach, float tie) {
    vec3 n, vc;
    return mesh_closest(u_root, p, 0, reach, n, vc) < -tie;
}

void keep(vec3 w, vec3 cp0, vec3 bp0, vec3 bp1, vec3 vb, vec3 nb, bool cone, vec3 c1, vec3 c2, int fid) {
    vec3 d = cp0 - bp0;
    float dist = length(d), tie = pair_tie_band(cp0);
    vec3 n = dist > tie ? d / dist : nb;
    if (cone) {
        float d1 = dot(n, c1), d2 = dot(n, c2);
        if (d1 + d2 < 0.0) return;
        if (dot(cross(c1, n), cross(n, c2)) < 0.0) {
            if (!(max(d1, d2) >= TURN_COS)) return;
            n = d1 > d2 ? c1 : c2;
        }
    }
    vec3 vc = vec3(0.0);
    for (int k = 0; k < cnt; ++k) vc += w[k] * ld(v, P[k]).xyz;
    float approach = -(dot(vc, n) - dot(vb, n));
    float dc = 2.0 * u_th + 1.5 * u_h * max(approach, 0.0);
    if (!(dist < dc)) return;
    if (behind(cp0, dc + u_th, tie)) return;
    for (int k = 0; k < cnt; ++k) {
        vec3 xk = ld(x, P[k]).xyz;
        if (behind(xk, 1e30, pair_tie_band(xk))) return;
    }
    float off = dot(n, bp1) + u_th;
    float cap = u_push * u_h, g0 = dot(n, cp0) - off;
    if (cap > 0.0 && g0 + cap < 0.0) off += g0 + cap;
    int slot = imageAtomicAdd(wg_img1, ivec2(0), 1);
    if (slot >= u_cap) return;
    imageStore(wg_img0, tc(3 * slot), vec4(vec3(P), float(q_id)));
    imageStore(wg_img0, tc(3 * slot + 1), vec4(w, off));
    imageStore(wg_img0, tc(3 * slot + 2), vec4(n, float(fid)));
}

vec3 xa(int r) { return ld(mesh_vert, 3 * r).xyz; }
vec3 xb(int r) { return ld(mesh_vert, 3 * r + 1).xyz; }
vec3 vel(int r) { return ld(mesh_vert, 3 * r + 2).xyz; }

// The pairs of body triangle t, reached by the walk, with the cloth edge p0-q0: its sharp edges
// and vertices, each from one triangle only (an edge from its first triangle the walk reaches, a
// vertex from the first of its triangles the walk reaches): core's marks of the features seen.
void visit_edge(int t, vec3 p0, vec3 q0) {
    vec4 te = ld(btri, t);
    for (int c = 0; c < 3; ++c) {
        int e = int(te[c]);
        if (ld(sharp, e).x == 0.0) continue;
        vec4 be = ld(bedge, 2 * e);
        int t1 = int(be.z), t2 = int(be.w);
        // the edge's owner: the first of its triangles core's walk reaches (the smaller leaf)
        int own = t2 >= 0 && reached(t2) && (!reached(t1) || leaf_of(t2) < leaf_of(t1)) ? t2 : t1;
        if (t != own) continue;
        int r = int(be.x), s = int(be.y);
        float a, b;
        closest_segments(p0, q0, xa(r), xa(s), a, b);
        if (!(a > INTERIOR && a < 1.0 - INTERIOR && b > INTERIOR && b < 1.0 - INTERIOR)) continue;
        bool cone = t2 >= 0 && ld(bedge, 2 * e + 1).x == 0.0;
        keep(vec3(1.0 - a, a, 0.0), mix(p0, q0, a), mix(xa(r), xa(s), b), mix(xb(r), xb(s), b),
             mix(vel(r), vel(s), b), ld(mesh_tri, 3 * t + 1).xyz, cone, ld(mesh_tri, 3 * t1 + 1).xyz,
             cone ? ld(mesh_tri, 3 * t2 + 1).xyz : vec3(0.0), e);
    }
    vec3 ev = q0 - p0;
    float ee = dot(ev, ev);
    if (!(ee > 0.0)) return;
    ivec3 tv = ivec3(ld(mesh_tri, 3 * t).xyz);
    for (int c = 0; c < 3; ++c) {
        int r = tv[c];
        if (ld(sharp, u_nef + r).x == 0.0 || vertex_reached(r) != t) continue;
        float a = dot(xa(r) - p0, ev) / ee;
        if (!(a > INTERIOR && a < 1.0 - INTERIOR)) continue;
        keep(vec3(1.0 - a, a, 0.0), mix(p0, q0, a), xa(r), xb(r), vel(r), ld(mesh_tri, 3 * t + 1).xyz, false,
             vec3(0.0), vec3(0.0), u_nef + r);
    }
}

// The pairs of body triangle t with the cloth triangle ABC: its sharp vertices.
void visit_vertex(int t, vec3 A, vec3 B, vec3 C) {
    ivec3 tv = ivec3(ld(mesh_tri, 3 * t).xyz);
    for (int c = 0; c < 3; ++c) {
        int r = tv[c];
        if (ld(sharp, u_nef + r).x == 0.0 || vertex_reached(r) != t) continue;
        vec3 w = closest_weights(xa(r), A, B, C);
        if (!(w.x > INTERIOR && w.y > INTERIOR && w.z > INTERIOR)) continue;
        keep(w, w.x * A + w.y * B + w.z * C, xa(r), xb(r), vel(r), ld(mesh_tri, 3 * t + 1).xyz, false, vec3(0.0),
             vec3(0.0), u_nef + r);
    }
}

void main() {
    int i = int(gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u + gl_GlobalInvocationID.x);
    if (i >= u_n) return;
    vec4 f = ld(cfeat, i);
    cnt = f.z < 0.0 ? 2 : 3;
    P = ivec3(f.xy, f.z < 0.0 ? f.x : f.z);
    q_id = int(f.w);
    blo = vec3(3.0e38);
    bhi = vec3(-3.0e38);
    for (int k = 0; k < cnt; ++k) {
        vec3 p = ld(x, P[k]).xyz, e = p + u_h * ld(v, P[k]).xyz;
        blo = min(blo, min(p, e));
        bhi = max(bhi, max(p, e));
    }
    blo -= vec3(u_r);
    bhi += vec3(u_r);
    vec3 A = ld(x, P.x).xyz, B = ld(x, P.y).xyz, C = ld(x, P.z).xyz;
    // the body's refitted tree, the triangles whose leaf boxes meet the feature's box (core's
    // wc_bvh_query_masked: the mask prunes what cannot give a pair)
    int stack[66];
    int top = 0;
    stack[top++] = u_root;
    while (top > 0) {
        int j = stack[--top];
        if (ld(mask, j).x == 0.0) continue;
        vec4 lo = ld(mesh_node, 2 * j), hi = ld(mesh_node, 2 * j + 1);
        if (any(greaterThan(lo.xyz, bhi)) || any(lessThan(hi.xyz, blo))) continue;
        if (lo.w >= 0.0) {
            stack[top++] = int(hi.w);
            stack[top++] = int(lo.w);
            continue;
        }
        int t = int(hi.w);
        if (ld(mesh_tri, 3 * t + 1).xyz == vec3(0.0)) continue;   // degenerate
        if (cnt == 2) visit_edge(t, A, B);
        else visit_vertex(t, A, B, C);
    }
}
