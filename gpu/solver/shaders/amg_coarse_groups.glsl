#version 430 core
// The multigrid's coarsest solve, x = L^-T L^-1 r with amg_factor_groups.glsl's factor, by one
// invocation (amg_coarse_solve.glsl; the level has at most WG_AMG_DENSE_NODES nodes): x into
// image 0 in the layout.
layout(local_size_x = 1, local_size_y = 1) in;
#pragma weft include amg_coarse_solve
uniform sampler2D r;
layout(binding = 0) writeonly uniform image2D wg_img0;

void main() {
    int d = 3 * u_n;
    for (int i = 0; i < d; ++i) y[i] = ld(r, i / 3)[i % 3];
    amg_coarse_solve(d);
    for (int i = 0; i < u_n; ++i) imageStore(wg_img0, tc(i), vec4(y[3 * i], y[3 * i + 1], y[3 * i + 2], 0.0));
}
