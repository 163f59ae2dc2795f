// The self-collision walks' rules (an include of self_pairs_walk_groups.glsl and
// self_idle_walk_groups.glsl, not a pass): a query's particles, the walk of a tree, a pair's
// particles, core's adjacency rules and the support lower bound of a pair's distance.
// A query q is a particle q < u_np (against the triangle tree), else the edge q - u_np (against
// the edges above it in the edge tree). A pair's particles ids: the first split (1: a vertex, 2:
// an edge) the first feature's, the rest the second's (a triangle, an edge).
// The includer defines, after this, visit (a leaf's pair) and too_deep (the walk's stack full).
uniform sampler2D tnode;       // the triangle tree's nodes: (min, left), (max, right or element)
uniform sampler2D enode;       // the edge tree's
uniform sampler2D elem;        // (particles a, b, c or -1, -) the triangles, then the edges
uniform sampler2D part;        // a particle's (seam links first, end, tangled, -)
uniform sampler2D seam;        // the seam links (x)
uniform int u_np, u_nt;

// query q's particles (the particle's second: -1)
ivec2 query_particles(int q) { return q < u_np ? ivec2(q, -1) : ivec2(ld(elem, u_nt + (q - u_np)).xy); }

// the vertex i against triangle t (split 1)
ivec4 tri_ids(int i, int t) {
    vec4 tv = ld(elem, t);
    return ivec4(i, int(tv.x), int(tv.y), int(tv.z));
}

// the edge e against the edge f (split 2)
ivec4 edge_ids(int e, int f) {
    vec4 ea = ld(elem, u_nt + e), eb = ld(elem, u_nt + f);
    return ivec4(int(ea.x), int(ea.y), int(eb.x), int(eb.y));
}

// a and b share a particle (a == b: same, the includer's rule) or are sewn by a seam link
bool linked(int a, int b, bool same) {
    if (a == b) return same;
    vec4 r = ld(part, a);
    for (int k = int(r.x); k < int(r.y); ++k)
        if (int(ld(seam, k).x) == b) return true;
    return false;
}

bool tangled(int a) { return ld(part, a).z != 0.0; }

// core's adjacency rules drop the pair: a particle of each feature linked (shared or sewn), or
// all four tangled at rest
bool adjacent(ivec4 ids, int split, bool same) {
    for (int i = 0; i < split; ++i)
        for (int j = split; j < 4; ++j)
            if (linked(ids[i], ids[j], same)) return true;
    return tangled(ids.x) && tangled(ids.y) && tangled(ids.z) && tangled(ids.w);
}

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

// The support bound of the pair's distance at the positions pos: for any unit u,
// |p - y| >= (p - y).u >= min over the corners of the difference set, so with u along the float
// closest points' difference lb is within rounding of the distance; ext is the pair's extent
// (its largest corner offset, for the includer's rounding allowance). False when there is no
// bound (the closest points coincide, or are not finite).
bool support_bound(sampler2D pos, ivec4 ids, int split, out float lb, out float ext) {
    if (split == 1) {
        vec3 p = ld(pos, ids.x).xyz;
        vec3 a = ld(pos, ids.y).xyz - p, b = ld(pos, ids.z).xyz - p, c = ld(pos, ids.w).xyz - p;
        vec3 q = closest_tri(a, b, c);
        float l = length(q);
        if (!(l > 0.0)) return false;
        vec3 u = -q / l;   // from the triangle towards p
        lb = min(min(dot(-a, u), dot(-b, u)), dot(-c, u));
        ext = max(max(length(a), length(b)), length(c));
        return true;
    }
    vec3 o = ld(pos, ids.x).xyz;
    vec3 p0 = vec3(0.0), p1 = ld(pos, ids.y).xyz - o, q0 = ld(pos, ids.z).xyz - o, q1 = ld(pos, ids.w).xyz - o;
    vec2 st = closest_seg(p0, p1, q0, q1);
    vec3 w = p1 * st.x - (q0 + (q1 - q0) * st.y);
    float l = length(w);
    if (!(l > 0.0)) return false;
    vec3 u = w / l;   // from the second edge towards the first
    lb = min(min(dot(p0 - q0, u), dot(p0 - q1, u)), min(dot(p1 - q0, u), dot(p1 - q1, u)));
    ext = max(max(length(p1), length(q0)), max(length(q1), length(p1 - q0)));
    return true;
}

// the includer's: query q meets leaf prim, the pair's particles ids (split as above)
void visit(int q, int prim, ivec4 ids, int split);
// the includer's: a node deeper than the walk's stack holds (deeper than core's trees go); true
// ends the walk, false skips the node
bool too_deep();

// Query q's walk of its tree (root node 0), core's order (left child first): every leaf whose
// box meets [blo, bhi] is visited, an edge's only above it.
void walk(int q, vec3 blo, vec3 bhi) {
    bool vq = q < u_np;
    int e = q - u_np;
    int stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int j = stack[--top];
        vec4 lo = vq ? ld(tnode, 2 * j) : ld(enode, 2 * j), hi = vq ? ld(tnode, 2 * j + 1) : ld(enode, 2 * j + 1);
        if (any(greaterThan(lo.xyz, bhi)) || any(lessThan(hi.xyz, blo))) continue;
        if (lo.w >= 0.0) {
            if (top + 2 > 64) {
                if (too_deep()) return;
                continue;
            }
            stack[top++] = int(hi.w);
            stack[top++] = int(lo.w);
            continue;
        }
        int prim = int(hi.w);
        if (vq) visit(q, prim, tri_ids(q, prim), 1);
        else if (prim > e) visit(q, prim, edge_ids(e, prim), 2);
    }
}
