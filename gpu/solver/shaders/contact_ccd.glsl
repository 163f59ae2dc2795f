// Included by contact_begin and contact_project after contact_query (#pragma weft include
// contact_ccd): the meshes' continuous test (core/mesh_query.c wc_mesh_ccd, core/geom.c
// wc_ccd_point_triangle, in float): the earliest time a point moving linearly from p0 to p1 over
// the substep crosses a triangle moving from its start to its end positions, from the triangle's
// front to its back, passing within eta of it. The candidate times are the roots in [0, 1] of the
// cubic that says the point and the triangle are coplanar (split at its turning points,
// bisected), the start and the end when it is identically zero (its coefficients within 1e-6 of
// their terms' scale: core's 1e-12 is below float's resolution).
const float CCD_ETA = 1e-6;

float cubic_at(vec4 c, float t) { return ((c.w * t + c.z) * t + c.y) * t + c.x; }

// The roots of c.x + c.y t + c.z t^2 + c.w t^3 in [0, 1], ascending, into r; -1: identically zero.
int cubic_roots01(vec4 c, float scale, out vec3 r) {
    r = vec3(0.0);
    float tol = 1e-6 * (scale > 0.0 ? scale : 1.0);
    if (all(lessThanEqual(abs(c), vec4(tol)))) return -1;
    float cut[4];
    int nc = 0;
    cut[nc++] = 0.0;
    float qa = 3.0 * c.w, qb = 2.0 * c.z, qc = c.y;
    float ext[2];
    int ne = 0;
    if (abs(qa) > 1e-30) {
        float disc = qb * qb - 4.0 * qa * qc;
        if (disc >= 0.0) {
            float sq = sqrt(disc), q = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));
            float r1 = q / qa, r2 = q != 0.0 ? qc / q : r1;
            ext[ne++] = min(r1, r2);
            ext[ne++] = max(r1, r2);
        }
    } else if (abs(qb) > 1e-30) {
        ext[ne++] = -qc / qb;
    }
    for (int i = 0; i < ne; ++i)
        if (ext[i] > 0.0 && ext[i] < 1.0 && ext[i] > cut[nc - 1]) cut[nc++] = ext[i];
    cut[nc++] = 1.0;
    int nr = 0;
    for (int i = 0; i + 1 < nc; ++i) {
        float lo = cut[i], hi = cut[i + 1], flo = cubic_at(c, lo), fhi = cubic_at(c, hi), root;
        if (abs(flo) <= tol) {
            root = lo;
        } else if (abs(fhi) <= tol) {
            root = hi;
        } else if ((flo < 0.0) != (fhi < 0.0)) {
            for (int it = 0; it < 40 && hi - lo > 1e-7; ++it) {
                float mid = 0.5 * (lo + hi), fm = cubic_at(c, mid);
                if ((fm < 0.0) == (flo < 0.0)) { lo = mid; flo = fm; }
                else hi = mid;
            }
            root = 0.5 * (lo + hi);
        } else {
            continue;
        }
        if (nr == 0 || root > r[nr - 1] + 1e-7) r[nr++] = root;
    }
    return nr;
}

// wc_ccd_point_triangle: the first candidate time at which p is within eta of the triangle abc.
bool ccd_point_triangle(vec3 p0, vec3 a0, vec3 b0, vec3 c0, vec3 p1, vec3 a1, vec3 b1, vec3 c1, float eta,
                        out float t, out vec3 w) {
    vec3 u0 = p0 - a0, v0 = b0 - a0, w0 = c0 - a0;
    vec3 u1 = (p1 - a1) - u0, v1 = (b1 - a1) - v0, w1 = (c1 - a1) - w0;
    vec4 c;
    vec3 x = cross(v0, w0);
    c.x = dot(u0, x);
    c.y = dot(u1, x);
    x = cross(v1, w0);
    c.y += dot(u0, x);
    c.z = dot(u1, x);
    x = cross(v0, w1);
    c.y += dot(u0, x);
    c.z += dot(u1, x);
    x = cross(v1, w1);
    c.z += dot(u0, x);
    c.w = dot(u1, x);
    float scale = (length(u0) + length(u1)) * (length(v0) + length(v1)) * (length(w0) + length(w1));
    vec3 times;
    int nr = cubic_roots01(c, scale, times);
    if (nr < 0) { times = vec3(0.0, 1.0, 0.0); nr = 2; }
    t = 0.0;
    w = vec3(0.0);
    for (int i = 0; i < nr; ++i) {
        float s = times[i];
        vec3 p = mix(p0, p1, s), a = mix(a0, a1, s), b = mix(b0, b1, s), cc = mix(c0, c1, s);
        vec3 wi = closest_weights(p, a, b, cc), d = p - (wi.x * a + wi.y * b + wi.z * cc);
        if (dot(d, d) <= eta * eta) { t = s; w = wi; return true; }
    }
    return false;
}

