// Per node i of a level with the smoothed prolongator (wg_amg_smooth.c): x_i + (P xc)_i, row i
// of P's entries times the next level's solution, filtered on the finest level (op_prolong:
// amg_level_inputs.glsl), before the post-smoothing.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D pv0;     // P's blocks, row 0
uniform sampler2D pv1;
uniform sampler2D pv2;
uniform isampler2D p_ent;  // P's entries: (row, coarse node, -, -)
uniform isampler2D p_rows; // per node: (first entry, end, -, -)
uniform sampler2D x;
uniform sampler2D xc;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    ivec4 r = ldi(p_rows, i);
    vec3 s = vec3(0.0);
    for (int e = r.x; e < r.y; ++e) s += blk(pv0, pv1, pv2, e) * ld(xc, ldi(p_ent, e).y).xyz;
    o0 = vec4(ld(x, i).xyz + op_prolong(i, s), 0.0);
}
