// Per particle: dv = z + S dv (constrained particles; free ones unchanged). A non-finite guess is
// replaced by z. With u_to_z, dv = z (the answer of a zero right-hand side). project_row.glsl.
#pragma weft include project_row
uniform sampler2D dv;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D z;
uniform int u_to_z;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    o0 = vec4(project_row(ld(dv, i).xyz, ld(z, i).xyz, ld(S0, i), ld(S1, i), u_to_z != 0), 0.0);
}
