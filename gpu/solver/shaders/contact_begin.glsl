// Contacts, step 1 (core/collide.c wc_contacts_begin), per particle: find contacts (held: in
// contact with k last substep and d < h |vr| + SLOP; new: d < -SLOP or, unless released, it
// reaches the shell this substep), keep the two smallest d (parallel second normal dropped),
// push x out onto the shells, write the filter S = I - n1 n1^T (- e2 e2^T) and z (relative
// normal velocity -max(d, 0) / h after dv). Particles with pin ndof >= 2 keep their filter and
// get no contact. Contact state: C0 = (collider 1, collider 2, released, stick) (-1: none),
// C1 = (normal 1, in contact), C2 = (normal 2, w: the second contact's surface velocity along
// normal 2, which TR-BDF2's integ_contacts.glsl reads; contact_recheck puts "changed" there). A mesh's candidate is the first triangle
// the particle's path x -> x + h v crosses (contact_ccd.glsl: always taken, on that triangle's
// plane), else its closest point within reach at the substep's start (contact_query.glsl); a
// collider with a push_speed caps
// the correction at push_speed x h (the share used goes to project through o7.w).
// Outputs: o0 = x, o1 = S0, o2 = S1, o3 = z, o4 = C0, o5 = C1, o6 = C2, o7 = (the first contact's
// surface velocity, the correction's length).
uniform sampler2D x;
uniform sampler2D v;    // the substep's start
uniform sampler2D S0;   // pins.glsl
uniform sampler2D S1;   // pins.glsl
uniform sampler2D z;    // pins.glsl
uniform sampler2D c0;   // C0 of the last substep
uniform float u_h;
uniform int u_nc;
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
out vec4 o4;
out vec4 o5;
out vec4 o6;
out vec4 o7;
#pragma weft include contact_geometry
#pragma weft include contact_query
#pragma weft include contact_ccd

void main() {
    int i = self_index();
    o4 = vec4(-1.0, -1.0, 0.0, 0.0); o5 = vec4(0.0); o6 = vec4(0.0); o7 = vec4(0.0);
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); o4 = vec4(0.0); return; }
    vec4 x4 = ld(x, i);
    vec3 xi = x4.xyz, vi = ld(v, i).xyz;
    vec4 s1 = ld(S1, i);
    o0 = x4; o1 = ld(S0, i); o2 = s1; o3 = ld(z, i);
    if (s1.z >= 2.0) return;   // pinned (line or point): no contact
    o1 = vec4(1.0, 0.0, 0.0, 1.0); o2 = vec4(0.0, 1.0, 0.0, 0.0); o3 = vec4(0.0);
    vec4 c = ld(c0, i);
    bool released = c.z != 0.0;
    int h0 = int(c.x), h1 = int(c.y);
    float sl = slop_at(xi), move = u_h * length(vi);
    vec3 x1 = xi + u_h * vi;
    B2 b;
    b2_init(b);
    for (int k = 0; k < u_nc; ++k) {
        vec3 n, vc;
        vec4 q;
        float d;
        if (crossing(k, xi, x1, 0, xi, d, n, vc, q)) {
            b2_add(b, k, d, n, vc, q);
            continue;
        }
        d = query(k, xi, 0, move, n, vc);
        if (!(d < HUGE_D)) continue;
        vec3 vr = vi - vc;
        float vn = dot(vr, n);
        bool take;
        if (h0 == k || h1 == k) take = d < u_h * length(vr) + sl;
        else take = d < -sl || (!released && d < u_h * max(0.0, -vn) + sl);
        if (take) b2_add(b, k, d, n, vc, vec4(0.0));
    }
    b2_prune(b);
    if (b.cnt == 0) return;
    float pushed;
    push_out(b, 0, move, push_cap(b, u_h), xi, pushed);
    vec3 n0, n1 = vec3(0.0), vc0, vc1 = vec3(0.0), e2;
    float d0 = requery(b.k.x, b.q0, b.n0, b.v0, xi, 0, move, n0, vc0), d1 = 0.0;
    if (!(d0 < HUGE_D)) d0 = 0.0;
    if (b.cnt > 1) {
        d1 = requery(b.k.y, b.q1, b.n1, b.v1, xi, 0, move, n1, vc1);
        if (!(d1 < HUGE_D)) d1 = 0.0;
    }
    int cnt = b.cnt;
    if (cnt == 2 && ortho(n0, n1, e2) < PARALLEL_MIN) cnt = 1;
    float a0 = (u_h > 0.0 ? -max(d0, 0.0) / u_h : 0.0) - dot(vi - vc0, n0), a1 = 0.0;
    if (cnt > 1) a1 = (u_h > 0.0 ? -max(d1, 0.0) / u_h : 0.0) - dot(vi - vc1, n1);
    mat3 S = mat3(1.0) - outerProduct(n0, n0);
    if (cnt == 2) S -= outerProduct(e2, e2);
    o0 = vec4(xi, x4.w);
    o1 = sym_lo(S);
    o2 = vec4(sym_hi(S), float(cnt), 0.0);
    o3 = vec4(solve_pair(n0, a0, n1, a1, cnt > 1), 0.0);
    o4 = vec4(float(b.k.x), cnt > 1 ? float(b.k.y) : -1.0, 0.0, 0.0);
    o5 = vec4(n0, 1.0);
    o6 = cnt > 1 ? vec4(n1, dot(vc1, n1)) : vec4(0.0);
    o7 = vec4(vc0, pushed);
}
