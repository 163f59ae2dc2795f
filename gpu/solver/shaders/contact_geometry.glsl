// Included by the contact passes (#pragma weft include contact_geometry): collider geometry
// (core/collide.c, in float). The colliders' texture has one row per collider: (type, radius,
// thickness, friction), (plane normal, offset), (center / a, -), (b, push_speed), (velocity, -);
// the meshes come first, with rows of their own (contact_query.glsl).
uniform sampler2D colliders;
const float HUGE_D = 1e30;
const float SLOP = 1e-9;
// "On the shell" in float: SLOP is below float resolution at metre scale, so the GPU widens it
// by a few ulps of the position (a distance after a push out is exact to rounding only).
float slop_at(vec3 p) { vec3 a = abs(p); return SLOP + 1e-6 * max(1.0, max(a.x, max(a.y, a.z))); }
const float PARALLEL_MIN = 0.1;
const int CORRECT_PASSES = 4;
vec4 col(int k, int j) { return texelFetch(colliders, ivec2(j, k), 0); }

float ball_distance(vec3 p, vec3 q, float r, bool has_u, vec3 u, out vec3 n) {
    vec3 d = p - q;
    float len = length(d);
    if (len > 0.0) { n = d / len; return len - r; }
    n = vec3(0.0, 1.0, 0.0);
    if (has_u) {
        vec3 w = n - dot(n, u) * u;
        if (dot(w, w) < 0.25) w = vec3(1.0, 0.0, 0.0) - u.x * u;
        n = w / length(w);
    }
    return -r;
}

// Distance to the shell (thickness included) and the outward normal.
float shell_distance(int k, vec3 p, out vec3 n) {
    vec4 c0 = col(k, 0);
    int type = int(c0.x);
    float d;
    if (type == 0) {
        vec4 c1 = col(k, 1);
        n = c1.xyz;
        d = dot(c1.xyz, p) - c1.w;
    } else if (type == 1) {
        d = ball_distance(p, col(k, 2).xyz, c0.y, false, vec3(0.0), n);
    } else if (type == 2) {
        vec3 a = col(k, 2).xyz, ab = col(k, 3).xyz - a;
        float l2 = dot(ab, ab);
        if (!(l2 > 0.0)) {
            d = ball_distance(p, a, c0.y, false, vec3(0.0), n);
        } else {
            float t = clamp(dot(p - a, ab) / l2, 0.0, 1.0);
            d = ball_distance(p, a + t * ab, c0.y, true, ab / sqrt(l2), n);
        }
    } else {
        n = vec3(0.0, 1.0, 0.0);
        return HUGE_D;
    }
    return d - c0.z;
}

float ortho(vec3 n1, vec3 n2, out vec3 e) {
    e = n2 - dot(n1, n2) * n1;
    float l = length(e);
    if (l > 0.0) e /= l;
    return l;
}

// The two smallest candidates (collider, shell distance, normal, surface velocity; q: a mesh
// triangle's plane the particle's path crosses, its point and 1 in w, else 0).
struct B2 { ivec2 k; vec2 d; vec3 n0; vec3 n1; vec3 v0; vec3 v1; vec4 q0; vec4 q1; int cnt; };
void b2_init(out B2 b) {
    b.k = ivec2(-1); b.d = vec2(HUGE_D); b.n0 = vec3(0.0); b.n1 = vec3(0.0); b.v0 = vec3(0.0); b.v1 = vec3(0.0);
    b.q0 = vec4(0.0); b.q1 = vec4(0.0); b.cnt = 0;
}
void b2_add(inout B2 b, int k, float d, vec3 n, vec3 vc, vec4 q) {
    if (b.cnt == 0 || d < b.d.x) {
        b.k.y = b.k.x; b.d.y = b.d.x; b.n1 = b.n0; b.v1 = b.v0; b.q1 = b.q0;
        b.k.x = k; b.d.x = d; b.n0 = n; b.v0 = vc; b.q0 = q;
    } else if (b.cnt == 1 || d < b.d.y) {
        b.k.y = k; b.d.y = d; b.n1 = n; b.v1 = vc; b.q1 = q;
    }
    if (b.cnt < 2) ++b.cnt;
}
void b2_prune(inout B2 b) {
    vec3 e;
    if (b.cnt == 2 && ortho(b.n0, b.n1, e) < PARALLEL_MIN) { b.cnt = 1; b.k.y = -1; }
}
