// Per particle: r = S (b - A x) (the filtered residual), and r.r in w for a reduction; o1 =
// (|A| |x|)_i and its square in w: the size of the terms the row's product sums, whose float
// rounding (2^-24 of it) is the floor a residual computed in float cannot go below (wg_solve.c:
// PCG stops there).
uniform isampler2D t0;  // particle blocks (row start, row end, diagonal block, -)
uniform isampler2D t1;  // block (row, column, -, -)
uniform sampler2D t2;   // A lo
uniform sampler2D t3;   // A hi
uniform sampler2D t4;   // x
uniform sampler2D t5;   // b
uniform sampler2D t6;   // S0
uniform sampler2D t7;   // S1
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    ivec4 row = ldi(t0, i);
    vec3 y = vec3(0.0), ya = vec3(0.0);
    for (int k = row.x; k < row.y; ++k) {
        mat3 B = sym(ld(t2, k), ld(t3, k).xy);
        vec3 xj = ld(t4, ldi(t1, k).y).xyz;
        y += B * xj;
        ya += mat3(abs(B[0]), abs(B[1]), abs(B[2])) * abs(xj);
    }
    vec3 r = filter_apply(ld(t6, i), ld(t7, i), ld(t5, i).xyz - y);
    o0 = vec4(r, dot(r, r));
    o1 = vec4(ya, dot(ya, ya));
}
