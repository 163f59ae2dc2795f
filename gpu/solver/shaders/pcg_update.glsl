// Per particle, one PCG update (pcg_update_row.glsl) and the partial products (r.t, r.r) for the
// next reduction. Outputs: o0 = dv, o1 = r, o2 = t, o3 = (r.t, r.r, -, -). u_jacobi 0 (the
// multigrid preconditions: wg_solve.c binds o0 and o1 only): no t.
#pragma weft include pcg_update_row
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); return; }
    vec3 dvi, ri, t;
    pcg_update_row(i, pcg_alpha(texelFetch(scalars0, ivec2(0), 0), texelFetch(scalars1, ivec2(0), 0)), dvi, ri, t);
    o0 = vec4(dvi, 0.0);
    o1 = vec4(ri, 0.0);
    o2 = vec4(t, 0.0);
    o3 = vec4(dot(ri, t), dot(ri, ri), 0.0, 0.0);
}
