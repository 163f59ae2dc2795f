// One texel (0, 0) of t0 into the texel of the output the viewport selects (a per-step record).
uniform sampler2D t0;
out vec4 o0;

void main() { o0 = texelFetch(t0, ivec2(0), 0); }
