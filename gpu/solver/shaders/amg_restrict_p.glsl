// Per node I of the next level with the smoothed prolongator (wg_amg_smooth.c): rc_I = sum of
// P_(i, I)^T t_i over P's entries in column I (t: amg_residual.glsl's r - A x).
#pragma weft include amg_blocks
uniform sampler2D pv0;       // P's blocks, row 0
uniform sampler2D pv1;
uniform sampler2D pv2;
uniform isampler2D pt_range; // next level's nodes: ld_range's (list start, end, -, shifts)
uniform isampler2D pt_list;  // items (entry of P, its row i), two a texel (ld_item)
uniform sampler2D r;         // the residual t
out vec4 o0;

void main() {
    int I = self_index();
    if (I >= u_n) { o0 = vec4(0.0); return; }
    ivec4 m = ld_range(pt_range, I);
    vec3 s = vec3(0.0);
    for (int e = m.x; e < m.y; ++e) {
        ivec2 q = ld_item(pt_list, e, m.w);
        s += transpose(blk(pv0, pv1, pv2, q.x)) * ld(r, q.y).xyz;
    }
    o0 = vec4(s, 0.0);
}
