// Contacts, step 2 (core/collide.c wc_contacts_friction), per particle in contact with friction:
// the impulse it needs to stick, predicted alone (q = m (z - u - mom) - h f, mom TR-BDF2's
// momentum term, u_mom; 0 for the others) and held by its springs
// (q = A_ii (z - u) - b_i), u = S (v - vc) the relative velocity in its free directions. It sticks
// when both are within Coulomb's bound B = sum mu_k max(N_k, 0): S = 0, z = z_n - u, ndof 3; else
// it slides with the implicit damping A_ii += h c S, b_i -= h c u, h c = B / w.
// Outputs: o0 = S0, o1 = S1, o2 = z, o3 = b, o4 = C0 (stick in w), o5/o6 = A_ii (lo, hi) per
// particle (contact_diag puts them into the blocks).
uniform sampler2D v;        // the substep's start
uniform sampler2D mass;     // (m, 1/m)
uniform sampler2D ftot;     // f_total (assemble_b.glsl)
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D z;
uniform sampler2D b;
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D c0;
uniform sampler2D c1;
uniform sampler2D c2;
uniform sampler2D cvel;     // the first contact's surface velocity (contact_begin's o7)
uniform sampler2D mom;      // the stage's momentum term, read with u_mom (core's friction mom)
uniform float u_h;
uniform int u_mom;
uniform int u_nc;
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
out vec4 o4;
out vec4 o5;
out vec4 o6;
#pragma weft include contact_geometry
#pragma weft include contact_friction_rules

void main() {
    int i = self_index();
    if (i >= u_n) {
        o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); o4 = vec4(0.0); o5 = vec4(0.0); o6 = vec4(0.0);
        return;
    }
    vec4 s0 = ld(S0, i), s1 = ld(S1, i), zi = ld(z, i), bi = ld(b, i), c = ld(c0, i);
    int dk = ldi(pblocks, i).z;
    vec4 a0 = ld(a_lo, dk), a1 = ld(a_hi, dk);
    o0 = s0; o1 = s1; o2 = zi; o3 = bi; o4 = c; o5 = a0; o6 = a1;
    int k0 = int(c.x), k1 = int(c.y);
    int cnt = (k0 >= 0 ? 1 : 0) + (k1 >= 0 ? 1 : 0);
    if (cnt == 0 || k0 >= u_nc || k1 >= u_nc) return;
    float mu0 = col(k0, 0).w, mu1 = cnt > 1 ? col(k1, 0).w : 0.0;
    if (!(mu0 > 0.0) && !(cnt > 1 && mu1 > 0.0)) return;
    float m = ld(mass, i).x;
    if (int(s1.z) != cnt || !(m > 0.0)) return;
    vec3 n0 = ld(c1, i).xyz, n1 = ld(c2, i).xyz;
    mat3 Sn = free_projector(n0, n1, cnt);
    vec3 u = Sn * (ld(v, i).xyz - ld(cvel, i).xyz);
    mat3 A = sym(a0, a1.xy);
    vec3 w0 = zi.xyz - u;
    vec3 qa = m * w0 - u_h * ld(ftot, i).xyz;
    if (u_mom != 0) qa -= m * ld(mom, i).xyz;
    vec3 qn = A * w0 - bi.xyz;
    vec2 ia = contact_impulses(qa, n0, n1, cnt), in_ = contact_impulses(qn, n0, n1, cnt);
    float ba = mu0 * max(ia.x, 0.0) + (cnt > 1 ? mu1 * max(ia.y, 0.0) : 0.0);
    float bn = mu0 * max(in_.x, 0.0) + (cnt > 1 ? mu1 * max(in_.y, 0.0) : 0.0);
    vec3 rta = Sn * qa, rtn = Sn * qn;
    float ha = length(rta), hn = length(rtn);
    bool stick = holds(ba, ha) && holds(bn, hn);
    float w = (ha - ba) / m;
    if (!(w > 0.0) && hn > bn) {
        vec3 t = rtn / hn;
        float stiff = dot(t, A * t);
        if (stiff > 0.0) w = (hn - bn) / stiff;
    }
    vec3 zn = zi.xyz - Sn * zi.xyz;
    if (stick) {
        o0 = vec4(0.0); o1 = vec4(0.0, 0.0, 3.0, 0.0); o2 = vec4(zn - u, 0.0);
        o4 = vec4(c.xyz, 1.0);
        return;
    }
    o0 = sym_lo(Sn); o1 = vec4(sym_hi(Sn), float(cnt), 0.0); o2 = vec4(zn, 0.0);
    o4 = vec4(c.xyz, 0.0);
    if (ba > 0.0 && w > 0.0) {
        float hc = ba / w;
        A += hc * Sn;
        o3 = vec4(bi.xyz - hc * u, bi.w);
        o5 = sym_lo(A); o6 = vec4(sym_hi(A), 0.0, 0.0);
    }
}
