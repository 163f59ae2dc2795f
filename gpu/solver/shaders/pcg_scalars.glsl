// The PCG scalars (pcg_scalars_rules.glsl) as a fragment pass over one texel, reading the
// reductions' one-texel results: o0..o2 = s0..s2.
#pragma weft include pcg_scalars_rules
uniform sampler2D scalars0; // the last pcg_scalars outputs
uniform sampler2D scalars1;
uniform sampler2D sum;      // a reduction whose w is the sum wanted (residual0^2 or cq)
uniform sampler2D dots;     // a reduction whose xy are (delta, rr)
uniform sampler2D scalars2;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    vec4 s0 = texelFetch(scalars0, ivec2(0), 0), s1 = texelFetch(scalars1, ivec2(0), 0), s2 = texelFetch(scalars2, ivec2(0), 0);
    pcg_scalars_rules(s0, s1, s2, texelFetch(sum, ivec2(0), 0).w, texelFetch(dots, ivec2(0), 0).xy);
    o0 = s0;
    o1 = s1;
    o2 = s2;
}
