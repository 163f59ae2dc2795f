// Per particle: dv = z + S dv (constrained particles; free ones unchanged). A non-finite guess is
// replaced by z. With u_to_z, dv = z (the answer of a zero right-hand side).
uniform sampler2D t0;   // dv
uniform sampler2D t1;   // S0
uniform sampler2D t2;   // S1
uniform sampler2D t3;   // z
uniform int u_to_z;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 dv = ld(t0, i).xyz, z = ld(t3, i).xyz;
    vec4 s1 = ld(t2, i);
    if (u_to_z != 0 || !finite3(dv)) { o0 = vec4(z, 0.0); return; }
    if (s1.z != 0.0) dv = z + filter_S(ld(t1, i), s1) * dv;
    o0 = vec4(dv, 0.0);
}
