// One texel (0, 0) of src into the texel of the output the viewport selects (a per-step record).
uniform sampler2D src;
out vec4 o0;

void main() { o0 = texelFetch(src, ivec2(0), 0); }
