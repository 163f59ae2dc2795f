// Per texel t = 2i + q (rotations about the current positions, wg_amg.current): P_tent's block
// from node i to the next level's node K = 2 agg(i) + q, core's RB(tent, i, r, 3q + c), by rows (the
// amg_prolongator pass's tent0..2): node i's rows about its aggregate's centre (the next level's
// nc_next of K) times K's coefficients of Q (amg_tent_coef.glsl). A dead column's block is 0.
#pragma weft include amg_blocks
#pragma weft include amg_tent_qr
uniform isampler2D tq_of;     // per node: its aggregate
uniform sampler2D nc_next;    // the next level's (centre, dead bits)
uniform sampler2D tq_t0;      // the next level's coefficients: column 3q + k's ta in tq_t(2k), tb in
uniform sampler2D tq_t1;      // tq_t(2k + 1)
uniform sampler2D tq_t2;
uniform sampler2D tq_t3;
uniform sampler2D tq_t4;
uniform sampler2D tq_t5;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int t = self_index();
    if (t >= u_n) { o0 = o1 = o2 = vec4(0.0); return; }
    int i = t >> 1, q = t & 1;
    int K = 2 * ldi(tq_of, i).x + q;
    mat3 tr, ro;
    tq_rows(i, ld(nc_next, K).xyz, tr, ro);
    mat3 b = mat3(tr * ld(tq_t0, K).xyz + ro * ld(tq_t1, K).xyz, tr * ld(tq_t2, K).xyz + ro * ld(tq_t3, K).xyz,
                  tr * ld(tq_t4, K).xyz + ro * ld(tq_t5, K).xyz);
    o0 = blk_row(b, 0);
    o1 = blk_row(b, 1);
    o2 = blk_row(b, 2);
}
