// Per particle: the start vector of the Lanczos estimate of Chebyshev's rho (core/solve_rho.c):
// r = S g, g a fixed pseudo-random vector in [-0.5, 0.5)^3, component k of particle i
// core's start_value(3 i + k): splitmix64, here in 32-bit halves (GLSL 3.30 has no 64-bit
// integers), so both backends start from the same vector to float rounding: the estimate's
// extrapolation of lambda_min is sensitive to the start vector, and another one can leave rho
// far from core's and Chebyshev taking many more iterations.
// w = r.r, for the |g| that starts the recorded CG steps (wg_solve.c).
uniform sampler2D S0;
uniform sampler2D S1;
out vec4 o0;

// 64-bit unsigned integers as uvec2(high, low)
uvec2 add64(uvec2 a, uvec2 b) {
    uint lo = a.y + b.y;
    return uvec2(a.x + b.x + (lo < a.y ? 1u : 0u), lo);
}
uvec2 mul32(uint a, uint b) {   // the full 64-bit product, by 16-bit halves
    uint a0 = a & 0xFFFFu, a1 = a >> 16, b0 = b & 0xFFFFu, b1 = b >> 16;
    uint p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint mid = (p00 >> 16) + (p01 & 0xFFFFu) + (p10 & 0xFFFFu);
    return uvec2(p11 + (p01 >> 16) + (p10 >> 16) + (mid >> 16), (p00 & 0xFFFFu) | (mid << 16));
}
uvec2 mul64(uvec2 a, uvec2 b) {   // modulo 2^64
    uvec2 p = mul32(a.y, b.y);
    return uvec2(p.x + a.x * b.y + a.y * b.x, p.y);
}
uvec2 xor_shr(uvec2 z, int s) {   // z ^ (z >> s), 0 < s < 32
    return z ^ uvec2(z.x >> s, (z.y >> s) | (z.x << (32 - s)));
}

float start_value(uint k) {
    uvec2 z = add64(uvec2(0u, k), uvec2(0x9E3779B9u, 0x7F4A7C15u));
    z = mul64(xor_shr(z, 30), uvec2(0xBF58476Du, 0x1CE4E5B9u));
    z = mul64(xor_shr(z, 27), uvec2(0x94D049BBu, 0x133111EBu));
    z = xor_shr(z, 31);
    return float(z.x >> 8) * (1.0 / 16777216.0) - 0.5;   // (z >> 11) / 2^53 - 0.5 to float
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    uint k = uint(3 * i);
    vec3 g = vec3(start_value(k), start_value(k + 1u), start_value(k + 2u));
    vec3 r = filter_apply(ld(S0, i), ld(S1, i), g);
    o0 = vec4(r, dot(r, r));
}
