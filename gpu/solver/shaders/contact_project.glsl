// Contacts, step 5 (core/collide.c wc_contacts_project), per particle but the pinned ones (ndof 3
// without stick): push x out of the two deepest colliders' shells (re-picked up to
// PROJECT_ROUNDS times), then give v the nearest value with no inward relative normal velocity
// on the (up to two deepest) shells it lies on (d < SLOP).
// Outputs: o0 = x, o1 = v.
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D S1;   // ndof in z
uniform sampler2D c0;   // stick in w
uniform int u_nc;
out vec4 o0;
out vec4 o1;
#pragma weft include contact_geometry
const int PROJECT_ROUNDS = 3;

void deepest2(vec3 p, out B2 b) {
    b2_init(b);
    for (int k = 0; k < u_nc; ++k) {
        vec3 n;
        float d = shell_distance(k, p, n);
        if (d < HUGE_D) b2_add(b, k, d, n);
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
    B2 b;
    for (int round = 0; round < PROJECT_ROUNDS; ++round) {
        deepest2(xp, b);
        if (b.cnt == 0 || !(b.d.x < 0.0)) break;
        push_out(b, xp);
    }
    deepest2(xp, b);
    int cnt = 0;
    float a0 = 0.0, a1 = 0.0;
    float sl = slop_at(xp);
    if (b.cnt > 0 && b.d.x < sl) {
        a0 = dot(col(b.k.x, 4).xyz, b.n0) - dot(vp, b.n0);
        cnt = 1;
        if (b.cnt > 1 && b.d.y < sl) {
            a1 = dot(col(b.k.y, 4).xyz, b.n1) - dot(vp, b.n1);
            cnt = 2;
        }
    }
    if (cnt > 0) vp += halfspaces(b.n0, a0, b.n1, a1, cnt);
    o0 = vec4(xp, x4.w);
    o1 = vec4(vp, v4.w);
}
