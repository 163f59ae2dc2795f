// Per node of a level: r - A x, the residual after the pre-smoothing, which the smoothed
// prolongator's restriction reads (amg_restrict_p.glsl; each node is in several aggregates'
// rows of P^T). The level's inputs: amg_level_inputs.glsl.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
uniform sampler2D r;
uniform sampler2D x;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    o0 = vec4(ld(r, i).xyz - op_row(i, x, x, false), 0.0);
}
