// The multigrid's coarsest solve by one invocation (an include of amg_coarse_groups.glsl and
// pcg_group_amg.glsl, not a pass): y = L^-T L^-1 y over the first d entries of the invocation's
// y, with amg_factor_groups.glsl's factor L (texel (c, r) = L[r][c]); d at most DMAX (3 x
// wg_amg.h's WG_AMG_DENSE_NODES).
uniform sampler2D factor;
const int DMAX = 96;
float y[DMAX];

float Lf(int r, int c) { return texelFetch(factor, ivec2(c, r), 0).x; }

void amg_coarse_solve(int d) {
    for (int i = 0; i < d; ++i) {
        float s = y[i];
        for (int k = 0; k < i; ++k) s -= Lf(i, k) * y[k];
        y[i] = s / Lf(i, i);
    }
    for (int i = d - 1; i >= 0; --i) {
        float s = y[i];
        for (int k = i + 1; k < d; ++k) s -= Lf(k, i) * y[k];
        y[i] = s / Lf(i, i);
    }
}
