// The multigrid's coarse levels in one work group (an include of pcg_group_amg.glsl and
// amg_sub_groups.glsl, not a pass): wg_amg_group.c's packed levels (ipack, fpack; their layout in
// pcg_group_amg.glsl's header), the V-cycle's vectors of a coarse level in "image 5" (wg_img5), a coarse
// level's smoothing step, residual restricted, and dense coarsest solve, and the V-cycle's loop
// from a level down and back (amg_group_cycle), each in wg_amg.c vcycle's order and arithmetic.
// The includer defines R (rows an invocation), T (the invocation), row(k) (its row k: T + 1,024 k)
// and GROUP_SCRATCH (image 5's unit: wg_run_groups_scratch binds it after the outputs) before it, includes amg_blocks, amg_smooth_step and amg_coarse_inverse, and defines the three
// steps amg_group_cycle calls on any level (the finest may be its own): smooth_level,
// coarsest_dense and restrict_into.
uniform isampler2D ipack;
uniform sampler2D fpack;
uniform int u_levels;
uniform int u_dense;        // the coarsest level has a dense factor
uniform int u_smoothed;     // the smoothed prolongator: P's lists restrict and prolong
uniform int u_sweeps;       // the smoother's degree
uniform int u_coarse_sweeps;
uniform float u_ratio;
layout(binding = GROUP_SCRATCH, rgba32f) coherent uniform image2D wg_img5;   // the includer's unit

#define SR 0                // image 5's slots of a level: r, x, d, the residual restricted
#define SX 1
#define SD 2
#define SE 3

struct level {
    int rows, cols, mr, ml, f, s, n, nb, pr, pt, pair, pf, np;
};

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

// the coarsest level L's dense solve on a coarse level: node I's x from the inverse's row of
// blocks, by invocation I (at most WG_AMG_DENSE_NODES nodes)
void coarsest_dense_coarse(level L) {
    vec3 x = vec3(0.0);
    if (T < L.n)
        for (int J = 0; J < L.n; ++J) x += coarse_inverse_block(T, J) * sget(L, SR, J);
    if (T < L.n) sset(L, SX, T, x);
    sync_image();
}

// a coarse level L's residual r - A x (x its last smoothing step's) restricted into N's r
void restrict_coarse(level L, level N) {
    for (int k = 0; k < R; ++k)
        if (row(k) < L.n) sset(L, SE, row(k), sget(L, SR, row(k)) - coarse_row(L, row(k)));
    sync_image();
    if (u_smoothed != 0) {
        RESTRICT_P(L, N, sget(L, SE, i));
    } else {
        RESTRICT_INTO(N, sget(L, SE, i));
    }
}

void smooth_level(int l, level L, level N, int step, bool zero, bool prolong);
void coarsest_dense(int l, level L);
void restrict_into(int l, level L, level N);

// the V-cycle from level first on its r (wg_amg.c vcycle). One loop over its smoothing steps
// with one call of each phase (a shader compiler inlines every call): down the levels u_sweeps
// steps from x = 0 then the restriction, the coarsest level, up the levels u_sweeps steps with
// the prolongation in the first.
void amg_group_cycle(int first) {
    int top = u_levels - 1, l = first, k = 0;
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
        if (--l < first) break;
    }
}
