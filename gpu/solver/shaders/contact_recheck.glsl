// Contacts, step 3b (core/collide.c wc_contacts_friction_recheck), per sticking particle: with
// r = (A dv - b)_i of the solved system, it slides when |S r| exceeds B = sum mu_k max(N_k, 0)
// (N_k the components of r on the normals): S = Sn, z = z_n, ndof = contacts, damping
// h c = B / w with w = (|S r| - B) / m.
// Outputs: o0 = S0, o1 = S1, o2 = z, o3 = b, o4 = C0 (stick in w), o5 = C2 (changed in w),
// o6/o7 = A_ii (lo, hi) per particle.
uniform sampler2D v;        // the substep's start
uniform sampler2D mass;     // (m, 1/m)
uniform sampler2D dv;       // the solve's result
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D z;
uniform sampler2D b;
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform isampler2D block;   // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D c0;
uniform sampler2D c1;
uniform sampler2D c2;
uniform sampler2D cvel;     // the first contact's surface velocity (contact_begin's o7)
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
    vec4 s0 = ld(S0, i), s1 = ld(S1, i), zi = ld(z, i), bi = ld(b, i), c = ld(c0, i), c2i = ld(c2, i);
    ivec4 pb = ldi(pblocks, i);
    vec4 a0 = ld(a_lo, pb.z), a1 = ld(a_hi, pb.z);
    o0 = s0; o1 = s1; o2 = zi; o3 = bi; o4 = c; o5 = vec4(c2i.xyz, 0.0); o6 = a0; o7 = a1;
    if (c.w == 0.0) return;
    int k0 = int(c.x), k1 = int(c.y);
    int cnt = (k0 >= 0 ? 1 : 0) + (k1 >= 0 ? 1 : 0);
    if (cnt == 0 || k0 >= u_nc || k1 >= u_nc) return;
    float mu0 = col(k0, 0).w, mu1 = cnt > 1 ? col(k1, 0).w : 0.0;
    if (!(mu0 > 0.0) && !(cnt > 1 && mu1 > 0.0)) return;
    vec3 n0 = ld(c1, i).xyz, n1 = c2i.xyz;
    mat3 Sn = free_projector(n0, n1, cnt);
    vec3 u = Sn * (ld(v, i).xyz - ld(cvel, i).xyz);
    vec3 r = -bi.xyz;
    for (int k = pb.x; k < pb.y; ++k) r += sym(ld(a_lo, k), ld(a_hi, k).xy) * ld(dv, ldi(block, k).y).xyz;
    vec2 imp = contact_impulses(r, n0, n1, cnt);
    float bound = mu0 * max(imp.x, 0.0) + (cnt > 1 ? mu1 * max(imp.y, 0.0) : 0.0);
    float held = length(Sn * r);
    if (holds(bound, held)) return;
    float m = ld(mass, i).x, w = (held - bound) / m;
    o0 = sym_lo(Sn); o1 = vec4(sym_hi(Sn), float(cnt), 0.0); o2 = vec4(zi.xyz - Sn * zi.xyz, 0.0);
    o4 = vec4(c.xyz, 0.0);
    o5 = vec4(c2i.xyz, 1.0);
    if (bound > 0.0 && w > 0.0) {
        float hc = bound / w;
        mat3 A = sym(a0, a1.xy) + hc * Sn;
        o3 = vec4(bi.xyz - hc * u, bi.w);
        o6 = sym_lo(A); o7 = vec4(sym_hi(A), 0.0, 0.0);
    }
}
