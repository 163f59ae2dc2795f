// Per node of a level, one power iteration for lambda_max(D^-1 A) (core/amg_eigen.c, the power
// method): v' = D^-1 A v, and (v.Av, v.Dv) for the Rayleigh quotient of the last one. Not
// normalised: over the few iterations a setup takes (wg_amg.h) |v| grows by lambda_max^k, far
// from float's range.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D t8;   // v
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 av = lvl_row(t0, t1, t2, t3, t4, t8, i);
    vec3 v = ld(t8, i).xyz;
    vec3 dv = blk(t2, t3, t4, ldi(t0, i).z) * v;
    o0 = vec4(blk(t5, t6, t7, i) * av, 0.0);
    o1 = vec4(dot(v, av), dot(v, dv), 0.0, 0.0);
}
