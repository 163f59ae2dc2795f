// Per particle: r = S (b - A x) (the filtered residual; A x with the penalty pairs' off-diagonal
// blocks, pairs_row.glsl), and r.r in w for a reduction; o1 = (|A| |x|)_i and its square in w:
// the size of the terms the row's product sums, whose float rounding (2^-24 of it) is the floor
// a residual computed in float cannot go below (wg_solve.c: PCG stops there).
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform isampler2D block;   // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D x;
uniform sampler2D b;
uniform sampler2D S0;
uniform sampler2D S1;
#pragma weft include pairs_row
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    ivec4 row = ldi(pblocks, i);
    vec3 y = vec3(0.0), ya = vec3(0.0);
    for (int k = row.x; k < row.y; ++k) {
        mat3 B = sym(ld(a_lo, k), ld(a_hi, k).xy);
        vec3 xj = ld(x, ldi(block, k).y).xyz;
        y += B * xj;
        ya += mat3(abs(B[0]), abs(B[1]), abs(B[2])) * abs(xj);
    }
    y += pairs_row(x, i);   // the penalty pairs' off-diagonal blocks (not in the floor's size)
    vec3 r = filter_apply(ld(S0, i), ld(S1, i), ld(b, i).xyz - y);
    o0 = vec4(r, dot(r, r));
    o1 = vec4(ya, dot(ya, ya));
}
