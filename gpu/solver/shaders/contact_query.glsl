// Included by contact_begin and contact_project after contact_geometry (#pragma weft include
// contact_query): each collider's candidate for a particle (query: shell distance, outward
// normal, the surface's velocity there) and the push out of the shells (core/collide.c query and
// push_out). Triangle meshes (core/mesh_query.c wc_mesh_closest, in float): the closest point
// within reach, searched through the body's BVH (core's tree, refitted by core every substep),
// in core's order (preorder, left child first, boxes beyond the best distance skipped), with its
// side rules. The mesh textures (wg_mesh.c): mesh_vert 3 texels a vertex (substep start, end,
// velocity), mesh_tri 3 a triangle (vertex indices as floats, unit normal at the start, at the
// end; zero: degenerate), mesh_node 2 a node ((min, left child), (max, right child); a leaf:
// (min, -1), (max, triangle)); a mesh's collider row: (3, -, thickness, friction), (root node,
// h x fastest vertex speed, -, -), -, (-, push_speed), 0.
uniform sampler2D mesh_vert;
uniform sampler2D mesh_tri;
uniform sampler2D mesh_node;
const float FACE_W = 1e-9;
const float DEEP_REACH = 0.02;
const float BIG2 = 1e38;
// Two triangles give the same closest point (an edge or a vertex) within this relative part of
// the squared distance: core's 1e-10 is below float's resolution.
const float TIE_REL = 1e-6;
// For the side rule, also a tie within float's rounding of the coordinates in the squared
// distances, 2 |p - q| x TIE_COORD x slack (a few units in the last place of the coordinates), at
// most TIE_WIDE of it: above TIE_REL at millimetres (a point over a box's corner, just inside the
// top face: the top's distance and a side face's, through the rim), the rule as before within
// a tenth of a millimetre of the surface.
const float TIE_COORD = 0.1;
const float TIE_WIDE = 1e-3;

float closest_on_segment(vec3 p, vec3 a, vec3 b, out float s) {
    vec3 ab = b - a;
    float l2 = dot(ab, ab);
    s = l2 > 0.0 ? clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    vec3 d = p - (a + s * ab);
    return dot(d, d);
}

// core/geom.c wc_closest_on_triangle (Ericson 5.1.5): the barycentric weights w of the closest point.
vec3 closest_weights(vec3 p, vec3 a, vec3 b, vec3 c) {
    vec3 ab = b - a, ac = c - a, n = cross(ab, ac);
    float nn = dot(n, n), scale = dot(ab, ab) * dot(ac, ac);
    if (!(nn > 1e-24 * scale) || scale == 0.0) {
        float s, best, d;
        vec3 w;
        best = closest_on_segment(p, a, b, s);
        w = vec3(1.0 - s, s, 0.0);
        d = closest_on_segment(p, b, c, s);
        if (d < best) { best = d; w = vec3(0.0, 1.0 - s, s); }
        d = closest_on_segment(p, a, c, s);
        if (d < best) { best = d; w = vec3(1.0 - s, 0.0, s); }
        return w;
    }
    vec3 ap = p - a;
    float d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return vec3(1.0, 0.0, 0.0);
    vec3 bp = p - b;
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return vec3(0.0, 1.0, 0.0);
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) { float v = d1 / (d1 - d3); return vec3(1.0 - v, v, 0.0); }
    vec3 cp = p - c;
    float d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return vec3(0.0, 0.0, 1.0);
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) { float v = d2 / (d2 - d6); return vec3(1.0 - v, 0.0, v); }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        float v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return vec3(0.0, 1.0 - v, v);
    }
    float den = 1.0 / (va + vb + vc);
    return vec3(1.0 - vb * den - vc * den, vb * den, vc * den);
}

float box_dist2(vec3 lo, vec3 hi, vec3 p) {
    vec3 g = max(max(lo - p, p - hi), vec3(0.0));
    return dot(g, g);
}

ivec3 tri_verts(int t) { return ivec3(ld(mesh_tri, 3 * t).xyz); }

