// Per node of a level, one power iteration for lambda_max(D^-1 A) (core/amg_eigen.c, the power
// method): v' = D^-1 A v, and (v.Av, v.Dv, v'.v') for the Rayleigh quotient of the last one and
// the last iterate's norm. Not normalised within a setup: over its few steps (wg_amg.h) |v| grows
// by lambda_max^k, far from float's range. A warm setup's first step (u_warm) starts from the last
// setup's iterate v scaled to unit norm by the last reduction's v'.v' (bound.z), or from core's
// start vector v0 where that norm is not positive and finite. The level's inputs:
// amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D v;
uniform sampler2D v0;
uniform sampler2D bound;
uniform int u_warm;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    float s = 1.0;
    bool fresh = false;
    if (u_warm != 0) {
        float n2 = texelFetch(bound, ivec2(0), 0).z;
        if (n2 > 1e-30 && !isinf(n2)) s = inversesqrt(n2);
        else fresh = true;
    }
    vec3 av = fresh ? op_row_any(i, v0) : s * op_row_any(i, v);
    vec3 vi = fresh ? ld(v0, i).xyz : s * ld(v, i).xyz;
    vec3 dv = op_diag_full(i) * vi;
    vec3 vn = op_dinv(i) * av;
    o0 = vec4(vn, 0.0);
    o1 = vec4(dot(vi, av), dot(vi, dv), dot(vn, vn), 0.0);
}
