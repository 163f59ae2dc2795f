// Per block k of the BSR pattern (row i, column j): A_ii = m_i I - sum of J over row i's springs,
// A_ij = sum of J over the springs joining i and j (core/assemble.c); TR-BDF2's implicit air adds
// he L_i to A_ii (core/bdf2.c wc_integ_forces; u_air_he = 0: none); Newton's systems add kinetic
// friction's frozen Fa_i to A_ii (u_friction; core/newton.c newton_system). Blocks are symmetric.
// Outputs: o0 = (a00, a01, a02, a11), o1 = (a12, a22) of block k.
uniform isampler2D block;      // (row, column, spring list start, end)
uniform isampler2D block_list; // per list entry: spring
uniform sampler2D mass;        // (m, 1/m)
uniform sampler2D spring_f;    // springs.glsl o0: (f, J00)
uniform sampler2D spring_w;    // springs.glsl o1: (w, J11)
uniform sampler2D spring_j;    // springs.glsl o2: (J01, J02, J12, J22)
uniform sampler2D air_lo;      // per particle: the lumped drag Jacobian L (air_lump.glsl o0, o1)
uniform sampler2D air_hi;
uniform sampler2D fric_lo;     // per particle: friction's Fa (newton_friction.glsl o0, o1)
uniform sampler2D fric_hi;
uniform float u_air_he;
uniform int u_friction;
out vec4 o0;
out vec2 o1;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec2(0.0); return; }
    ivec4 bi = ldi(block, k);
    vec4 lo = vec4(0.0);
    vec2 hi = vec2(0.0);
    for (int e = bi.z; e < bi.w; ++e) {
        int s = ldi(block_list, e).x;
        vec4 a = ld(spring_f, s), b = ld(spring_w, s), c = ld(spring_j, s);
        lo += vec4(a.w, c.x, c.y, b.w);
        hi += c.zw;
    }
    if (bi.x == bi.y) {
        float m = ld(mass, bi.x).x;
        lo = vec4(m, 0.0, 0.0, m) - lo;
        hi = vec2(0.0, m) - hi;
        if (u_air_he != 0.0) {
            lo += u_air_he * ld(air_lo, bi.x);
            hi += u_air_he * ld(air_hi, bi.x).xy;
        }
        if (u_friction != 0) {
            lo += ld(fric_lo, bi.x);
            hi += ld(fric_hi, bi.x).xy;
        }
    }
    o0 = lo;
    o1 = hi;
}
