// TR-BDF2's collider contacts in the xb form (core/bdf2.c wc_integ_contacts; the rule in
// core/bdf2.h "Contacts"), per particle in contact, after contact_begin and integ_prepare: its
// normal velocity relative to each collider is set to 0 (a = -(v - vc).n), xb's normal part to
// x.n + (h - he) vc.n - gap (gap: what begin left to close, -h (z.n - a)), z to 0, so that
// x_new = xb + he v_new with v_new.n = vc.n lands on the shell as it is at the stage's end; then
// v* = v + (xb - x) / he, and stage 1's v_prev = v (u_stage 1) or stage 2's mom = c2 (v - v_prev)
// (u_stage 2). Two contacts: the changes in the span of both normals (solve_pair). vc.n of the
// first contact is contact_begin's surface velocity (cvel) along normal 1, of the second C2's w.
// A particle without contact keeps everything.
// Outputs: o0 = v, o1 = xb, o2 = v*, o3 = v_prev (stage 1) or mom (stage 2), o4 = z.
uniform sampler2D x;       // after begin's correction
uniform sampler2D v;
uniform sampler2D xb;      // integ_prepare.glsl's
uniform sampler2D vstar;
uniform sampler2D mom;
uniform sampler2D vp;      // stage 1's start v_n (stage 1: integ_prepare.glsl's new one)
uniform sampler2D z;       // contact_begin's
uniform sampler2D c0;
uniform sampler2D c1;
uniform sampler2D c2;
uniform sampler2D cvel;    // contact_begin's o7
uniform int u_stage;
uniform float u_h;         // the stage's length
uniform float u_he;        // the system's step
uniform float u_c2;        // TR-BDF2's c2
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
out vec4 o4;

void main() {
    int i = self_index();
    o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); o4 = vec4(0.0);
    if (i >= u_n) return;
    vec4 vi = ld(v, i), xbi = ld(xb, i), vsi = ld(vstar, i), zi = ld(z, i), vpi = ld(vp, i);
    vec4 carried = u_stage == 1 ? vpi : ld(mom, i);
    o0 = vi; o1 = xbi; o2 = vsi; o3 = carried; o4 = zi;
    vec4 c = ld(c0, i);
    if (c.x < 0.0) return;
    bool two = c.y >= 0.0;
    vec3 xi = ld(x, i).xyz, n0 = ld(c1, i).xyz;
    vec4 c2i = ld(c2, i);
    vec3 n1 = two ? c2i.xyz : vec3(0.0);
    float vn0 = dot(ld(cvel, i).xyz, n0), vn1 = two ? c2i.w : 0.0;
    vec3 back = xbi.xyz - xi;
    float a0 = -(dot(vi.xyz, n0) - vn0), a1 = two ? -(dot(vi.xyz, n1) - vn1) : 0.0;
    float g0 = u_h * vn0 + u_h * (dot(zi.xyz, n0) - a0) - u_he * vn0 - dot(back, n0);
    float g1 = two ? u_h * vn1 + u_h * (dot(zi.xyz, n1) - a1) - u_he * vn1 - dot(back, n1) : 0.0;
    vec3 v1 = vi.xyz + solve_pair(n0, a0, n1, a1, two);
    vec3 xb1 = xbi.xyz + solve_pair(n0, g0, n1, g1, two);
    o0 = vec4(v1, vi.w);
    o1 = vec4(xb1, xbi.w);
    o2 = vec4(v1 + (xb1 - xi) / u_he, vsi.w);
    o3 = u_stage == 1 ? vec4(v1, vpi.w) : vec4(u_c2 * (v1 - vpi.xyz), carried.w);
    o4 = vec4(0.0, 0.0, 0.0, zi.w);
}
