#version 430 core
// The multigrid's coarsest solve with the restriction before it in one work group (the smoothed
// prolongator; wg_amg.c vcycle where the level above the coarsest has at most
// WG_AMG_FOLD_COARSE_ROWS nodes): amg_restrict_res.glsl then amg_coarse_groups.glsl, each phase
// a barrier from the next where they were two passes. The group makes the level's residual
// rows t_i = r_i - (A x)_i once each into shared memory (amg_residual.glsl's arithmetic), then
// each coarsest node I its rc_I = sum of P_(i, I)^T t_i over P's entries in column I (the
// restriction's order), then x_I = sum over J of M^-1's block (I, J) times rc_J
// (amg_coarse_inverse.glsl): x into image 0. u_n: the coarsest level's nodes (at most
// WG_AMG_DENSE_NODES); u_rows: the level's above it. The level's inputs: amg_level_inputs.glsl.
layout(local_size_x = 256, local_size_y = 1) in;
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
#pragma weft include amg_coarse_inverse
uniform sampler2D pv0;       // P's blocks, row 0
uniform sampler2D pv1;
uniform sampler2D pv2;
uniform isampler2D pt_range; // the coarsest level's nodes: ld_range's (list start, end, -, shifts)
uniform isampler2D pt_list;  // items (entry of P, its row i), two a texel (ld_item)
uniform sampler2D r;
uniform sampler2D x;         // the level's x after the pre-smoothing
uniform int u_rows;
layout(binding = 0) writeonly uniform image2D wg_img0;
const int ROWS = 1024;       // WG_AMG_FOLD_COARSE_ROWS
const int NC = 32;           // WG_AMG_DENSE_NODES
shared vec3 s_t[ROWS];
shared vec3 s_rc[NC];

void main() {
    int t = int(gl_LocalInvocationID.x);
    for (int i = t; i < u_rows; i += 256) s_t[i] = ld(r, i).xyz - op_row(i, x, x, false);
    memoryBarrierShared();
    barrier();
    if (t < u_n) {
        ivec4 m = ld_range(pt_range, t);
        vec3 s = vec3(0.0);
        for (int e = m.x; e < m.y; ++e) {
            ivec2 q = ld_item(pt_list, e, m.w);
            s += transpose(blk(pv0, pv1, pv2, q.x)) * s_t[q.y];
        }
        s_rc[t] = s;
    }
    memoryBarrierShared();
    barrier();
    if (t >= u_n) return;
    vec3 xo = vec3(0.0);
    for (int J = 0; J < u_n; ++J) xo += coarse_inverse_block(t, J) * s_rc[J];
    imageStore(wg_img0, tc(t), vec4(xo, 0.0));
}