// wc_mesh_ccd over the mesh under root: the earliest crossing (ties: the first in the tree's order).
bool mesh_ccd(int root, vec3 p0, vec3 p1, float eta, out int tri, out vec3 wb) {
    vec3 blo = min(p0, p1) - vec3(eta), bhi = max(p0, p1) + vec3(eta);
    float tb = 0.0;
    tri = -1;
    wb = vec3(0.0);
    int stack[66];
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
        int j = stack[--top];
        vec4 lo = ld(mesh_node, 2 * j), hi = ld(mesh_node, 2 * j + 1);
        if (any(greaterThan(lo.xyz, bhi)) || any(lessThan(hi.xyz, blo))) continue;
        if (lo.w >= 0.0) {
            stack[top++] = int(hi.w);
            stack[top++] = int(lo.w);
            continue;
        }
        int t = int(hi.w);
        ivec3 iv = tri_verts(t);
        vec3 a0 = ld(mesh_vert, 3 * iv.x).xyz, b0 = ld(mesh_vert, 3 * iv.y).xyz, c0 = ld(mesh_vert, 3 * iv.z).xyz;
        vec3 a1 = ld(mesh_vert, 3 * iv.x + 1).xyz, b1 = ld(mesh_vert, 3 * iv.y + 1).xyz;
        vec3 c1 = ld(mesh_vert, 3 * iv.z + 1).xyz;
        // from the front at the start to the back at the end
        if (!(dot(p0 - a0, ld(mesh_tri, 3 * t + 1).xyz) > 0.0) || !(dot(p1 - a1, ld(mesh_tri, 3 * t + 2).xyz) < 0.0))
            continue;
        float tt;
        vec3 w;
        if (!ccd_point_triangle(p0, a0, b0, c0, p1, a1, b1, c1, eta, tt, w)) continue;
        if (tri < 0 || tt < tb) { tb = tt; tri = t; wb = w; }
    }
    return tri >= 0;
}

// collide.c crossing: the triangle of mesh collider k that the path p0 -> p1 crosses first, as a
// plane candidate at the substep's start (end 0) or end (end 1), measured at p: the shell distance
// from the triangle's plane, its normal, the crossing point's velocity, the plane's point (w 1).
bool crossing(int k, vec3 p0, vec3 p1, int end, vec3 p, out float d, out vec3 n, out vec3 vc, out vec4 q) {
    d = HUGE_D; n = vec3(0.0, 1.0, 0.0); vc = vec3(0.0); q = vec4(0.0);
    if (int(col(k, 0).x) != 3) return false;
    vec3 ap = abs(p0);
    float eta = CCD_ETA + 1e-7 * max(1.0, max(ap.x, max(ap.y, ap.z)));   // float's reach at p0
    int tri;
    vec3 w;
    if (!mesh_ccd(int(col(k, 1).x), p0, p1, eta, tri, w)) return false;
    ivec3 iv = tri_verts(tri);
    n = ld(mesh_tri, 3 * tri + 1 + end).xyz;
    q = vec4(w.x * ld(mesh_vert, 3 * iv.x + end).xyz + w.y * ld(mesh_vert, 3 * iv.y + end).xyz
             + w.z * ld(mesh_vert, 3 * iv.z + end).xyz, 1.0);
    vc = w.x * ld(mesh_vert, 3 * iv.x + 2).xyz + w.y * ld(mesh_vert, 3 * iv.y + 2).xyz
       + w.z * ld(mesh_vert, 3 * iv.z + 2).xyz;
    d = dot(p - q.xyz, n) - col(k, 0).z;
    return true;
}
