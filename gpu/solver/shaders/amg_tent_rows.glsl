// Per node K = 2a + q of the next level (rotations about the current positions, wg_amg.current):
// its near-null rows, rows 3q..3q + 2 of aggregate a's R about the aggregate's centre
// (amg_tent_qr.glsl), the centre and K's dead unknowns (bit r: column 3q + r dead; core's
// wc_amg_level.dead, amg_ptap.glsl).
#pragma weft include amg_blocks
#pragma weft include amg_tent_qr
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
out vec4 o4;
out vec4 o5;
out vec4 o6;

void main() {
    int K = self_index();
    if (K >= u_n) { o0 = o1 = o2 = o3 = o4 = o5 = o6 = vec4(0.0); return; }
    int q = K & 1;
    vec3 c = tent_qr(K >> 1);
    vec4 o[6];
    for (int r = 0; r < 3; ++r)
        for (int h = 0; h < 2; ++h) {
            int b = 6 * (3 * q + r) + 3 * h;
            o[2 * r + h] = vec4(tq_R[b], tq_R[b + 1], tq_R[b + 2], 0.0);
        }
    int dead = 0;
    for (int r = 0; r < 3; ++r)
        if (!tq_live[3 * q + r]) dead |= 1 << r;
    o0 = o[0]; o1 = o[1]; o2 = o[2]; o3 = o[3]; o4 = o[4]; o5 = o[5];
    o6 = vec4(c, float(dead));
}
