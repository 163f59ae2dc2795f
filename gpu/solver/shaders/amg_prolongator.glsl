// Per entry e of the smoothed prolongator to the next level (wg_amg_smooth.c), row i, coarse node
// J: P_e = [J on i's own aggregate] Pt_(i, J) - w D_i^-1 Z_e, Z_e = sum_k A_k Pt_(col k, J), the
// sum over the blocks k of row i whose column's aggregate is J (strong blocks; the weak ones, the
// bend springs, lumped onto i's own aggregate with Pt_(i, J): core/amg_setup.c prolongator), listed
// per entry when the hierarchy was built; w = u_weight / (u_bound_scale x lvl_bound): core's
// prolong_weight over the level's lambda_max bound, the smoother's. Pt: P_tent's blocks, identity
// with translations (u_tent 0), core's QR blocks with rotations (u_tent 1: the list's and p_ent's
// .w name them). On a pair level (op_pair) D^-1 couples rows 2a and 2a + 1, which share their
// columns: the entry at the same place in row i ^ 1 is gathered too. This level's inputs:
// amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform isampler2D p_ent;   // P's entries: (row i, coarse node, 1 on i's own aggregate, its Pt block)
uniform isampler2D p_rows;  // per node: (first entry, end, -, -)
uniform isampler2D p_range; // per entry: ld_range's (list start, end, -, shifts)
uniform isampler2D p_list;  // items (block of row i, its Pt block), two a texel (ld_item)
uniform sampler2D tent0;    // P_tent's blocks, row 0 (u_tent)
uniform sampler2D tent1;
uniform sampler2D tent2;
uniform sampler2D bound;    // the level's power iterations' reduction
uniform float u_weight;
uniform float u_bound_scale;
uniform int u_tent;
out vec4 o0;
out vec4 o1;
out vec4 o2;

mat3 tent_blk(int t) { return blk(tent0, tent1, tent2, t); }

mat3 gather(int e) {
    ivec4 r = ld_range(p_range, e);
    mat3 s = mat3(0.0);
    if (u_tent == 0) {
        for (int m = r.x; m < r.y; ++m) s += op_block(ld_item(p_list, m, r.w).x);
    } else {
        for (int m = r.x; m < r.y; ++m) {
            ivec2 q = ld_item(p_list, m, r.w);
            s += op_block(q.x) * tent_blk(q.y);
        }
    }
    return s;
}

void main() {
    int e = self_index();
    if (e >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 p = ldi(p_ent, e);
    mat3 s = gather(e), ds;
    float w = u_weight / (u_bound_scale * lvl_bound(bound));
    if (op_pair()) {
        int i = p.x;
        mat3 sp = gather(ldi(p_rows, i ^ 1).x + e - ldi(p_rows, i).x);
        bool odd = (i & 1) != 0;
        ds = op_dinv(2 * i) * (odd ? sp : s) + op_dinv(2 * i + 1) * (odd ? s : sp);
    } else {
        ds = op_dinv(p.x) * s;
    }
    mat3 P = (-w) * ds;
    if (p.z != 0) P += u_tent != 0 ? tent_blk(p.w) : mat3(1.0);
    o0 = blk_row(P, 0);
    o1 = blk_row(P, 1);
    o2 = blk_row(P, 2);
}
