// The filtered block-diagonal preconditioner of one particle (an include of dinv.glsl and
// pcg_group.glsl, not a pass): D~_i^{-1}, D~_i = S_i A_ii S_i + I - S_i (core/solver.c
// wcs_build_precond), symmetrised; identity where D~_i is singular or not finite. A is the
// particle's diagonal block, s0 and s1 its filter (common.glsl's filter_S).
mat3 dinv_block(mat3 A, vec4 s0, vec4 s1) {
    mat3 D = A;
    if (s1.z != 0.0) {
        mat3 S = filter_S(s0, s1);
        D = S * A * S + mat3(1.0) - S;
    }
    float det = determinant(D);
    mat3 inv = mat3(1.0);
    if (det != 0.0 && !isnan(det) && !isinf(det)) {
        inv = inverse(D);
        inv = 0.5 * (inv + transpose(inv));
        if (!finite3(inv[0]) || !finite3(inv[1]) || !finite3(inv[2])) inv = mat3(1.0);
    }
    return inv;
}
