// Per particle: y = A x over the BSR rows (gather: row i reads its own blocks and x at their
// columns). With u_filter, q = S (A x) and w = c.q for the PCG step (c = x).
uniform isampler2D t0;  // particle blocks (row start, row end, diagonal block, -)
uniform isampler2D t1;  // block (row, column, -, -)
uniform sampler2D t2;   // A lo
uniform sampler2D t3;   // A hi
uniform sampler2D t4;   // x
uniform sampler2D t5;   // S0
uniform sampler2D t6;   // S1
uniform int u_filter;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 y = bsr_row(t0, t1, t2, t3, t4, i);
    if (u_filter != 0) {
        y = filter_apply(ld(t5, i), ld(t6, i), y);
        o0 = vec4(y, dot(ld(t4, i).xyz, y));
    } else {
        o0 = vec4(y, 0.0);
    }
}
