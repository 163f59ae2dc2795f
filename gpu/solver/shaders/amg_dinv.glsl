// Per node of a level: the inverse of its diagonal block (core/amg_setup.c block_inverse: the
// inverse of the mean diagonal where the block is singular or its inverse not finite). The
// level's inputs: amg_level_inputs.glsl (D^-1 itself is this pass's output, not read).
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    mat3 D = op_diag_full(i);
    float det = determinant(D);
    mat3 inv;
    if (det != 0.0 && !isnan(det) && !isinf(det)) inv = inverse(D);
    if (!(det != 0.0 && !isnan(det) && !isinf(det)) || !finite3(inv[0]) || !finite3(inv[1]) || !finite3(inv[2])) {
        float tr = (D[0][0] + D[1][1] + D[2][2]) / 3.0;
        inv = mat3(tr > 0.0 && !isinf(tr) ? 1.0 / tr : 1.0);
    }
    o0 = blk_row(inv, 0);
    o1 = blk_row(inv, 1);
    o2 = blk_row(inv, 2);
}
