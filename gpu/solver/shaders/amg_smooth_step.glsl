// One step of the multigrid's smoother on a node (an include of amg_smooth.glsl and
// pcg_group_amg.glsl, not a pass; core/amg_cycle.c chebyshev): the Chebyshev polynomial in
// D^-1 A on [b / ratio, b], step `step` (0: d = e / theta; k >= 1: d = c1 dprev + c2 e with the
// recurrence's coefficients), or step -1: weighted block Jacobi, d = e / b. e = D^-1 (r - A x);
// dprev, the previous step's d, is read only from step 1 on. Returns the step's d (x' = x + d).
vec3 amg_smooth_step(int step, float b, float ratio, vec3 e, vec3 dprev) {
    if (step < 0) return e / b;
    float a = b / ratio, theta = 0.5 * (b + a), delta = 0.5 * (b - a), sigma = theta / delta;
    if (step == 0) return e / theta;
    float rho = 1.0 / sigma, c1 = 0.0, c2 = 0.0;
    for (int s = 0; s < step; ++s) {
        float rn = 1.0 / (2.0 * sigma - rho);
        c1 = rn * rho;
        c2 = 2.0 * rn / delta;
        rho = rn;
    }
    return c1 * dprev + c2 * e;
}
