// Per particle: the next PCG search direction c = S (t + beta c) (core/solve_pcg.c
// wcs_pcg_direction); with u_first, c = S t; once the solve is done, c is kept.
uniform sampler2D t0;   // t
uniform sampler2D t1;   // c
uniform sampler2D t2;   // S0
uniform sampler2D t3;   // S1
uniform sampler2D t4;   // scalars 0 (delta, alpha, beta, rr)
uniform sampler2D t5;   // scalars 1 (done, ...)
uniform int u_first;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 v = ld(t0, i).xyz;
    if (u_first == 0) {
        // the old c is read only here: at a start or restart it may hold anything (a texture's
        // first contents are undefined, and a diverged solve leaves NaN), and 0 * NaN is NaN
        vec3 c = ld(t1, i).xyz;
        if (texelFetch(t5, ivec2(0), 0).x != 0.0) { o0 = vec4(c, 0.0); return; }
        v += texelFetch(t4, ivec2(0), 0).z * c;
    }
    o0 = vec4(filter_apply(ld(t2, i), ld(t3, i), v), 0.0);
}
