// Contacts, step 2 (core/collide.c wc_contacts_friction), per particle in contact with friction:
// the impulse it needs to stick, predicted alone (q = m (z - u) - h f) and held by its springs
// (q = A_ii (z - u) - b_i), u = S (v - vc) the relative velocity in its free directions. It sticks
// when both are within Coulomb's bound B = sum mu_k max(N_k, 0): S = 0, z = z_n - u, ndof 3; else
// it slides with the implicit damping A_ii += h c S, b_i -= h c u, h c = B / w.
// Outputs: o0 = S0, o1 = S1, o2 = z, o3 = b, o4 = C0 (stick in w), o5/o6 = A_ii (lo, hi) per
// particle (contact_diag puts them into the blocks).
uniform sampler2D t0;   // v (start of the substep)
uniform sampler2D t1;   // mass (m, 1/m)
uniform sampler2D t2;   // f total
uniform sampler2D t3;   // S0
uniform sampler2D t4;   // S1
uniform sampler2D t5;   // z
uniform sampler2D t6;   // b
uniform isampler2D t7;  // particle blocks (row start, row end, diagonal block, -)
uniform sampler2D t8;   // A lo
uniform sampler2D t9;   // A hi
uniform sampler2D t10;  // C0
uniform sampler2D t11;  // C1
uniform sampler2D t12;  // C2
uniform float u_h;
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
    vec4 s0 = ld(t3, i), s1 = ld(t4, i), z = ld(t5, i), b = ld(t6, i), c = ld(t10, i);
    int dk = ldi(t7, i).z;
    vec4 a0 = ld(t8, dk), a1 = ld(t9, dk);
    o0 = s0; o1 = s1; o2 = z; o3 = b; o4 = c; o5 = a0; o6 = a1;
    int k0 = int(c.x), k1 = int(c.y);
    int cnt = (k0 >= 0 ? 1 : 0) + (k1 >= 0 ? 1 : 0);
    if (cnt == 0 || k0 >= u_nc || k1 >= u_nc) return;
    float mu0 = col(k0, 0).w, mu1 = cnt > 1 ? col(k1, 0).w : 0.0;
    if (!(mu0 > 0.0) && !(cnt > 1 && mu1 > 0.0)) return;
    float m = ld(t1, i).x;
    if (int(s1.z) != cnt || !(m > 0.0)) return;
    vec3 n0 = ld(t11, i).xyz, n1 = ld(t12, i).xyz;
    mat3 Sn = free_projector(n0, n1, cnt);
    vec3 u = Sn * (ld(t0, i).xyz - col(k0, 4).xyz);
    mat3 A = sym(a0, a1.xy);
    vec3 w0 = z.xyz - u;
    vec3 qa = m * w0 - u_h * ld(t2, i).xyz;
    vec3 qn = A * w0 - b.xyz;
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
    vec3 zn = z.xyz - Sn * z.xyz;
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
        o3 = vec4(b.xyz - hc * u, b.w);
        o5 = sym_lo(A); o6 = vec4(sym_hi(A), 0.0, 0.0);
    }
}
