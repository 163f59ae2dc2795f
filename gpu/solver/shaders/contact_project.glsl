// Contacts, step 5 (core/collide.c wc_contacts_project), per particle but the pinned ones (ndof 3
// without stick): push x out of the two deepest colliders' shells (re-picked up to
// PROJECT_ROUNDS times), then give v the nearest value with no inward relative normal velocity
// on the (up to two deepest) shells it lies on (d < SLOP). Meshes at the substep's end: first a
// particle whose path since begin (x_sub -> x) crossed a triangle goes back in front of the first
// it crossed, at the thickness, its inward velocity relative to it removed (contact_ccd.glsl);
// then the closest points, searched within the particle's move since begin. A collider with a
// push_speed caps the push at what begin left of push_speed x h (cvel.w: begin's share).
// Outputs: o0 = x, o1 = v.
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D S1;   // ndof in z
uniform sampler2D c0;   // stick in w
uniform sampler2D x_sub;   // x after begin (x itself without meshes)
uniform sampler2D cvel;    // begin's o7: the correction's length in w
uniform int u_nc;
uniform float u_h;
out vec4 o0;
out vec4 o1;
#pragma weft include contact_geometry
#pragma weft include contact_query
#pragma weft include contact_ccd
const int PROJECT_ROUNDS = 3;

void deepest2(vec3 p, float move, out B2 b) {
    b2_init(b);
    for (int k = 0; k < u_nc; ++k) {
        vec3 n, vc;
        float d = query(k, p, 1, move, n, vc);
        if (d < HUGE_D) b2_add(b, k, d, n, vc, vec4(0.0));
    }
    b2_prune(b);
}

vec3 halfspaces(vec3 n1, float a1, vec3 n2, float a2, int cnt) {
    bool bad1 = a1 > 0.0, bad2 = cnt > 1 && a2 > 0.0;
    if (!bad1 && !bad2) return vec3(0.0);
    if (cnt == 1) return n1 * a1;
    float c = dot(n1, n2);
    if (bad1 && a1 * c >= a2) return n1 * a1;
    if (bad2 && a2 * c >= a1) return n2 * a2;
    return solve_pair(n1, a1, n2, a2, true);
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec4 x4 = ld(x, i), v4 = ld(v, i);
    o0 = x4; o1 = v4;
    if (ld(S1, i).z == 3.0 && ld(c0, i).w == 0.0) return;   // a pin
    vec3 xp = x4.xyz, vp = v4.xyz;
    vec3 x0 = ld(x_sub, i).xyz;
    for (int k = 0; k < u_nc; ++k) {   // collide.c uncross
        float d;
        vec3 n, vc;
        vec4 q;
        if (!crossing(k, x0, xp, 1, xp, d, n, vc, q)) continue;
        if (d < 0.0) xp -= d * n;
        float a = dot(vc, n) - dot(vp, n);
        if (a > 0.0) vp += a * n;
    }
    float move = length(xp - x0), pushed = ld(cvel, i).w, spent = 0.0;
    B2 b;
    bool fresh = false;   // b is deepest2 at xp
    for (int round = 0; round < PROJECT_ROUNDS; ++round) {
        deepest2(xp, move, b);
        fresh = true;
        if (b.cnt == 0 || !(b.d.x < 0.0)) break;
        float cap = push_cap(b, u_h), by;
        if (cap < HUGE_D) cap = max(0.0, cap - pushed - spent);
        if (!(cap > 0.0)) break;
        if (push_out(b, 1, move, cap, xp, by)) fresh = false;
        spent += by;
    }
    if (!fresh) deepest2(xp, move, b);
    int cnt = 0;
    float a0 = 0.0, a1 = 0.0;
    float sl = slop_at(xp);
    if (b.cnt > 0 && b.d.x < sl) {
        a0 = dot(b.v0, b.n0) - dot(vp, b.n0);
        cnt = 1;
        if (b.cnt > 1 && b.d.y < sl) {
            a1 = dot(b.v1, b.n1) - dot(vp, b.n1);
            cnt = 2;
        }
    }
    if (cnt > 0) vp += halfspaces(b.n0, a0, b.n1, a1, cnt);
    o0 = vec4(xp, x4.w);
    o1 = vec4(vp, v4.w);
}
