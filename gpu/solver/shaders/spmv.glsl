// Per particle: y = A x over the BSR rows (gather: row i reads its own blocks and x at their
// columns), then the penalty pairs' off-diagonal blocks (pairs_row.glsl). With u_filter,
// q = S (A x) and w = c.q for the PCG step (c = x).
#pragma weft include spmv_inputs
#pragma weft include pairs_row
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 y = bsr_row(pblocks, block, a_lo, a_hi, x, i) + pairs_row(x, i);
    if (u_filter != 0) {
        y = filter_apply(ld(S0, i), ld(S1, i), y);
        o0 = vec4(y, dot(ld(x, i).xyz, y));
    } else {
        o0 = vec4(y, 0.0);
    }
}
