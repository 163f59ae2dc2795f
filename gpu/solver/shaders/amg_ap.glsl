// Per entry (i, J) of T = A P (the smoothed prolongator's first Galerkin factor, wg_amg_smooth.c):
// the sum of A_ik P_(k, J) over the products listed per entry when the hierarchy was built.
// This level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D pv0;      // P's blocks, row 0
uniform sampler2D pv1;      // row 1
uniform sampler2D pv2;      // row 2
uniform isampler2D t_range; // T's entries: ld_range's (list start, end, -, shifts)
uniform isampler2D t_list;  // products (block k of A, entry of P), two a texel (ld_item)
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 r = ld_range(t_range, s);
    mat3 t = mat3(0.0);
    for (int m = r.x; m < r.y; ++m) {
        ivec2 q = ld_item(t_list, m, r.w);
        t += op_block(q.x) * blk(pv0, pv1, pv2, q.y);
    }
    o0 = blk_row(t, 0);
    o1 = blk_row(t, 1);
    o2 = blk_row(t, 2);
}