// Signed distance from p to mesh (root node) at the substep's start (end 0) or end (end 1), the
// outward normal n and the surface velocity vc at the closest point; HUGE_D when no triangle lies
// within reach.
float mesh_closest(int root, vec3 p, int end, float reach, out vec3 n, out vec3 vc) {
    vec3 blo = p - vec3(reach), bhi = p + vec3(reach), ap = abs(p);
    float slack = 1e-6 * max(1.0, max(ap.x, max(ap.y, ap.z)));
    float best = BIG2, bound2 = BIG2, cosb = 0.0, side = 1.0;
    int tri = -1;
    vec3 wb = vec3(0.0), qb = vec3(0.0);
    int stack[66];
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
        int j = stack[--top];
        vec4 lo = ld(mesh_node, 2 * j), hi = ld(mesh_node, 2 * j + 1);
        if (any(greaterThan(lo.xyz, bhi)) || any(lessThan(hi.xyz, blo)) || box_dist2(lo.xyz, hi.xyz, p) > bound2)
            continue;
        if (lo.w >= 0.0) {
            stack[top++] = int(hi.w);
            stack[top++] = int(lo.w);
            continue;
        }
        int t = int(hi.w);
        vec3 fn = ld(mesh_tri, 3 * t + 1 + end).xyz;
        if (fn == vec3(0.0)) continue;   // degenerate
        ivec3 iv = tri_verts(t);
        vec3 a = ld(mesh_vert, 3 * iv.x + end).xyz, b = ld(mesh_vert, 3 * iv.y + end).xyz;
        vec3 c = ld(mesh_vert, 3 * iv.z + end).xyz;
        vec3 w = closest_weights(p, a, b, c);
        vec3 q = w.x * a + w.y * b + w.z * c, d = p - q;
        float d2 = dot(d, d), len = sqrt(d2), dn = dot(d, fn);
        float cs = len > 0.0 ? dn / len : 0.0;
        float tol = TIE_REL * best + 1e-30;
        // the side from the triangle most facing p among those tied to float's rounding (tie),
        // whichever comes first; the closest point stays the strictly nearest
        float tie = tol + min(2.0 * sqrt(best) * slack * TIE_COORD, TIE_WIDE * best);
        if (d2 < best - tol || tri < 0) {
            bool was = tri >= 0 && d2 >= best - tie && cosb > abs(cs);
            best = d2; tri = t; wb = w; qb = q;
            if (!was) { cosb = abs(cs); side = dn < 0.0 ? -1.0 : 1.0; }
        } else if (d2 <= best + tie && abs(cs) > cosb) {
            cosb = abs(cs); side = dn < 0.0 ? -1.0 : 1.0;
            if (d2 < best) best = d2;
        }
        float r = sqrt(best) * (1.0 + TIE_REL) + slack;
        bound2 = min(bound2, r * r);
    }
    float dist = sqrt(best);
    if (tri < 0 || dist > reach) return HUGE_D;
    float d;
    vec3 fn = ld(mesh_tri, 3 * tri + 1 + end).xyz;
    if ((wb.x > FACE_W && wb.y > FACE_W && wb.z > FACE_W) || !(dist > 1e-12)) {
        n = fn;
        d = dot(p - qb, fn);
    } else {
        n = (p - qb) * (side / dist);
        d = side * dist;
    }
    ivec3 iv = tri_verts(tri);
    vc = wb.x * ld(mesh_vert, 3 * iv.x + 2).xyz + wb.y * ld(mesh_vert, 3 * iv.y + 2).xyz
       + wb.z * ld(mesh_vert, 3 * iv.z + 2).xyz;
    return d;
}

// Collider k's candidate for a particle at p moving by at most `move` (m) in the substep: the
// shell distance (HUGE_D: a mesh out of reach), the outward normal and the surface velocity.
float query(int k, vec3 p, int end, float move, out vec3 n, out vec3 vc) {
    vec4 c0 = col(k, 0);
    if (int(c0.x) == 3) {
        vec4 c1 = col(k, 1);
        float reach = c0.z + move + c1.y + DEEP_REACH + 1e-6;
        float d = mesh_closest(int(c1.x), p, end, reach, n, vc);
        if (!(d < HUGE_D)) { n = vec3(0.0, 1.0, 0.0); vc = vec3(0.0); return HUGE_D; }
        return d - c0.z;
    }
    vc = col(k, 4).xyz;
    return shell_distance(k, p, n);
}

// core's requery: a plane candidate (q.w 1: a crossed triangle's plane) keeps its plane, normal
// and velocity, the rest query again.
float requery(int k, vec4 q, vec3 pn, vec3 pv, vec3 p, int end, float move, out vec3 n, out vec3 vc) {
    if (q.w != 0.0) {
        n = pn;
        vc = pv;
        return dot(p - q.xyz, pn) - col(k, 0).z;
    }
    return query(k, p, end, move, n, vc);
}

// The push_speed cap (m) of the contacts in b over a substep of length h; HUGE_D: none.
float push_cap(B2 b, float h) {
    float cap = HUGE_D;
    for (int s = 0; s < b.cnt; ++s) {
        float ps = col(s == 0 ? b.k.x : b.k.y, 3).w;
        if (ps > 0.0) cap = min(cap, ps * h);
    }
    return cap;
}

// Move p out of the shells of b's colliders (core/collide.c push_out), the whole move at most cap
// (the last step shortened to it); *used the path's length.
bool push_out(B2 b, int end, float move, float cap, inout vec3 p, out float used) {
    bool act0 = false, act1 = false, moved = false;
    used = 0.0;
    for (int pass = 0; pass < CORRECT_PASSES && used < cap; ++pass) {
        vec3 n0, n1 = vec3(0.0), vc, e;
        float d0 = requery(b.k.x, b.q0, b.n0, b.v0, p, end, move, n0, vc), d1 = 0.0;
        if (!(d0 < HUGE_D)) d0 = 0.0;   // a mesh that moved out of reach: nothing to push
        if (d0 < 0.0) act0 = true;
        if (b.cnt > 1) {
            d1 = requery(b.k.y, b.q1, b.n1, b.v1, p, end, move, n1, vc);
            if (!(d1 < HUGE_D)) d1 = 0.0;
            if (d1 < 0.0) act1 = true;
        }
        if (!act0 && !act1) break;
        vec3 delta;
        if (act0 && act1 && ortho(n0, n1, e) >= PARALLEL_MIN) delta = solve_pair(n0, -d0, n1, -d1, true);
        else if (act0) delta = -d0 * n0;
        else delta = -d1 * n1;
        float len = length(delta);
        if (len == 0.0) break;
        if (used + len > cap) {
            delta *= (cap - used) / len;
            len = cap - used;
        }
        p += delta;
        used += len;
        moved = true;
    }
    return moved;
}
