// Per particle: the filtered block-diagonal preconditioner D~_i^{-1} (dinv_block.glsl).
// Outputs: o0 = (d00, d01, d02, d11), o1 = (d12, d22) of the (symmetric) inverse.
#pragma weft include dinv_block
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
    mat3 inv = dinv_block(sym(ld(a_lo, dk), ld(a_hi, dk).xy), ld(S0, i), ld(S1, i));
    o0 = sym_lo(inv);
    o1 = sym_hi(inv);
}
