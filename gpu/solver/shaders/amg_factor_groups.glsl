#version 430 core
// The dense Cholesky factor of the multigrid's coarsest level (core/amg_setup.c coarse_factor),
// once per setup, by one work group (the level has at most WG_AMG_DENSE_NODES nodes, wg_amg.h),
// in place in image 0 (read-write: wg_amg.c binds it so): texel (c, r) = M[r][c]; at the end the
// inverse L^-T L^-1 there, whole and symmetric, each invocation solving for its columns, so the
// V-cycle's coarsest solve is a product the level's nodes share (amg_coarse_inverse.glsl), not
// two triangular solves in one invocation. Column by column (left-looking): one invocation takes the pivot, then the group the
// column's rows below it. A pivot that is not positive, or has lost more than 5 of float's 7
// digits against its own diagonal entry, gets 1 and its row and column are decoupled: a
// semi-definite coarse operator's null directions. (Core's double factor compares with 1e-14 x
// the largest diagonal entry; in float that bound would decouple the soft unknowns of a stiff
// level: a transverse direction's pivot is ~1e-6 of a stretch direction's, which float's
// rounding of the largest swamps.) The matrix lives in the image, not in an array of the
// invocation: 96^2 floats were past llvmpipe's stack for one (its factor came out zero).
// The level's inputs: amg_level_inputs.glsl (the finest level's form where the hierarchy has one
// level), the self-contact pairs' cross terms included.
#pragma weft include amg_blocks
#pragma weft include amg_level_inputs
layout(local_size_x = 64, local_size_y = 1) in;
layout(binding = 0, rgba32f) coherent uniform image2D wg_img0;
shared int decouple;
const int DMAX = 96;       // 3 x WG_AMG_DENSE_NODES
shared float diag[DMAX];

float M(int r, int c) { return imageLoad(wg_img0, ivec2(c, r)).x; }
void put(int r, int c, float v) { imageStore(wg_img0, ivec2(c, r), vec4(v, 0.0, 0.0, 0.0)); }
void sync() {
    memoryBarrierImage();
    memoryBarrierShared();
    barrier();
}

void main() {
    int t = int(gl_LocalInvocationID.x), d = 3 * u_n;
    for (int q = t; q < d * d; q += 64) put(q / d, q % d, 0.0);
    sync();
    for (int i = t; i < u_n; i += 64) {
        ivec4 r = ldi(rows, i);
        for (int k = r.x; k < r.y; ++k) {
            int j = ldi(cols, k).y;
            mat3 B = op_block(k);
            vec3 b0 = blk_row(B, 0).xyz, b1 = blk_row(B, 1).xyz, b2 = blk_row(B, 2).xyz;
            for (int c = 0; c < 3; ++c) {
                put(3 * i, 3 * j + c, b0[c]);
                put(3 * i + 1, 3 * j + c, b1[c]);
                put(3 * i + 2, 3 * j + c, b2[c]);
            }
        }
        if (u_cross == 0) continue;
        /* the pairs' cross blocks (amg_level_inputs.glsl op_cross) into row i's blocks */
        ivec4 cr = ldi(cross_i, i);
        for (int h = cr.x; h < cr.y; ++h) {
            int j = ldi(cross_i, h).x;
            mat3 B = op_cross_block(h - cr.w);
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c) put(3 * i + a, 3 * j + c, M(3 * i + a, 3 * j + c) + B[c][a]);
        }
    }
    sync();
    for (int j = 0; j < d; ++j) {
        if (t == 0) {
            float s = M(j, j), own = s;
            for (int k = 0; k < j; ++k) s -= M(j, k) * M(j, k);
            decouple = (!(s > 1e-5 * own) || isinf(s)) ? 1 : 0;
            if (decouple != 0) {
                for (int k = 0; k < j; ++k) put(j, k, 0.0);
                s = 1.0;
            }
            put(j, j, sqrt(s));
        }
        sync();
        float l = M(j, j);
        for (int i = j + 1 + t; i < d; i += 64) {
            float x = 0.0;
            if (decouple == 0) {
                x = M(i, j);
                for (int k = 0; k < j; ++k) x -= M(i, k) * M(j, k);
            }
            put(i, j, x / l);
        }
        sync();
    }
    // column c of the inverse (c = t, t + 64): L w = e_c, then L^T x = w, reading L's lower
    // triangle only; x's part above the diagonal goes to the upper triangle, free until now, and
    // x_c to shared memory; then the lower triangle and the diagonal from them (symmetry)
    for (int c = t; c < d; c += 64) {
        float w[DMAX];
        for (int i = 0; i < d; ++i) {
            float s = i == c ? 1.0 : 0.0;
            for (int k = c; k < i; ++k) s -= M(i, k) * w[k];
            w[i] = i < c ? 0.0 : s / M(i, i);
        }
        for (int i = d - 1; i >= 0; --i) {
            float s = w[i];
            for (int k = i + 1; k < d; ++k) s -= M(k, i) * w[k];
            w[i] = s / M(i, i);
        }
        for (int i = 0; i < c; ++i) put(i, c, w[i]);
        diag[c] = w[c];
    }
    sync();   // every read of L done
    for (int q = t; q < d * d; q += 64) {
        int r = q / d, c = q % d;
        if (r > c) put(r, c, M(c, r));
        else if (r == c) put(r, c, diag[r]);
    }
}
