#version 430 core
// PCG with the multigrid's V-cycle, a whole solve in one work group of 1,024 invocations
// (compute passes, a cloth of at most GRP_MAX particles: wg_solve.c solve_group): the solve is
// pcg_group_solve.glsl's, the preconditioner one V-cycle of wg_amg.c's (vcycle) per
// precondition(), in its order and with its arithmetic: amg_smooth_step.glsl's steps (Chebyshev
// of degree u_sweeps before and after the coarse correction, the prolongation added in the first
// step after it), the restriction summing each aggregate's residuals in its member list's order,
// or with the smoothed prolongator (u_smoothed; wg_amg.h smoothed, rotations) the residual
// restricted by P^T in amg_restrict_p.glsl's order and the correction prolonged by P's rows
// (amg_prolong.glsl) before the first step after it, a pair level's smoother taking its pair's
// 6x6 D^-1 (amg_level_inputs.glsl op_dinv_mul), and the coarsest level's dense solve (amg_coarse_inverse.glsl) or its u_coarse_sweeps block-Jacobi
// sweeps. The setup (wg_amg_setup) ran before as passes; amg_group_pack_groups.glsl copied each
// smoothed level's bound, D^-1 and blocks into fpack.
//
// Where the V-cycle's vectors live: the finest level's x (z, the preconditioned residual) and d
// in registers with PCG's vectors, x in shared memory when neighbours read it (the residual
// restricted goes through shared memory too); a coarser level's r, x, d and restricted residual
// in image 5 (coherent; every phase that writes them ends in memoryBarrierImage and barrier); the
// coarsest level's dense solve one node an invocation. Node I of every level is invocation
// I mod 1,024's.
//
// ipack (int4): per level l, texels 4 l = (rows, cols, members' ranges, members) offsets,
// 4 l + 1 = (fpack offset, image 5 offset, nodes, blocks), 4 l + 2 = (P's rows, P's columns
// offsets, a pair level, fpack offset of P's blocks) and 4 l + 3 = (P's entries, -, -, -); then,
// per coarse level, its rows (block start, end, diagonal, the block (i, i ^ 1) on a pair level,
// else the aggregate on the next level or -1), blocks (row, column), with P = P_tent each node's
// range of members and the members (nodes of the finer level) ascending; per level with a
// smoothed P, its rows (entries first, end), its entries (row, coarse node), each next-level
// node's range of entries and those (entry, row) (wg_amg_smooth.c's p_rows, p_ent, pt_range,
// pt_list). fpack (float4), per smoothed level from its offset: the smoother's bound (x), D^-1's
// rows 0..2 (n texels each; 2n on a pair level: node i's blocks 2i, 2i + 1), and on a coarse
// level its blocks' rows 0..2 (nb each); per level with a smoothed P from its own offset, P's
// blocks' rows 0..2 (np each). Image 5, per coarse level from its offset: r, x, d and the
// residual to restrict (n texels each).
layout(local_size_x = 1024, local_size_y = 1) in;
#pragma weft include pcg_scalars_rules
#pragma weft include project_row
#pragma weft include pcg_group_solve
#pragma weft include amg_blocks
#pragma weft include amg_smooth_step
#pragma weft include amg_coarse_inverse
uniform isampler2D rows;    // the finest level's nodes (amg_level_inputs.glsl): w its aggregate
uniform isampler2D ipack;
uniform sampler2D fpack;
uniform int u_levels;
uniform int u_dense;        // the coarsest level has a dense factor
uniform int u_smoothed;     // the smoothed prolongator: P's lists restrict and prolong
uniform int u_sweeps;       // the smoother's degree
uniform int u_coarse_sweeps;
uniform float u_ratio;
layout(binding = 5, rgba32f) coherent uniform image2D wg_img5;

#define SR 0                // image 5's slots of a level: r, x, d, the residual restricted
#define SX 1
#define SD 2
#define SE 3

struct level {
    int rows, cols, mr, ml, f, s, n, nb, pr, pt, pair, pf, np;
};

vec3 xd[R];                 // the finest level's smoothing step d (xt holds its x)

