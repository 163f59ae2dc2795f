// Per particle: the start vector of the Lanczos estimate of Chebyshev's rho (core/solve_rho.c):
// r = S g, g a fixed pseudo-random vector in [-0.5, 0.5)^3 (a 32-bit integer hash of the index;
// core uses splitmix64, which GLSL 3.30 cannot: another start vector, the same estimate).
// w = r.r, for the |g| that starts the recorded CG steps (wg_solve.c).
uniform sampler2D t0;   // S0
uniform sampler2D t1;   // S1
out vec4 o0;

float h01(uint x) {
    x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
    return float(x >> 8) * (1.0 / 16777216.0) - 0.5;
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    uint k = uint(3 * i);
    vec3 g = vec3(h01(k + 0x9E3779B9u), h01(k + 1u + 0x9E3779B9u), h01(k + 2u + 0x9E3779B9u));
    vec3 r = filter_apply(ld(t0, i), ld(t1, i), g);
    o0 = vec4(r, dot(r, r));
}
