// Per particle: r = S (b - A x) (the filtered residual), and r.r in w for a reduction.
uniform isampler2D t0;  // particle blocks (row start, row end, diagonal block, -)
uniform isampler2D t1;  // block (row, column, -, -)
uniform sampler2D t2;   // A lo
uniform sampler2D t3;   // A hi
uniform sampler2D t4;   // x
uniform sampler2D t5;   // b
uniform sampler2D t6;   // S0
uniform sampler2D t7;   // S1
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 y = bsr_row(t0, t1, t2, t3, t4, i);
    vec3 r = filter_apply(ld(t6, i), ld(t7, i), ld(t5, i).xyz - y);
    o0 = vec4(r, dot(r, r));
}
