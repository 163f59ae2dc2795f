// Per particle, Newton's right-hand side at the iterate w (core/newton.c newton_system):
// g = -grad Phi(w) = h f_total(w) - m w, with h f_total from assemble_b.glsl over
// newton_springs.glsl's forces. Output: o0 = g.
uniform sampler2D hf;          // assemble_b.glsl o0: h f_total at w
uniform sampler2D w;
uniform sampler2D mass;        // (m, 1/m)
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    o0 = vec4(ld(hf, i).xyz - ld(mass, i).x * ld(w, i).xyz, 0.0);
}
