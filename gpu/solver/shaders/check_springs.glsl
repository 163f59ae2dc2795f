// Per spring: (elastic energy w k e^2 / 2, the strain (l - rest) / rest of a stretch spring (0 for
// the others), -, -), reduced as (sum, max). The extension e is l - rest, or for a seam spring
// max(0, l - rest x u_seam_scale) (core/forces.h wc_spring_extension).
uniform sampler2D x;
uniform isampler2D spring;     // (a, b, type, -)
uniform sampler2D spring_rest; // (rest length, stiffness weight w)
uniform vec4 u_k;              // stiffness per spring type
uniform float u_seam_scale;
out vec4 o0;

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); return; }
    ivec4 sp = ldi(spring, s);
    vec2 rw = ld(spring_rest, s).xy;
    float rest = rw.x;
    float l = length(ld(x, sp.x).xyz - ld(x, sp.y).xyz);
    float dl = l - rest;
    float strain = (sp.z == 0 && rest > 0.0) ? max(dl / rest, 0.0) : 0.0;
    float e = dl;
    if (sp.z == 3) {
        float r = rest * u_seam_scale;
        e = l > r ? l - r : 0.0;
    }
    if (isnan(l)) strain = uintBitsToFloat(0x7f800000u);
    o0 = vec4(0.5 * u_k[sp.z] * rw.y * e * e, strain, 0.0, 0.0);
}
