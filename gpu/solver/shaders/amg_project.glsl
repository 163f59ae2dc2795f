// Per block k of the fine pattern: the multigrid's finest operator (core/amg_setup.c
// project_fine), P^ = S A S + a (I - S), a_i = trace(A_ii) / 3, as full blocks (amg_blocks.glsl).
#pragma weft include amg_blocks
uniform isampler2D t0;  // block (row, column, -, -)
uniform sampler2D t1;   // A lo
uniform sampler2D t2;   // A hi
uniform sampler2D t3;   // S0
uniform sampler2D t4;   // S1
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 b = ldi(t0, k);
    mat3 A = sym(ld(t1, k), ld(t2, k).xy);
    vec4 si0 = ld(t3, b.x), si1 = ld(t4, b.x), sj0 = ld(t3, b.y), sj1 = ld(t4, b.y);
    mat3 o = A;
    if (sj1.z != 0.0) o = o * filter_S(sj0, sj1);
    if (si1.z != 0.0) o = filter_S(si0, si1) * o;
    if (b.x == b.y && si1.z != 0.0) {
        float a = (A[0][0] + A[1][1] + A[2][2]) / 3.0;
        if (!(a > 0.0) || isinf(a)) a = 1.0;
        o += a * (mat3(1.0) - filter_S(si0, si1));
    }
    o0 = blk_row(o, 0);
    o1 = blk_row(o, 1);
    o2 = blk_row(o, 2);
}
