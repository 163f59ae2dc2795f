#version 430 core
// PCG with the block-Jacobi preconditioner, a whole solve in one work group of 1,024 invocations
// (compute passes, a cloth of at most GRP_MAX particles: wg_solve.c solve_group): the solve is
// pcg_group_solve.glsl's, the preconditioner D~^-1 per row (dinv_block.glsl, shared with the
// dinv pass), made at the start and kept in registers with the solve's vectors (63 floats a row
// in all: a GPU may spill some to its L1).
layout(local_size_x = 1024, local_size_y = 1) in;
#pragma weft include pcg_scalars_rules
#pragma weft include dinv_block
#pragma weft include project_row
#pragma weft include pcg_group_solve

vec4 xdl[R];                // D~^-1 as symmetric blocks (common.glsl's sym): 18 floats, not 27
vec2 xdh[R];

void precondition_setup(int k, int i) {
    int dk = ldi(pblocks, i).z;
    mat3 inv = dinv_block(sym(ld(a_lo, dk), ld(a_hi, dk).xy), ld(S0, i), ld(S1, i));
    xdl[k] = sym_lo(inv);
    xdh[k] = sym_hi(inv);
}

// (r.t, r.r) of the rows, t = D~^-1 r first
vec2 precondition() {
    vec2 acc = vec2(0.0);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            xt[k] = sym(xdl[k], xdh[k]) * xr[k];
            acc += vec2(dot(xr[k], xt[k]), dot(xr[k], xr[k]));
        }
    return sum2(acc);
}

void main() { pcg_group_main(); }
