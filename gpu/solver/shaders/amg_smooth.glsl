// Per node of a level, one step of the V-cycle's smoother (amg_smooth_step.glsl: Chebyshev on
// [bound / u_ratio, bound], step u_step, or -1: weighted block Jacobi, the coarsest level's
// sweeps when it has no dense factor; bound: lvl_bound x u_bound_scale, wg_amg.h fine_bound_scale on the
// finest level, 1 elsewhere), t = r - A x, x' = x + d. u_zero: x = 0 (the first step
// before the coarse correction: t = r). With u_prolong the coarse correction is added first:
// x_j + xc[aggregate(j)] wherever x is read (the prolongation of unsmoothed aggregation fused
// into the first step after it; filtered on the finest level, op_prolong). u_dot (the finest level's last step): o2 = (r.x', r.r), PCG's
// partial products with z = x' (bound as a third output). On a pair level (op_pair, rotations)
// D^-1 is the pair's 6x6 inverse, so node i also takes the residual of node i ^ 1. The level's inputs:
// amg_level_inputs.glsl.
// u_zero 2: the first two steps in one pass (the pre-smoothing; the coarsest level's first two
// sweeps): x is the first step's from x = 0, made per node where it is read (op_x: node j's
// x_j = step 0 of D^-1 r, a pair level's with r of node j ^ 1), in that step's arithmetic, and
// the previous d is that x; then this step (u_step 1, or -1) as from a stored x. x and d unread.
#define WG_AMG_X_HOOK 1
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
#pragma weft include amg_smooth_step
uniform sampler2D r;
uniform sampler2D x;
uniform sampler2D d;     // the previous step's d
uniform sampler2D bound; // the power iterations' reduction (lvl_bound)
uniform sampler2D xc;    // the next level's solution (u_prolong)
uniform int u_step;
uniform int u_zero;
uniform int u_prolong;
uniform float u_ratio;
uniform float u_bound_scale;
uniform int u_dot;
out vec4 o0;
out vec4 o1;
out vec4 o2;

// The step's bound (lvl_bound x u_bound_scale)
float smooth_bound() { return u_bound_scale * lvl_bound(bound); }

// The first step from x = 0 at node j: d = x' (u_zero 1's arithmetic).
vec3 first_step(int j) {
    vec3 tp = op_pair() ? ld(r, j ^ 1).xyz : vec3(0.0);
    return amg_smooth_step(u_step < 0 ? -1 : 0, smooth_bound(), u_ratio, op_dinv_mul(j, ld(r, j).xyz, tp), vec3(0.0));
}

vec3 op_x(int j, sampler2D x, sampler2D xc, bool prolong) {
    if (u_zero == 2) return first_step(j);
    vec3 xj = ld(x, j).xyz;
    if (prolong) xj += op_prolong(j, ld(xc, ldi(rows, j).w).xyz);
    return xj;
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    vec3 ri = ld(r, i).xyz, t = ri, xi = vec3(0.0);
    int ip = i ^ 1;   /* a pair level: the pair's other node, whose residual D^-1 also reads */
    vec3 tp = op_pair() ? ld(r, ip).xyz : vec3(0.0);
    if (u_zero != 1) {
        bool prolong = u_prolong != 0;
        t -= op_row(i, x, xc, prolong);
        if (op_pair()) tp -= op_row(ip, x, xc, false);   /* no u_prolong there (smoothed P) */
        xi = op_x(i, x, xc, prolong);
    }
    vec3 dprev = u_step < 1 ? vec3(0.0) : u_zero == 2 ? xi : ld(d, i).xyz;
    vec3 e = op_dinv_mul(i, t, tp);
    vec3 di = amg_smooth_step(u_step, smooth_bound(), u_ratio, e, dprev);
    o0 = vec4(xi + di, 0.0);
    o1 = vec4(di, 0.0);
    o2 = u_dot != 0 ? vec4(dot(ri, xi + di), dot(ri, ri), 0.0, 0.0) : vec4(0.0);
}
