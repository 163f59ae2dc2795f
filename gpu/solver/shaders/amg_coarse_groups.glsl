#version 430 core
// The multigrid's coarsest solve, x = L^-T L^-1 r with amg_factor_groups.glsl's factor, by one
// invocation (the level has at most WG_AMG_DENSE_NODES nodes): x into image 0 in the layout.
layout(local_size_x = 1, local_size_y = 1) in;
uniform sampler2D factor; // L: texel (c, r) = L[r][c]
uniform sampler2D r;
layout(binding = 0) writeonly uniform image2D wg_img0;
const int DMAX = 96;
float y[DMAX];

float Lf(int r, int c) { return texelFetch(factor, ivec2(c, r), 0).x; }

void main() {
    int d = 3 * u_n;
    for (int i = 0; i < d; ++i) {
        float s = ld(r, i / 3)[i % 3];
        for (int k = 0; k < i; ++k) s -= Lf(i, k) * y[k];
        y[i] = s / Lf(i, i);
    }
    for (int i = d - 1; i >= 0; --i) {
        float s = y[i];
        for (int k = i + 1; k < d; ++k) s -= Lf(k, i) * y[k];
        y[i] = s / Lf(i, i);
    }
    for (int i = 0; i < u_n; ++i) imageStore(wg_img0, tc(i), vec4(y[3 * i], y[3 * i + 1], y[3 * i + 2], 0.0));
}
