// Per particle: PCG's partial products (r.z, r.r) with z the multigrid's V-cycle, where the cycle
// ends in the coarsest level's dense solve (a one-level hierarchy); otherwise the finest level's
// last smoothing step makes them (amg_smooth.glsl u_dot).
uniform sampler2D r;
uniform sampler2D z;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 ri = ld(r, i).xyz;
    o0 = vec4(dot(ri, ld(z, i).xyz), dot(ri, ri), 0.0, 0.0);
}
