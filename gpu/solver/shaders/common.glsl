// Prelude of every solver pass (prepended by wg_device.c; the #version line comes from here).
// Arrays live in textures: item i of any array is texel (i mod W, i div W), W = 2^u_shift the
// layout width shared by all of a cloth's arrays. A pass renders one output texel per item of
// its output array (u_n items); texels past u_n (the end of the last row) are written as zeros
// so that reductions over whole textures see nothing there.
#version 330 core
uniform int u_n;
uniform int u_shift;

ivec2 tc(int i) { return ivec2(i & ((1 << u_shift) - 1), i >> u_shift); }
int self_index() { ivec2 p = ivec2(gl_FragCoord.xy); return (p.y << u_shift) + p.x; }
vec4 ld(sampler2D t, int i) { return texelFetch(t, tc(i), 0); }
ivec4 ldi(isampler2D t, int i) { return texelFetch(t, tc(i), 0); }

// Symmetric 3x3 blocks are stored as two texels: (a00, a01, a02, a11) and (a12, a22).
mat3 sym(vec4 a, vec2 b) { return mat3(a.x, a.y, a.z, a.y, a.w, b.x, a.z, b.x, b.y); }
vec4 sym_lo(mat3 m) { return vec4(m[0][0], m[1][0], m[2][0], m[1][1]); }
vec2 sym_hi(mat3 m) { return vec2(m[2][1], m[2][2]); }

// The constraint filter of a particle: S (symmetric projection) and its constrained DOF count,
// from S0 = (s00, s01, s02, s11), S1 = (s12, s22, ndof, -).
mat3 filter_S(vec4 s0, vec4 s1) { return sym(s0, s1.xy); }
vec3 filter_apply(vec4 s0, vec4 s1, vec3 v) { return s1.z == 0.0 ? v : filter_S(s0, s1) * v; }

// The vector d in the span of n1 (and n2 when two) with d.n1 = a1 (and d.n2 = a2): core/vec3.h
// v3_span2, the contacts' prescribed normal motion.
vec3 solve_pair(vec3 n1, float a1, vec3 n2, float a2, bool two) {
    if (!two) return n1 * a1;
    float c = dot(n1, n2), g = 1.0 - c * c;
    return n1 * ((a1 - c * a2) / g) + n2 * ((a2 - c * a1) / g);
}

bool finite3(vec3 v) { return !any(isnan(v)) && !any(isinf(v)); }

// Row i of y = A x over the BSR pattern: pb = particle blocks (row start, end, ...), blk = block
// (row, column, ...), A as two symmetric-block textures. Gather only: row i reads its own blocks.
vec3 bsr_row(isampler2D pb, isampler2D blk, sampler2D a_lo, sampler2D a_hi, sampler2D x, int i) {
    ivec4 r = ldi(pb, i);
    vec3 y = vec3(0.0);
    for (int k = r.x; k < r.y; ++k) y += sym(ld(a_lo, k), ld(a_hi, k).xy) * ld(x, ldi(blk, k).y).xyz;
    return y;
}
