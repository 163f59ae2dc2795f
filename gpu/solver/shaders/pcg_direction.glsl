// Per particle: the next PCG search direction c = S (t + beta c) (core/solve_pcg.c
// wcs_pcg_direction); with u_first, c = S t; once the solve is done, c is kept.
uniform sampler2D t;        // the preconditioned residual (pcg_update, or the multigrid)
uniform sampler2D c;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D scalars0; // pcg_scalars.glsl: (delta, alpha, beta, rr)
uniform sampler2D scalars1; // (done, ...)
uniform int u_first;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 v = ld(t, i).xyz;
    if (u_first == 0) {
        // the old cp is read only here: at a start or restart it may hold anything (a texture's
        // first contents are undefined, and a diverged solve leaves NaN), and 0 * NaN is NaN
        vec3 cp = ld(c, i).xyz;
        if (texelFetch(scalars1, ivec2(0), 0).x != 0.0) { o0 = vec4(cp, 0.0); return; }
        v += texelFetch(scalars0, ivec2(0), 0).z * cp;
    }
    o0 = vec4(filter_apply(ld(S0, i), ld(S1, i), v), 0.0);
}
