// Per spring: (elastic energy k (l - rest)^2 / 2, the strain (l - rest) / rest of a stretch spring
// (0 for the others), -, -), reduced as (sum, max).
uniform sampler2D x;
uniform isampler2D spring;     // (a, b, type, -)
uniform sampler2D spring_rest; // rest length
uniform vec3 u_k;
out vec4 o0;

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); return; }
    ivec4 sp = ldi(spring, s);
    float rest = ld(spring_rest, s).r;
    float l = length(ld(x, sp.x).xyz - ld(x, sp.y).xyz);
    float dl = l - rest;
    float strain = (sp.z == 0 && rest > 0.0) ? max(dl / rest, 0.0) : 0.0;
    if (isnan(l)) strain = uintBitsToFloat(0x7f800000u);
    o0 = vec4(0.5 * u_k[sp.z] * dl * dl, strain, 0.0, 0.0);
}
