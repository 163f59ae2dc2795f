// Per block of a coarse level: the Galerkin product of unsmoothed aggregation, the sum of the
// finer level's blocks (i, j) with aggregate(i), aggregate(j) its row and column (P = P_tent of
// translations: identity blocks), listed per coarse block when the hierarchy was built. The
// finer level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform isampler2D gal_range; // this level's blocks: (list start, end, -, -)
uniform isampler2D gal_list;  // list: (finer block, -, -, -)
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 r = ldi(gal_range, k);
    mat3 s = mat3(0.0);
    for (int e = r.x; e < r.y; ++e) s += op_block(ldi(gal_list, e).x);
    o0 = blk_row(s, 0);
    o1 = blk_row(s, 1);
    o2 = blk_row(s, 2);
}
