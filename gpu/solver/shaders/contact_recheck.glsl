// Contacts, step 3b (core/collide.c wc_contacts_friction_recheck), per sticking particle: with
// r = (A dv - b)_i of the solved system, it slides when |S r| exceeds B = sum mu_k max(N_k, 0)
// (N_k the components of r on the normals): S = Sn, z = z_n, ndof = contacts, damping
// h c = B / w with w = (|S r| - B) / m.
// Outputs: o0 = S0, o1 = S1, o2 = z, o3 = b, o4 = C0 (stick in w), o5 = C2 (changed in w),
// o6/o7 = A_ii (lo, hi) per particle.
uniform sampler2D t0;   // v (start of the substep)
uniform sampler2D t1;   // mass (m, 1/m)
uniform sampler2D t2;   // dv (the solve's result)
uniform sampler2D t3;   // S0
uniform sampler2D t4;   // S1
uniform sampler2D t5;   // z
uniform sampler2D t6;   // b
uniform isampler2D t7;  // particle blocks (row start, row end, diagonal block, -)
uniform isampler2D t8;  // block (row, column, -, -)
uniform sampler2D t9;   // A lo
uniform sampler2D t10;  // A hi
uniform sampler2D t11;  // C0
uniform sampler2D t12;  // C1
uniform sampler2D t13;  // C2
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
#pragma weft include contact_friction_rules

void main() {
    int i = self_index();
    if (i >= u_n) {
        o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); o4 = vec4(0.0); o5 = vec4(0.0);
        o6 = vec4(0.0); o7 = vec4(0.0);
        return;
    }
    vec4 s0 = ld(t3, i), s1 = ld(t4, i), z = ld(t5, i), b = ld(t6, i), c = ld(t11, i), c2 = ld(t13, i);
    ivec4 pb = ldi(t7, i);
    vec4 a0 = ld(t9, pb.z), a1 = ld(t10, pb.z);
    o0 = s0; o1 = s1; o2 = z; o3 = b; o4 = c; o5 = vec4(c2.xyz, 0.0); o6 = a0; o7 = a1;
    if (c.w == 0.0) return;
    int k0 = int(c.x), k1 = int(c.y);
    int cnt = (k0 >= 0 ? 1 : 0) + (k1 >= 0 ? 1 : 0);
    if (cnt == 0 || k0 >= u_nc || k1 >= u_nc) return;
    float mu0 = col(k0, 0).w, mu1 = cnt > 1 ? col(k1, 0).w : 0.0;
    if (!(mu0 > 0.0) && !(cnt > 1 && mu1 > 0.0)) return;
    vec3 n0 = ld(t12, i).xyz, n1 = c2.xyz;
    mat3 Sn = free_projector(n0, n1, cnt);
    vec3 u = Sn * (ld(t0, i).xyz - col(k0, 4).xyz);
    vec3 r = -b.xyz;
    for (int k = pb.x; k < pb.y; ++k) r += sym(ld(t9, k), ld(t10, k).xy) * ld(t2, ldi(t8, k).y).xyz;
    vec2 imp = contact_impulses(r, n0, n1, cnt);
    float bound = mu0 * max(imp.x, 0.0) + (cnt > 1 ? mu1 * max(imp.y, 0.0) : 0.0);
    float held = length(Sn * r);
    if (holds(bound, held)) return;
    float m = ld(t1, i).x, w = (held - bound) / m;
    o0 = sym_lo(Sn); o1 = vec4(sym_hi(Sn), float(cnt), 0.0); o2 = vec4(z.xyz - Sn * z.xyz, 0.0);
    o4 = vec4(c.xyz, 0.0);
    o5 = vec4(c2.xyz, 1.0);
    if (bound > 0.0 && w > 0.0) {
        float hc = bound / w;
        mat3 A = sym(a0, a1.xy) + hc * Sn;
        o3 = vec4(b.xyz - hc * u, b.w);
        o6 = sym_lo(A); o7 = vec4(sym_hi(A), 0.0, 0.0);
    }
}
