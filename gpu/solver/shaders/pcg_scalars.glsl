// The PCG scalars, one texel, kept on the GPU between passes (no read-back per iteration):
//   o0 = (delta, alpha, beta, rr), o1 = (done, diverged, iterations, converged),
//   o2 = (residual0, goal, limit, cq).
// u_mode 0, start: residual0 = |S (b - A z)| (sum.w), (delta, rr) of the initial guess (dots.xy);
//                  goal = tolerance max(residual0, floor), limit = divergence_factor max(residual0, |r|).
//        1, alpha: alpha = delta / cq (sum.w summed c.q); cq <= 0 or alpha not finite: diverged.
//        2, beta:  (delta', rr) from dots.xy; beta = delta' / delta; iterations + 1.
//        3, restart: (delta, rr) from dots.xy; done cleared (the true residual replaced r).
// After modes 0, 2 and 3 the tests at the top of core's PCG loop: not finite, delta < 0 or
// |r| > limit: diverged; |r| <= goal: done with converged = 1 (the host confirms it with the true
// residual); iterations at the cap: done. Once done, nothing changes.
uniform sampler2D scalars0; // the last pcg_scalars outputs
uniform sampler2D scalars1;
uniform sampler2D sum;      // a reduction whose w is the sum wanted (residual0^2 or cq)
uniform sampler2D dots;     // a reduction whose xy are (delta, rr)
uniform sampler2D scalars2;
uniform int u_mode;
uniform float u_tolerance;
uniform float u_divergence;
uniform float u_max_iterations;
uniform float u_floor;  // the residual's floor (core/solve.h): goal = tolerance max(residual0, floor)
out vec4 o0;
out vec4 o1;
out vec4 o2;

bool bad(float x) { return isnan(x) || isinf(x); }

void main() {
    vec4 s0 = texelFetch(scalars0, ivec2(0), 0), s1 = texelFetch(scalars1, ivec2(0), 0), s2 = texelFetch(scalars2, ivec2(0), 0);
    if (u_mode == 0) {
        float res0 = sqrt(texelFetch(sum, ivec2(0), 0).w);
        vec2 dr = texelFetch(dots, ivec2(0), 0).xy;
        s0 = vec4(dr.x, 0.0, 0.0, dr.y);
        s1 = vec4(0.0);
        s2 = vec4(res0, u_tolerance * max(res0, u_floor), u_divergence * max(res0, sqrt(dr.y)), 0.0);
        if (bad(res0)) s1 = vec4(1.0, 1.0, 0.0, 0.0);
        else if (res0 == 0.0) s1 = vec4(1.0, 0.0, 0.0, 1.0);
    } else if (s1.x == 0.0 && u_mode == 1) {
        float cq = texelFetch(sum, ivec2(0), 0).w;
        float alpha = s0.x / cq;
        s2.w = cq;
        if (!(cq > 0.0) || bad(alpha)) s1.xy = vec2(1.0, 1.0);
        else s0.y = alpha;
    } else if (s1.x == 0.0 && u_mode == 2) {
        vec2 dr = texelFetch(dots, ivec2(0), 0).xy;
        s0.z = dr.x / s0.x;
        s0.x = dr.x;
        s0.w = dr.y;
        s1.z += 1.0;
    } else if (u_mode == 3) {
        vec2 dr = texelFetch(dots, ivec2(0), 0).xy;
        s0 = vec4(dr.x, 0.0, 0.0, dr.y);
        s1 = vec4(0.0, 0.0, s1.z, 0.0);
    }
    if (u_mode != 1 && s1.x == 0.0) {
        float rn = sqrt(s0.w);
        if (bad(s0.w) || !(s0.x >= 0.0) || bad(s0.x) || rn > s2.z) s1.xy = vec2(1.0, 1.0);
        else if (rn <= s2.y) s1 = vec4(1.0, 0.0, s1.z, 1.0);
        else if (s1.z >= u_max_iterations) s1.x = 1.0;
    }
    o0 = s0;
    o1 = s1;
    o2 = s2;
}
