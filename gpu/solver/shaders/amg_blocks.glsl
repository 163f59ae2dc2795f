// The GPU multigrid's levels (wg_amg.c; an include, not a pass). A level's operator is held as
// full 3x3 blocks in three textures, row r of block k in texel k of texture r (xyz): the
// projected fine operator S A S + a (I - S) is not symmetric block by block, nor are the
// Galerkin sums of its blocks. Patterns: amg_level_inputs.glsl.
mat3 blk_rows(vec3 r0, vec3 r1, vec3 r2) { return transpose(mat3(r0, r1, r2)); }
mat3 blk(sampler2D a0, sampler2D a1, sampler2D a2, int k) { return blk_rows(ld(a0, k).xyz, ld(a1, k).xyz, ld(a2, k).xyz); }
// Group k's range in a list (wg_amg_smooth.c upload_keyed: RG32I, x its first item, y its count
// << 5 | 3 bits << 2 | 2 bits of shifts): (first, end, the 3 bits, the shifts for ld_item).
ivec4 ld_range(isampler2D t, int k) {
    ivec4 q = ldi(t, k);
    return ivec4(q.x, q.x + (q.y >> 5), (q.y >> 2) & 7, q.y & 3);
}
// Item m of a list held two items a texel, (a, b) of item 2t in texel t's xy and of 2t + 1 in its
// zw (the smoothed prolongator's lists, wg_amg_smooth.c upload_keyed), for a group whose range
// texel's w is w: a group that borrows another's items (rotations: the odd one of a pair of
// coarse nodes, whose entries are the even one's + 1) adds 1 to a (bit 0) and b (bit 1).
ivec2 ld_item(isampler2D t, int m, int w) {
    ivec4 q = ldi(t, m >> 1);
    return ((m & 1) == 0 ? q.xy : q.zw) + ivec2(w & 1, (w >> 1) & 1);
}
// row r of m as a texel
vec4 blk_row(mat3 m, int r) { return vec4(m[0][r], m[1][r], m[2][r], 0.0); }

// The Chebyshev smoother's bound on lambda_max(D^-1 A) from the power iterations' reduction
// (x: sum v.Av, y: sum v.Dv, w: a warm setup's floor, amg_power.glsl): 1.1 x the larger of the
// Rayleigh quotient and the floor (core/amg.h WC_AMG_SAFETY), or 2 where the quotient is not
// positive and finite (core/amg_setup.c largest_eigenvalue).
float lvl_bound(sampler2D red) {
    vec4 s = texelFetch(red, ivec2(0), 0);
    float l = s.x / s.y;
    return (l > 0.0 && !isinf(l) && !isnan(l)) ? 1.1 * max(l, s.w) : 2.0;
}
