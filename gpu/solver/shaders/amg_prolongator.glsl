// Per entry e of the smoothed prolongator to the next level (wg_amg_smooth.c), row i, coarse node
// J: P_e = delta_{J, agg(i)} I - w D_i^-1 sum_k A_k, the sum over the blocks k of row i whose
// column's aggregate is J (strong blocks; the weak ones, the bend springs, lumped onto i's own
// aggregate: core/amg_setup.c prolongator_plain), listed per entry when the hierarchy was built;
// w = u_weight / (u_bound_scale x lvl_bound): core's prolong_weight over the level's lambda_max
// bound, the smoother's. This level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform isampler2D p_ent;   // P's entries: (row i, coarse node, 1 on i's own aggregate, -)
uniform isampler2D p_range; // per entry: (list start, end, -, -)
uniform isampler2D p_list;  // (block of row i, -, -, -)
uniform sampler2D bound;    // the level's power iterations' reduction
uniform float u_weight;
uniform float u_bound_scale;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int e = self_index();
    if (e >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 p = ldi(p_ent, e);
    ivec4 r = ldi(p_range, e);
    mat3 s = mat3(0.0);
    for (int m = r.x; m < r.y; ++m) s += op_block(ldi(p_list, m).x);
    float w = u_weight / (u_bound_scale * lvl_bound(bound));
    mat3 P = (-w) * (op_dinv(p.x) * s);
    if (p.z != 0) P += mat3(1.0);
    o0 = blk_row(P, 0);
    o1 = blk_row(P, 1);
    o2 = blk_row(P, 2);
}
