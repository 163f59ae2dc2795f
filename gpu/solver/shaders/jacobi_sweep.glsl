// Per particle, one (Chebyshev-accelerated) block-Jacobi sweep (core/solve_jacobi.c) from x = dv_k:
//   r = S (b - A x),  d = S D~^{-1} r,  n = x + gamma d,
//   dv_{k+1} = n (omega 1) or omega (n - p) + p with p = dv_{k-1};  w = r.r for the residual check.
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform isampler2D block;   // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D x;        // dv_k
uniform sampler2D b;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D dinv_lo;  // D~^-1 (lo, hi)
uniform sampler2D dinv_hi;
uniform sampler2D x_prev;   // dv_{k-1}
#pragma weft include pairs_row
uniform float u_gamma;
uniform float u_omega;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 y = bsr_row(pblocks, block, a_lo, a_hi, x, i) + pairs_row(x, i);   // A with the pairs' blocks
    vec4 s0 = ld(S0, i), s1 = ld(S1, i);
    vec3 r = filter_apply(s0, s1, ld(b, i).xyz - y);
    vec3 d = filter_apply(s0, s1, sym(ld(dinv_lo, i), ld(dinv_hi, i).xy) * r);
    vec3 nx = ld(x, i).xyz + u_gamma * d;
    if (u_omega != 1.0) {
        vec3 p = ld(x_prev, i).xyz;
        nx = u_omega * (nx - p) + p;
    }
    o0 = vec4(nx, dot(r, r));
}
