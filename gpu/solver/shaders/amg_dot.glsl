// Per particle: PCG's partial products (r.z, r.r) with z the multigrid's V-cycle, where the cycle
// ends in the coarsest level's dense solve (a one-level hierarchy); otherwise the finest level's
// last smoothing step makes them (amg_smooth.glsl u_dot).
uniform sampler2D t0;   // r
uniform sampler2D t1;   // z
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 r = ld(t0, i).xyz;
    o0 = vec4(dot(r, ld(t1, i).xyz), dot(r, r), 0.0, 0.0);
}
