// Per node I of the next level: rc_I = sum over the nodes i of aggregate I of (r - A x)_i, the
// residual after the smoothing restricted by P^T (unsmoothed aggregation: identity blocks). This
// level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform isampler2D t9;  // next level's nodes: (member start, end, -, -)
uniform isampler2D t10; // members: (node of this level, -, -, -)
uniform sampler2D t11;  // r
uniform sampler2D t12;  // x
out vec4 o0;

void main() {
    int I = self_index();
    if (I >= u_n) { o0 = vec4(0.0); return; }
    ivec4 m = ldi(t9, I);
    vec3 s = vec3(0.0);
    for (int e = m.x; e < m.y; ++e) {
        int i = ldi(t10, e).x;
        s += ld(t11, i).xyz - op_row(i, t12, t12, false);
    }
    o0 = vec4(s, 0.0);
}
