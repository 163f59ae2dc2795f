#version 430 core
// The multigrid's coarsest solve, x = M^-1 r with amg_factor_groups.glsl's inverse, one
// invocation a node (amg_coarse_inverse.glsl; the level has at most WG_AMG_DENSE_NODES nodes):
// x into image 0 in the layout.
layout(local_size_x = 64, local_size_y = 1) in;
#pragma weft include amg_coarse_inverse
uniform sampler2D r;
layout(binding = 0) writeonly uniform image2D wg_img0;

void main() {
    int I = int(gl_LocalInvocationID.x);
    if (I >= u_n) return;
    vec3 x = vec3(0.0);
    for (int J = 0; J < u_n; ++J) x += coarse_inverse_block(I, J) * ld(r, J).xyz;
    imageStore(wg_img0, tc(I), vec4(x, 0.0));
}
