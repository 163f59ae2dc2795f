// Per particle, one PCG update (core/solve_pcg.c wcs_pcg_update): dv += alpha c, r -= alpha q,
// t = D~^{-1} r, and the partial products (r.t, r.r) for the next reduction. alpha comes from the
// scalar texture (0 once the solve is done, and with u_first: the start of a solve or a restart).
// Outputs: o0 = dv, o1 = r, o2 = t, o3 = (r.t, r.r, -, -). u_jacobi 0 (the multigrid preconditions:
// wg_solve.c binds o0 and o1 only): no t.
uniform sampler2D dv;
uniform sampler2D r;
uniform sampler2D c;
uniform sampler2D q;        // A c, filtered (spmv)
uniform sampler2D dinv_lo;  // D~^-1 (lo, hi)
uniform sampler2D dinv_hi;
uniform sampler2D scalars0; // pcg_scalars.glsl: (delta, alpha, beta, rr)
uniform sampler2D scalars1; // (done, diverged, iterations, converged)
uniform int u_first;
uniform int u_jacobi;
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); return; }
    vec3 dvi = ld(dv, i).xyz, ri = ld(r, i).xyz;
    if (u_first == 0) {
        float alpha = texelFetch(scalars1, ivec2(0), 0).x != 0.0 ? 0.0 : texelFetch(scalars0, ivec2(0), 0).y;
        if (alpha != 0.0) {
            dvi += alpha * ld(c, i).xyz;
            ri -= alpha * ld(q, i).xyz;
        }
    }
    vec3 t = u_jacobi != 0 ? sym(ld(dinv_lo, i), ld(dinv_hi, i).xy) * ri : vec3(0.0);
    o0 = vec4(dvi, 0.0);
    o1 = vec4(ri, 0.0);
    o2 = vec4(t, 0.0);
    o3 = vec4(dot(ri, t), dot(ri, ri), 0.0, 0.0);
}
