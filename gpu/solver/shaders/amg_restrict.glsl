// Per node I of the next level: rc_I = sum over the nodes i of aggregate I of (r - A x)_i, the
// residual after the smoothing restricted by P^T (unsmoothed aggregation: identity blocks). This
// level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform isampler2D mem_range; // next level's nodes: (member start, end, -, -)
uniform isampler2D mem_list;  // members: (node of this level, -, -, -)
uniform sampler2D r;
uniform sampler2D x;
out vec4 o0;

void main() {
    int I = self_index();
    if (I >= u_n) { o0 = vec4(0.0); return; }
    ivec4 m = ldi(mem_range, I);
    vec3 s = vec3(0.0);
    for (int e = m.x; e < m.y; ++e) {
        int i = ldi(mem_list, e).x;
        s += ld(r, i).xyz - op_row(i, x, x, false);
    }
    o0 = vec4(s, 0.0);
}
