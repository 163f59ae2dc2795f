// One level of a reduction: output texel p combines the input texels of the block
// [8 p, 8 p + 8) (clipped to the input), channel c summed (u_mode[c] 0) or maximised (1).
// Repeated until one texel is left; a 1000 x 1000 array takes 4 levels.
uniform sampler2D src;
uniform ivec2 u_in;
uniform ivec4 u_mode;
out vec4 o0;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy) * 8;
    ivec2 e = min(p + 8, u_in);
    bvec4 take_max = notEqual(u_mode, ivec4(0));
    vec4 acc = vec4(0.0);
    for (int y = p.y; y < e.y; ++y)
        for (int x = p.x; x < e.x; ++x) {
            vec4 v = texelFetch(src, ivec2(x, y), 0);
            // a selection, not a blend: a float mix weighs the other candidate by 0, and a +inf
            // in a max channel (a non-finite state) made 0 inf = NaN there on IEEE drivers
            acc = mix(acc + v, max(acc, v), take_max);
        }
    o0 = acc;
}
