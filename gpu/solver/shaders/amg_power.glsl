// Per node of a level, one power iteration for lambda_max(D^-1 A) (core/amg_eigen.c, the power
// method): v' = D^-1 A v, and (v.Av, v.Dv, v'.v', floor) for the Rayleigh quotient of the last
// one, the last iterate's norm and the bound's floor (wg_amg.h). Normalised where u_norm is set
// (a warm setup's first step, and every WG_AMG_POWER_NORM steps of a cold one): v is first scaled
// to unit norm by the last reduction's v'.v' (bound.z), or replaced by core's start vector v0
// where that norm is not positive and finite. Between those |v| grows by lambda_max per step.
// The floor, written by node 0 alone so that the sum carries it (lvl_bound takes the larger of
// it and the quotient): 0 on a cold setup (u_floor 0); u_floor_factor x the cold setup's
// quotient on the first warm one after it (1); the last reduction's floor on the others (2).
// The level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D v;
uniform sampler2D v0;
uniform sampler2D bound;
uniform int u_norm;
uniform int u_floor;
uniform float u_floor_factor;
out vec4 o0;
out vec4 o1;

float floor_of(vec4 s) {
    float f = u_floor == 1 ? u_floor_factor * (s.x / s.y) : s.w;
    return (f > 0.0 && !isinf(f) && !isnan(f)) ? f : 0.0;
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    float s = 1.0;
    bool fresh = false;
    if (u_norm != 0) {
        float n2 = texelFetch(bound, ivec2(0), 0).z;
        if (n2 > 1e-30 && !isinf(n2)) s = inversesqrt(n2);
        else fresh = true;
    }
    vec3 av = fresh ? op_row_any(i, v0) : s * op_row_any(i, v);
    vec3 vi = fresh ? ld(v0, i).xyz : s * ld(v, i).xyz;
    vec3 dv = op_diag_full(i) * vi;
    vec3 avp = vec3(0.0);
    if (op_pair()) {   /* a pair level: D is 6x6 per pair (amg_level_inputs.glsl) */
        avp = fresh ? op_row_any(i ^ 1, v0) : s * op_row_any(i ^ 1, v);
        dv += op_pair_block(i) * (fresh ? ld(v0, i ^ 1).xyz : s * ld(v, i ^ 1).xyz);
    }
    vec3 vn = op_dinv_mul(i, av, avp);
    float fl = (i == 0 && u_floor != 0) ? floor_of(texelFetch(bound, ivec2(0), 0)) : 0.0;
    o0 = vec4(vn, 0.0);
    o1 = vec4(dot(vi, av), dot(vi, dv), dot(vn, vn), fl);
}
