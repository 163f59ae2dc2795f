// Per node of a level: the inverse of its diagonal block (core/amg_setup.c block_inverse: the
// inverse of the mean diagonal where the block is singular or its inverse not finite). On a pair
// level (op_pair, rotations: amg_level_inputs.glsl) per texel s = 2i + q instead: block q of node
// i's rows of its pair's 6x6 inverse (core's inverse6, Gauss-Jordan with partial pivoting; where a
// pivot is not above 1e-13 x the largest diagonal entry, the pair's two 3x3 inverses). The
// level's inputs: amg_level_inputs.glsl (D^-1 itself is this pass's output, not read).
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
out vec4 o0;
out vec4 o1;
out vec4 o2;

mat3 inverse3(mat3 D) {
    float det = determinant(D);
    mat3 inv;
    if (det != 0.0 && !isnan(det) && !isinf(det)) inv = inverse(D);
    if (!(det != 0.0 && !isnan(det) && !isinf(det)) || !finite3(inv[0]) || !finite3(inv[1]) || !finite3(inv[2])) {
        float tr = (D[0][0] + D[1][1] + D[2][2]) / 3.0;
        inv = mat3(tr > 0.0 && !isinf(tr) ? 1.0 / tr : 1.0);
    }
    return inv;
}

// Block q of node i's rows of its pair's 6x6 inverse.
mat3 pair_inverse(int i, int q) {
    int b = i & ~1;
    mat3 B[4];
    B[0] = op_diag_full(b);
    B[1] = op_pair_block(b);
    B[2] = op_pair_block(b + 1);
    B[3] = op_diag_full(b + 1);
    float M[36], V[36];
    float scale = 0.0;
    for (int p = 0; p < 2; ++p)
        for (int h = 0; h < 2; ++h)
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) M[6 * (3 * p + r) + 3 * h + c] = B[2 * p + h][c][r];
    for (int r = 0; r < 36; ++r) V[r] = 0.0;
    for (int r = 0; r < 6; ++r) {
        V[7 * r] = 1.0;
        scale = max(scale, abs(M[7 * r]));
    }
    bool ok = true;
    for (int c = 0; c < 6 && ok; ++c) {
        int piv = c;
        for (int r = c + 1; r < 6; ++r)
            if (abs(M[6 * r + c]) > abs(M[6 * piv + c])) piv = r;
        if (!(abs(M[6 * piv + c]) > 1e-13 * scale)) {
            ok = false;
            break;
        }
        if (piv != c)
            for (int h = 0; h < 6; ++h) {
                float t = M[6 * c + h];
                M[6 * c + h] = M[6 * piv + h];
                M[6 * piv + h] = t;
                t = V[6 * c + h];
                V[6 * c + h] = V[6 * piv + h];
                V[6 * piv + h] = t;
            }
        float d = 1.0 / M[6 * c + c];
        for (int h = 0; h < 6; ++h) {
            M[6 * c + h] *= d;
            V[6 * c + h] *= d;
        }
        for (int r = 0; r < 6; ++r) {
            if (r == c || M[6 * r + c] == 0.0) continue;
            float f = M[6 * r + c];
            for (int h = 0; h < 6; ++h) {
                M[6 * r + h] -= f * M[6 * c + h];
                V[6 * r + h] -= f * V[6 * c + h];
            }
        }
    }
    for (int r = 0; r < 36 && ok; ++r)
        if (isnan(V[r]) || isinf(V[r])) ok = false;
    int p = i & 1;
    if (!ok) return q == p ? inverse3(op_diag_full(i)) : mat3(0.0);
    mat3 o;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) o[c][r] = V[6 * (3 * p + r) + 3 * q + c];
    return o;
}

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    mat3 inv = op_pair() ? pair_inverse(s >> 1, s & 1) : inverse3(op_diag_full(s));
    o0 = blk_row(inv, 0);
    o1 = blk_row(inv, 1);
    o2 = blk_row(inv, 2);
}