level lvl(int l) {
    ivec4 a = ldi(ipack, 4 * l), c = ldi(ipack, 4 * l + 1), e = ldi(ipack, 4 * l + 2);
    return level(a.x, a.y, a.z, a.w, c.x, c.y, c.z, c.w, e.x, e.y, e.z, e.w, ldi(ipack, 4 * l + 3).x);
}
vec3 fp(int i) { return ld(fpack, i).xyz; }
float bound_of(level L) { return ld(fpack, L.f).x; }
int dinv_n(level L) { return L.pair != 0 ? 2 * L.n : L.n; }
mat3 dinv_at(level L, int t) {
    int o = L.f + 1, m = dinv_n(L);
    return blk_rows(fp(o + t), fp(o + m + t), fp(o + 2 * m + t));
}
// (D^-1 t)_i (amg_level_inputs.glsl op_dinv_mul): on a pair level from t_i and t of node i ^ 1 (tp)
vec3 dinv_mul(level L, int i, vec3 t, vec3 tp) {
    if (L.pair == 0) return dinv_at(L, i) * t;
    bool odd = (i & 1) != 0;
    return dinv_at(L, 2 * i) * (odd ? tp : t) + dinv_at(L, 2 * i + 1) * (odd ? t : tp);
}
mat3 block_of(level L, int k) {
    int o = L.f + 1 + 3 * dinv_n(L);
    return blk_rows(fp(o + k), fp(o + L.nb + k), fp(o + 2 * L.nb + k));
}
mat3 p_block(level L, int e) { return blk_rows(fp(L.pf + e), fp(L.pf + L.np + e), fp(L.pf + 2 * L.np + e)); }
vec3 sget(level L, int slot, int i) { return imageLoad(wg_img5, tc(L.s + slot * L.n + i)).xyz; }
void sset(level L, int slot, int i, vec3 v) { imageStore(wg_img5, tc(L.s + slot * L.n + i), vec4(v, 0.0)); }
void sync_image() {
    memoryBarrierImage();
    barrier();
}

// row I of a coarse level's operator times its x (amg_level_inputs.glsl op_row)
vec3 coarse_row(level L, int I) {
    ivec4 r = ldi(ipack, L.rows + I);
    vec3 y = vec3(0.0);
    for (int k = r.x; k < r.y; ++k) y += block_of(L, k) * sget(L, SX, ldi(ipack, L.cols + k).y);
    return y;
}

// the smoothed P's row i of level L times N's x (amg_prolong.glsl), or with P = P_tent the
// correction of node i's aggregate
vec3 prolong_row(level L, level N, int i, int agg) {
    if (u_smoothed == 0) return sget(N, SX, agg);
    ivec4 r = ldi(ipack, L.pr + i);
    vec3 s = vec3(0.0);
    for (int e = r.x; e < r.y; ++e) s += p_block(L, e) * sget(N, SX, ldi(ipack, L.pr + L.n + e).y);
    return s;
}

// the sum over each of N's aggregates of its members' residuals, into N's r; res(i) the finer
// level's residual of node i
#define RESTRICT_INTO(N, RES) \
    for (int k = 0; k < R; ++k) \
        if (row(k) < N.n) { \
            ivec4 m = ldi(ipack, N.mr + row(k)); \
            vec3 s = vec3(0.0); \
            for (int e = m.x; e < m.y; ++e) { int i = ldi(ipack, N.ml + e).x; s += RES; } \
            sset(N, SR, row(k), s); \
        } \
    sync_image()

// P^T of level L's residuals into N's r, each of N's nodes its entries of P in order
// (amg_restrict_p.glsl); res(i) the residual of L's node i
#define RESTRICT_P(L, N, RES) \
    for (int k = 0; k < R; ++k) \
        if (row(k) < N.n) { \
            ivec4 m = ldi(ipack, L.pt + row(k)); \
            vec3 s = vec3(0.0); \
            for (int e = m.x; e < m.y; ++e) { \
                ivec4 q = ldi(ipack, L.pt + N.n + e); \
                int i = q.y; \
                s += transpose(p_block(L, q.x)) * RES; \
            } \
            sset(N, SR, row(k), s); \
        } \
    sync_image()

// one smoothing step on the finest level (amg_smooth.glsl over it: the operator S (A x), the
// correction of N's x filtered as it is prolonged)
void smooth_fine(level L, level N, int step, bool zero, bool prolong) {
    if (!zero) {
        if (prolong)
            for (int k = 0; k < R; ++k)
                if (row(k) < u_n) {
                    int i = row(k);
                    xt[k] += filter_apply(ld(S0, i), ld(S1, i), prolong_row(L, N, i, ldi(rows, i).w));
                }
        share_rows(xt);
    }
    float bd = bound_of(L);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) {
            int i = row(k);
            vec3 t = xr[k];
            if (!zero) t -= spmv_row(i);
            vec3 di = amg_smooth_step(step, bd, u_ratio, dinv_at(L, i) * t, xd[k]);
            xt[k] = (zero ? vec3(0.0) : xt[k]) + di;
            xd[k] = di;
        }
}

