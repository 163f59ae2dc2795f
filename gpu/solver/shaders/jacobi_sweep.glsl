// Per particle, one (Chebyshev-accelerated) block-Jacobi sweep (core/solve_jacobi.c) from x = dv_k:
//   r = S (b - A x),  d = S D~^{-1} r,  n = x + gamma d,
//   dv_{k+1} = n (omega 1) or omega (n - p) + p with p = dv_{k-1};  w = r.r for the residual check.
uniform isampler2D t0;  // particle blocks (row start, row end, diagonal block, -)
uniform isampler2D t1;  // block (row, column, -, -)
uniform sampler2D t2;   // A lo
uniform sampler2D t3;   // A hi
uniform sampler2D t4;   // x = dv_k
uniform sampler2D t5;   // b
uniform sampler2D t6;   // S0
uniform sampler2D t7;   // S1
uniform sampler2D t8;   // D~^{-1} lo
uniform sampler2D t9;   // D~^{-1} hi
uniform sampler2D t10;  // p = dv_{k-1}
uniform float u_gamma;
uniform float u_omega;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 y = bsr_row(t0, t1, t2, t3, t4, i);
    vec4 s0 = ld(t6, i), s1 = ld(t7, i);
    vec3 r = filter_apply(s0, s1, ld(t5, i).xyz - y);
    vec3 d = filter_apply(s0, s1, sym(ld(t8, i), ld(t9, i).xy) * r);
    vec3 nx = ld(t4, i).xyz + u_gamma * d;
    if (u_omega != 1.0) {
        vec3 p = ld(t10, i).xyz;
        nx = u_omega * (nx - p) + p;
    }
    o0 = vec4(nx, dot(r, r));
}
