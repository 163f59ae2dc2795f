// Texel copy (state back-ups, and the bandwidth reference of the benchmarks).
uniform sampler2D src;
out vec4 o0;

void main() { o0 = texelFetch(src, ivec2(gl_FragCoord.xy), 0); }
