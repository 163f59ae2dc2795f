// Per node I of the next level with the smoothed prolongator: rc_I = sum of P_(i, I)^T t_i over
// P's entries in column I, each row's residual t_i = r_i - (A x)_i made here (amg_residual.glsl's
// arithmetic) rather than read from a pass of its own: amg_residual + amg_restrict_p in one pass,
// the same sums in the same order, a residual row made once per entry of P in it (wg_amg.h
// WG_AMG_FOLD_RESIDUAL). This level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D pv0;       // P's blocks, row 0
uniform sampler2D pv1;
uniform sampler2D pv2;
uniform isampler2D pt_range; // next level's nodes: ld_range's (list start, end, -, shifts)
uniform isampler2D pt_list;  // items (entry of P, its row i), two a texel (ld_item)
uniform sampler2D r;
uniform sampler2D x;         // this level's x after the pre-smoothing
out vec4 o0;

void main() {
    int I = self_index();
    if (I >= u_n) { o0 = vec4(0.0); return; }
    ivec4 m = ld_range(pt_range, I);
    vec3 s = vec3(0.0);
    for (int e = m.x; e < m.y; ++e) {
        ivec2 q = ld_item(pt_list, e, m.w);
        vec3 t = ld(r, q.y).xyz - op_row(q.y, x, x, false);
        s += transpose(blk(pv0, pv1, pv2, q.x)) * t;
    }
    o0 = vec4(s, 0.0);
}
