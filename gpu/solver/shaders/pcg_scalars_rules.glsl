// The PCG scalars' rules (an include of the passes that step them: pcg_scalars*.glsl, the folded
// *_groups.glsl passes and pcg_group.glsl; not a pass): one texel of state kept on the GPU between
// passes (no read-back per iteration):
//   s0 = (delta, alpha, beta, rr), s1 = (done, diverged, iterations, converged),
//   s2 = (residual0, goal, limit, cq).
// The mode (a pass's u_mode, or pcg_scalars_step's argument):
//        0, start: residual0 = |S (b - A z)| (sum = its square), (delta, rr) of the initial guess (dots);
//                  goal = tolerance max(residual0, floor), limit = divergence_factor max(residual0, |r|).
//        1, alpha: alpha = delta / cq (sum = c.q); cq <= 0 or alpha not finite: diverged.
//        2, beta:  (delta', rr) from dots; beta = delta' / delta; iterations + 1.
//        3, restart: (delta, rr) from dots; done cleared (the true residual replaced r).
// After modes 0, 2 and 3 the tests at the top of core's PCG loop: not finite, delta < 0 or
// |r| > limit: diverged; |r| <= goal: done with converged = 1 (the host confirms it with the true
// residual); iterations at the cap: done. Once done, nothing changes.
uniform int u_mode;
uniform float u_tolerance;
uniform float u_divergence;
uniform float u_max_iterations;
uniform float u_floor;  // the residual's floor (core/solve.h): goal = tolerance max(residual0, floor)

bool pcg_bad(float x) { return isnan(x) || isinf(x); }

// s0..s2 the last scalars, changed in place by the rules of `mode`; sum and dots the reductions
// the mode reads
void pcg_scalars_step(int mode, inout vec4 s0, inout vec4 s1, inout vec4 s2, float sum, vec2 dots) {
    if (mode == 0) {
        float res0 = sqrt(sum);
        s0 = vec4(dots.x, 0.0, 0.0, dots.y);
        s1 = vec4(0.0);
        s2 = vec4(res0, u_tolerance * max(res0, u_floor), u_divergence * max(res0, sqrt(dots.y)), 0.0);
        if (pcg_bad(res0)) s1 = vec4(1.0, 1.0, 0.0, 0.0);
        else if (res0 == 0.0) s1 = vec4(1.0, 0.0, 0.0, 1.0);
    } else if (s1.x == 0.0 && mode == 1) {
        float alpha = s0.x / sum;
        s2.w = sum;
        if (!(sum > 0.0) || pcg_bad(alpha)) s1.xy = vec2(1.0, 1.0);
        else s0.y = alpha;
    } else if (s1.x == 0.0 && mode == 2) {
        s0.z = dots.x / s0.x;
        s0.x = dots.x;
        s0.w = dots.y;
        s1.z += 1.0;
    } else if (mode == 3) {
        s0 = vec4(dots.x, 0.0, 0.0, dots.y);
        s1 = vec4(0.0, 0.0, s1.z, 0.0);
    }
    if (mode != 1 && s1.x == 0.0) {
        float rn = sqrt(s0.w);
        if (pcg_bad(s0.w) || !(s0.x >= 0.0) || pcg_bad(s0.x) || rn > s2.z) s1.xy = vec2(1.0, 1.0);
        else if (rn <= s2.y) s1 = vec4(1.0, 0.0, s1.z, 1.0);
        else if (s1.z >= u_max_iterations) s1.x = 1.0;
    }
}

// the step of the pass's mode, u_mode
void pcg_scalars_rules(inout vec4 s0, inout vec4 s1, inout vec4 s2, float sum, vec2 dots) {
    pcg_scalars_step(u_mode, s0, s1, s2, sum, dots);
}
