// Per node of a level, one power iteration for lambda_max(D^-1 A) (core/amg_eigen.c, the power
// method): v' = D^-1 A v, and (v.Av, v.Dv) for the Rayleigh quotient of the last one. Not
// normalised: over the few iterations a setup takes (wg_amg.h) |v| grows by lambda_max^k, far
// from float's range. The level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D v;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 av = op_row_any(i, v);
    vec3 vi = ld(v, i).xyz;
    vec3 dv = op_diag_full(i) * vi;
    vec3 avp = vec3(0.0);
    if (op_pair()) {   /* a pair level: D is 6x6 per pair (amg_level_inputs.glsl) */
        avp = op_row_any(i ^ 1, v);
        dv += op_pair_block(i) * ld(v, i ^ 1).xyz;
    }
    o0 = vec4(op_dinv_mul(i, av, avp), 0.0);
    o1 = vec4(dot(vi, av), dot(vi, dv), 0.0, 0.0);
}
