// Texel copy (state back-ups, and the bandwidth reference of the benchmarks).
uniform sampler2D t0;
out vec4 o0;

void main() { o0 = texelFetch(t0, ivec2(gl_FragCoord.xy), 0); }
