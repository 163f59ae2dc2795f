// Per particle: dv = z + S dv (constrained particles; free ones unchanged). A non-finite guess is
// replaced by z. With u_to_z, dv = z (the answer of a zero right-hand side).
uniform sampler2D dv;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D z;
uniform int u_to_z;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 d = ld(dv, i).xyz, zi = ld(z, i).xyz;
    vec4 s1 = ld(S1, i);
    if (u_to_z != 0 || !finite3(d)) { o0 = vec4(zi, 0.0); return; }
    if (s1.z != 0.0) d = zi + filter_S(ld(S0, i), s1) * d;
    o0 = vec4(d, 0.0);
}
