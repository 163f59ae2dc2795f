// Per texel t = 2i + q (rotations about the current positions, wg_amg.current): P_tent's block
// from node i to the next level's node 2 agg(i) + q, core's RB(tent, i, r, 3q + c), by rows (the
// amg_prolongator pass's tent0..2): node i's rows about its aggregate's centre times Q's
// coefficients (amg_tent_qr.glsl). A dead column's block is 0.
#pragma weft include amg_blocks
#pragma weft include amg_tent_qr
uniform isampler2D tq_of;     // per node: its aggregate
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int t = self_index();
    if (t >= u_n) { o0 = o1 = o2 = vec4(0.0); return; }
    int i = t >> 1, q = t & 1;
    vec3 c = tent_qr(ldi(tq_of, i).x);
    mat3 tr, ro;
    tq_rows(i, c, tr, ro);
    mat3 b = mat3(tr * tq_ta[3 * q] + ro * tq_tb[3 * q], tr * tq_ta[3 * q + 1] + ro * tq_tb[3 * q + 1],
                  tr * tq_ta[3 * q + 2] + ro * tq_tb[3 * q + 2]);
    o0 = blk_row(b, 0);
    o1 = blk_row(b, 1);
    o2 = blk_row(b, 2);
}
