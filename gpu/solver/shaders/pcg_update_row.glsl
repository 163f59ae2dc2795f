// One row of a PCG update (core/solve_pcg.c wcs_pcg_update; an include of pcg_update.glsl and
// pcg_update_groups.glsl, not a pass): dv += alpha c, r -= alpha q, t = D~^{-1} r. alpha comes
// from the scalars (pcg_alpha: 0 once the solve is done, and with u_first: the start of a solve
// or a restart). u_jacobi 0 (the multigrid preconditions instead): t = 0.
uniform sampler2D dv;
uniform sampler2D r;
uniform sampler2D c;
uniform sampler2D q;        // A c, filtered (spmv)
uniform sampler2D dinv_lo;  // D~^-1 (lo, hi)
uniform sampler2D dinv_hi;
uniform sampler2D scalars0; // pcg_scalars_rules.glsl: (delta, alpha, beta, rr)
uniform sampler2D scalars1; // (done, diverged, iterations, converged)
uniform int u_first;
uniform int u_jacobi;

// alpha of the scalars s0 = (delta, alpha, beta, rr), s1 = (done, ...)
float pcg_alpha(vec4 s0, vec4 s1) { return u_first != 0 || s1.x != 0.0 ? 0.0 : s0.y; }

void pcg_update_row(int i, float alpha, out vec3 dvi, out vec3 ri, out vec3 t) {
    dvi = ld(dv, i).xyz;
    ri = ld(r, i).xyz;
    if (alpha != 0.0) {
        dvi += alpha * ld(c, i).xyz;
        ri -= alpha * ld(q, i).xyz;
    }
    t = u_jacobi != 0 ? sym(ld(dinv_lo, i), ld(dinv_hi, i).xy) * ri : vec3(0.0);
}
