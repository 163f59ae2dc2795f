// Per particle, one PCG update (core/solve_pcg.c wcs_pcg_update): dv += alpha c, r -= alpha q,
// t = D~^{-1} r, and the partial products (r.t, r.r) for the next reduction. alpha comes from the
// scalar texture (0 once the solve is done, and with u_first: the start of a solve or a restart).
// Outputs: o0 = dv, o1 = r, o2 = t, o3 = (r.t, r.r, -, -). u_jacobi 0 (the multigrid preconditions:
// wg_solve.c binds o0 and o1 only): no t.
uniform sampler2D t0;   // dv
uniform sampler2D t1;   // r
uniform sampler2D t2;   // c
uniform sampler2D t3;   // q (filtered)
uniform sampler2D t4;   // D~^{-1} lo
uniform sampler2D t5;   // D~^{-1} hi
uniform sampler2D t6;   // scalars 0 (delta, alpha, beta, rr)
uniform sampler2D t7;   // scalars 1 (done, diverged, iterations, converged)
uniform int u_first;
uniform int u_jacobi;
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); return; }
    vec3 dv = ld(t0, i).xyz, r = ld(t1, i).xyz;
    if (u_first == 0) {
        float alpha = texelFetch(t7, ivec2(0), 0).x != 0.0 ? 0.0 : texelFetch(t6, ivec2(0), 0).y;
        if (alpha != 0.0) {
            dv += alpha * ld(t2, i).xyz;
            r -= alpha * ld(t3, i).xyz;
        }
    }
    vec3 t = u_jacobi != 0 ? sym(ld(t4, i), ld(t5, i).xy) * r : vec3(0.0);
    o0 = vec4(dv, 0.0);
    o1 = vec4(r, 0.0);
    o2 = vec4(t, 0.0);
    o3 = vec4(dot(r, t), dot(r, r), 0.0, 0.0);
}
