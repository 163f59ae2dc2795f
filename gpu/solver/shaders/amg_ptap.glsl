// Per block (I, J) of a coarse level with the smoothed prolongator (wg_amg_smooth.c): the
// Galerkin product sum P_(i, I)^T T_(i, J) over the finer level's rows i (T = A P, amg_ap.glsl),
// the products listed per block when the hierarchy was built (with rotations three blocks of a
// 2 x 2 group of coarse nodes read the fourth's list, shifted: ld_item). With rotations a
// diagonal block's dead unknowns (gal_range.z: a bit per row, core's wc_amg_level.dead) have zero
// rows and columns; their diagonal takes the block's mean live diagonal (or 1), core/amg_setup.c
// revive_dead. About the current positions (u_dead_nc) the bits are the setup's: the next level's
// nc.w (amg_tent_rows.glsl), on its diagonal blocks (cols).
#pragma weft include amg_blocks
uniform sampler2D pv0;        // P's blocks, row 0
uniform sampler2D pv1;
uniform sampler2D pv2;
uniform sampler2D tv0;        // T's blocks, row 0
uniform sampler2D tv1;
uniform sampler2D tv2;
uniform isampler2D gal_range; // this level's blocks: ld_range's (list start, end, dead rows' bits, shifts)
uniform isampler2D gal_list;  // products (entry of P, entry of T), two a texel (ld_item)
uniform isampler2D cols;      // this level's blocks: (row, column, -, -)
uniform sampler2D nc;         // u_dead_nc: this level's nodes' (centre, dead bits)
uniform int u_dead_nc;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 r = ld_range(gal_range, k);
    mat3 s = mat3(0.0);
    for (int m = r.x; m < r.y; ++m) {
        ivec2 q = ld_item(gal_list, m, r.w);
        s += transpose(blk(pv0, pv1, pv2, q.x)) * blk(tv0, tv1, tv2, q.y);
    }
    int bits = r.z;
    if (u_dead_nc != 0) {
        ivec4 b = ldi(cols, k);
        bits = b.x == b.y ? int(ld(nc, b.x).w) : 0;
    }
    if (bits != 0) {
        float sum = 0.0;
        int live = 0;
        for (int q = 0; q < 3; ++q)
            if ((bits & (1 << q)) == 0) {
                sum += s[q][q];
                ++live;
            }
        float v = live > 0 && sum > 0.0 && !isinf(sum) ? sum / float(live) : 1.0;
        for (int q = 0; q < 3; ++q)
            if ((bits & (1 << q)) != 0) s[q][q] = v;
    }
    o0 = blk_row(s, 0);
    o1 = blk_row(s, 1);
    o2 = blk_row(s, 2);
}
