// Per node of a level, one step of the V-cycle's smoother (core/amg_cycle.c chebyshev): the
// Chebyshev polynomial in D^-1 A on [bound / u_ratio, bound], step u_step (0: d = D^-1 t / theta;
// k >= 1: d = c1 d + c2 D^-1 t with the recurrence's coefficients), t = r - A x, x' = x + d.
// u_step -1: weighted block Jacobi, d = D^-1 t / bound (the coarsest level's sweeps when it has
// no dense factor). u_zero: x = 0 (the first step before the coarse correction: t = r). With
// u_prolong the coarse correction is added first: x_j + xc[aggregate(j)] wherever x is read (the
// prolongation of unsmoothed aggregation fused into the first step after it; filtered on the
// finest level, op_prolong). u_dot (the finest level's last step): o2 = (r.x', r.r), PCG's
// partial products with z = x' (bound as a third output). The level's inputs:
// amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D t9;   // r
uniform sampler2D t10;  // x
uniform sampler2D t11;  // d of the previous step
uniform sampler2D t12;  // the power iterations' reduction (lvl_bound)
uniform sampler2D t13;  // xc: the next level's solution (u_prolong)
uniform int u_step;
uniform int u_zero;
uniform int u_prolong;
uniform float u_ratio;
uniform int u_dot;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    vec3 r = ld(t9, i).xyz, t = r, x = vec3(0.0);
    if (u_zero == 0) {
        bool prolong = u_prolong != 0;
        t -= op_row(i, t10, t13, prolong);
        x = ld(t10, i).xyz;
        if (prolong) x += op_prolong(i, ld(t13, ldi(t0, i).w).xyz);
    }
    vec3 e = op_dinv(i) * t;
    float b = lvl_bound(t12);
    vec3 d;
    if (u_step < 0) {
        d = e / b;
    } else {
        float a = b / u_ratio, theta = 0.5 * (b + a), delta = 0.5 * (b - a), sigma = theta / delta;
        if (u_step == 0) {
            d = e / theta;
        } else {
            float rho = 1.0 / sigma, c1 = 0.0, c2 = 0.0;
            for (int s = 0; s < u_step; ++s) {
                float rn = 1.0 / (2.0 * sigma - rho);
                c1 = rn * rho;
                c2 = 2.0 * rn / delta;
                rho = rn;
            }
            d = c1 * ld(t11, i).xyz + c2 * e;
        }
    }
    o0 = vec4(x + d, 0.0);
    o1 = vec4(d, 0.0);
    o2 = u_dot != 0 ? vec4(dot(r, x + d), dot(r, r), 0.0, 0.0) : vec4(0.0);
}
