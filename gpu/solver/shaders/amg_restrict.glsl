// Per node I of the next level: rc_I = sum over the nodes i of aggregate I of (r - A x)_i, the
// residual after the smoothing restricted by P^T (unsmoothed aggregation: identity blocks).
#pragma weft include amg_blocks
uniform isampler2D t0;  // next level's nodes: (member start, end, -, -)
uniform isampler2D t1;  // members: (node of this level, -, -, -)
uniform isampler2D t2;  // this level's rows
uniform isampler2D t3;  // cols
uniform sampler2D t4;   // blocks, row 0
uniform sampler2D t5;   // row 1
uniform sampler2D t6;   // row 2
uniform sampler2D t7;   // r
uniform sampler2D t8;   // x
out vec4 o0;

void main() {
    int I = self_index();
    if (I >= u_n) { o0 = vec4(0.0); return; }
    ivec4 m = ldi(t0, I);
    vec3 s = vec3(0.0);
    for (int e = m.x; e < m.y; ++e) {
        int i = ldi(t1, e).x;
        s += ld(t7, i).xyz - lvl_row(t2, t3, t4, t5, t6, t8, i);
    }
    o0 = vec4(s, 0.0);
}
