// Per node of a level, one step of the V-cycle's smoother (core/amg_cycle.c chebyshev): the
// Chebyshev polynomial in D^-1 A on [bound / u_ratio, bound], step u_step (0: d = D^-1 t / theta;
// k >= 1: d = c1 d + c2 D^-1 t with the recurrence's coefficients), t = r - A x, x' = x + d.
// u_step -1: weighted block Jacobi, d = D^-1 t / bound (the coarsest level's sweeps when it has
// no dense factor). u_zero: x = 0 (the first step before the coarse correction: t = r). With
// u_prolong the coarse correction is added first: x_j + xc[aggregate(j)] wherever x is read (the
// prolongation of unsmoothed aggregation fused into the first step after it).
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D t8;   // r
uniform sampler2D t9;   // x
uniform sampler2D t10;  // d of the previous step
uniform sampler2D t11;  // the power iterations' reduction (lvl_bound)
uniform sampler2D t12;  // xc: the next level's solution (u_prolong)
uniform int u_step;
uniform int u_zero;
uniform int u_prolong;
uniform float u_ratio;
out vec4 o0;
out vec4 o1;

vec3 xval(int j) {
    vec3 x = ld(t9, j).xyz;
    if (u_prolong != 0) x += ld(t12, ldi(t0, j).w).xyz;
    return x;
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 t = ld(t8, i).xyz, x = vec3(0.0);
    if (u_zero == 0) {
        ivec4 r = ldi(t0, i);
        for (int k = r.x; k < r.y; ++k) t -= blk(t2, t3, t4, k) * xval(ldi(t1, k).x);
        x = xval(i);
    }
    vec3 e = blk(t5, t6, t7, i) * t;
    float b = lvl_bound(t11);
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
            d = c1 * ld(t10, i).xyz + c2 * e;
        }
    }
    o0 = vec4(x + d, 0.0);
    o1 = vec4(d, 0.0);
}
