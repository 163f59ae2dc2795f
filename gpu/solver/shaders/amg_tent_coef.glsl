// Per node K = 2a + q of the next level (rotations about the current positions, wg_amg.current):
// Q's coefficients for its three columns 3q + k of aggregate a's QR (amg_tent_qr.glsl: column
// 3q + k of Q is B (ta, tb) on the aggregate's rows about its centre), ta in o(2k), tb in o(2k + 1),
// read by amg_tent_blocks.
#pragma weft include amg_tent_qr
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
out vec4 o4;
out vec4 o5;

void main() {
    int K = self_index();
    if (K >= u_n) { o0 = o1 = o2 = o3 = o4 = o5 = vec4(0.0); return; }
    int q = K & 1;
    tent_qr(K >> 1);
    o0 = vec4(tq_ta[3 * q], 0.0);
    o1 = vec4(tq_tb[3 * q], 0.0);
    o2 = vec4(tq_ta[3 * q + 1], 0.0);
    o3 = vec4(tq_tb[3 * q + 1], 0.0);
    o4 = vec4(tq_ta[3 * q + 2], 0.0);
    o5 = vec4(tq_tb[3 * q + 2], 0.0);
}
