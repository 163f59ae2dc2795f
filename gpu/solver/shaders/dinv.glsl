// Per particle: the filtered block-diagonal preconditioner D~_i^{-1}, D~_i = S_i A_ii S_i + I - S_i
// (core/solver.c wcs_build_precond): identity where D~_i is singular or not finite.
// Outputs: o0 = (d00, d01, d02, d11), o1 = (d12, d22) of the (symmetric) inverse.
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D S0;
uniform sampler2D S1;
out vec4 o0;
out vec2 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec2(0.0); return; }
    int dk = ldi(pblocks, i).z;
    mat3 A = sym(ld(a_lo, dk), ld(a_hi, dk).xy);
    vec4 s0 = ld(S0, i), s1 = ld(S1, i);
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
    o0 = sym_lo(inv);
    o1 = sym_hi(inv);
}
