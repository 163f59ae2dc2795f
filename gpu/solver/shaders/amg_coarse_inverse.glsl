// The multigrid's coarsest solve as a product (an include of amg_coarse_groups.glsl and
// pcg_group_amg.glsl, not a pass): node I's x = sum over the level's nodes J of the inverse's
// 3x3 block (I, J) times r_J, with amg_factor_groups.glsl's inverse (texel (c, r) = M^-1[r][c]).
// Each node is one invocation's: a coarsest level of n nodes takes 9 n fetches an invocation
// where the triangular solves took (3 n)^2 in one.
uniform sampler2D factor;

mat3 coarse_inverse_block(int I, int J) {
    mat3 B;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) B[c][a] = texelFetch(factor, ivec2(3 * J + c, 3 * I + a), 0).x;
    return B;
}