// one smoothing step on a coarse level (amg_smooth.glsl), N's x added to x first with prolong
void smooth_coarse(level L, level N, int step, bool zero, bool prolong) {
    if (!zero && prolong) {
        for (int k = 0; k < R; ++k)
            if (row(k) < L.n) sset(L, SX, row(k), sget(L, SX, row(k)) + prolong_row(L, N, row(k), ldi(ipack, L.rows + row(k)).w));
        sync_image();
    }
    float bd = bound_of(L);
    vec3 xn[R], dn[R];
    for (int k = 0; k < R; ++k)
        if (row(k) < L.n) {
            int I = row(k);
            vec3 t = sget(L, SR, I), xi = vec3(0.0);
            vec3 tp = L.pair != 0 ? sget(L, SR, I ^ 1) : vec3(0.0);   // a pair level: D^-1 reads node I ^ 1's too
            if (!zero) {
                t -= coarse_row(L, I);
                if (L.pair != 0) tp -= coarse_row(L, I ^ 1);
                xi = sget(L, SX, I);
            }
            dn[k] = amg_smooth_step(step, bd, u_ratio, dinv_mul(L, I, t, tp), step >= 1 ? sget(L, SD, I) : vec3(0.0));
            xn[k] = xi + dn[k];
        }
    barrier();   // every read of x done
    for (int k = 0; k < R; ++k)
        if (row(k) < L.n) {
            sset(L, SX, row(k), xn[k]);
            sset(L, SD, row(k), dn[k]);
        }
    sync_image();
}

void smooth_level(int l, level L, level N, int step, bool zero, bool prolong) {
    if (l == 0) smooth_fine(L, N, step, zero, prolong);
    else smooth_coarse(L, N, step, zero, prolong);
}

// the coarsest level l's dense solve: node I's x from the inverse's row of blocks, by invocation I
// (the level has at most WG_AMG_DENSE_NODES nodes; on level 0, u_n: node I is row(0))
void coarsest_dense(int l, level L) {
    if (l == 0) share_rows(xr);
    vec3 x = vec3(0.0);
    if (T < L.n)
        for (int J = 0; J < L.n; ++J) x += coarse_inverse_block(T, J) * (l == 0 ? get(J) : sget(L, SR, J));
    if (l == 0) {
        if (T < u_n) xt[0] = x;
    } else {
        if (T < L.n) sset(L, SX, T, x);
        sync_image();
    }
}

void precondition_setup(int k, int i) {}

// the residual r - A x of level l's nodes (x its last smoothing step's) restricted into N's r
void restrict_into(int l, level L, level N) {
    if (l == 0) {   // through shared memory
        share_rows(xt);
        for (int k = 0; k < R; ++k)
            if (row(k) < u_n) xq[k] = xr[k] - spmv_row(row(k));
        share_rows(xq);
        if (u_smoothed != 0) {
            RESTRICT_P(L, N, get(i));
        } else {
            RESTRICT_INTO(N, get(i));
        }
    } else {
        for (int k = 0; k < R; ++k)
            if (row(k) < L.n) sset(L, SE, row(k), sget(L, SR, row(k)) - coarse_row(L, row(k)));
        sync_image();
        if (u_smoothed != 0) {
            RESTRICT_P(L, N, sget(L, SE, i));
        } else {
            RESTRICT_INTO(N, sget(L, SE, i));
        }
    }
}

// t = the V-cycle on r (wg_amg.c vcycle), and the group's (r.t, r.r). One loop over its
// smoothing steps with one call of each phase (a shader compiler inlines every call): down the
// levels u_sweeps steps from x = 0 then the restriction, the coarsest level, up the levels
// u_sweeps steps with the prolongation in the first.
vec2 precondition() {
    int top = u_levels - 1, l = 0, k = 0;
    bool down = true;
    for (;;) {
        bool bottom = l == top;
        if (bottom && u_dense != 0) {
            coarsest_dense(l, lvl(l));
        } else {
            level L = lvl(l), N = lvl(bottom ? l : l + 1);
            smooth_level(l, L, N, bottom ? -1 : k, (down || bottom) && k == 0, !down && !bottom && k == 0);
            if (++k < (bottom ? u_coarse_sweeps : u_sweeps)) continue;
            k = 0;
            if (down && !bottom) {
                restrict_into(l, L, N);
                ++l;
                continue;
            }
        }
        // the coarsest level done, or a step up
        down = false;
        k = 0;
        if (--l < 0) break;
    }
    vec2 acc = vec2(0.0);
    for (int k = 0; k < R; ++k)
        if (row(k) < u_n) acc += vec2(dot(xr[k], xt[k]), dot(xr[k], xr[k]));
    return sum2(acc);
}

void main() { pcg_group_main(); }
