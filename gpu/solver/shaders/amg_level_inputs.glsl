// One level's operator and smoother for the multigrid's passes over it (an include, not a pass;
// wg_amg.c level_in gives these inputs, and each pass's table in wg_passes.c names those it reads).
// Two forms, the same functions:
//  - a coarse level (and the finest of a one-level hierarchy): full 3x3 blocks in three textures
//    (amg_blocks.glsl), the Galerkin sums;
//  - the finest level (WG_AMG_FINE: the *_fine passes, wg_device.c): P^ = S A S + a (I - S),
//    a_i = trace(A_ii) / 3 (core/amg_setup.c project_fine), read from the system's own symmetric
//    blocks (24 bytes a block) and the filter, where a copy of P^ as full blocks took 48 and a
//    pass per solve. The V-cycle's vectors on it stay in range(S) (PCG's r is filtered, D^-1 and
//    P^ keep range(S), and the coarse correction is filtered as it is prolonged: op_prolong), and
//    there P^ x = S (A x), one filter per row. Filtering the correction changes no S z, the part
//    PCG uses: P^ and D are block diagonal over range(S) + null(S), so the null part never feeds
//    back into range(S).
// Pattern: rows = (block start, end, diagonal block, aggregate on the next level or -1), cols =
// (row, column, -, -) per block (the system's own block texture on the finest level).
uniform isampler2D rows;
uniform isampler2D cols;
#ifdef WG_AMG_FINE
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D dinv0; // D^-1, row 0
uniform sampler2D dinv1; // row 1
uniform sampler2D dinv2; // row 2

mat3 op_filter(int i) { return filter_S(ld(S0, i), ld(S1, i)); }
bool op_filtered(int i) { return ld(S1, i).z != 0.0; }
mat3 op_a(int k) { return sym(ld(a_lo, k), ld(a_hi, k).xy); }
// a_i of a diagonal block A_ii: its mean diagonal, 1 where that is not positive and finite.
float op_scale(mat3 A) {
    float a = (A[0][0] + A[1][1] + A[2][2]) / 3.0;
    return (!(a > 0.0) || isinf(a)) ? 1.0 : a;
}

// Block k of P^ (row i, column j).
mat3 op_block(int k) {
    ivec4 b = ldi(cols, k);
    mat3 A = op_a(k), o = A;
    if (op_filtered(b.y)) o = o * op_filter(b.y);
    if (op_filtered(b.x)) {
        mat3 S = op_filter(b.x);
        o = S * o;
        if (b.x == b.y) o += op_scale(A) * (mat3(1.0) - S);
    }
    return o;
}
mat3 op_dinv(int i) { return blk(dinv0, dinv1, dinv2, i); }
// The coarse correction xc of node j's aggregate, as added to x_j: filtered (above).
vec3 op_prolong(int j, vec3 xc) { return filter_apply(ld(S0, j), ld(S1, j), xc); }
// The finest level is never a pair level (op_pair below): its D^-1 is 3x3 per node.
bool op_pair() { return false; }
vec3 op_dinv_mul(int i, vec3 t, vec3 tp) { return op_dinv(i) * t; }
mat3 op_pair_block(int i) { return mat3(0.0); }

// op_row's parts (below): for x in range(S) (the V-cycle's vectors) row i of P^ x is S_i (A x)_i.
vec3 op_mul(int k, vec3 x) { return op_a(k) * x; }
vec3 op_row_end(int i, vec3 y) { return filter_apply(ld(S0, i), ld(S1, i), y); }
#else
uniform sampler2D a0;    // blocks, row 0
uniform sampler2D a1;    // row 1
uniform sampler2D a2;    // row 2
uniform sampler2D dinv0; // D^-1, row 0
uniform sampler2D dinv1; // row 1
uniform sampler2D dinv2; // row 2

// u_pair 1: a pair level of the rotations' hierarchy (wg_amg.h "rotations"; core's group 2 with
// pair_blocks): the nodes 2a, 2a + 1 of one finer aggregate share their columns and the smoother's
// D is 6x6 per pair; D^-1 then holds node i's rows in two blocks, texel 2i (to node i & ~1) and
// 2i + 1 (to i | 1), and rows.w is the block (i, i ^ 1) of row i (no aggregate is read there:
// rotations go with the smoothed prolongator, whose passes read P's lists instead).
uniform int u_pair;
mat3 op_block(int k) { return blk(a0, a1, a2, k); }
mat3 op_dinv(int i) { return blk(dinv0, dinv1, dinv2, i); }
vec3 op_prolong(int j, vec3 xc) { return xc; }
bool op_pair() { return u_pair != 0; }
// (D^-1 t)_i from t_i and, on a pair level, t of node i ^ 1 (tp).
vec3 op_dinv_mul(int i, vec3 t, vec3 tp) {
    if (u_pair == 0) return op_dinv(i) * t;
    bool odd = (i & 1) != 0;
    return op_dinv(2 * i) * (odd ? tp : t) + op_dinv(2 * i + 1) * (odd ? t : tp);
}
// The pair's block (i, i ^ 1) of D on a pair level.
mat3 op_pair_block(int i) { return u_pair != 0 ? op_block(ldi(rows, i).w) : mat3(0.0); }

vec3 op_mul(int k, vec3 x) { return op_block(k) * x; }
vec3 op_row_end(int i, vec3 y) { return y; }
#endif
mat3 op_diag(int i) { return op_block(ldi(rows, i).z); }

// Node j's x as the level's products read it: x_j, + op_prolong(j, xc[agg j]) with prolong. A pass
// that defines WG_AMG_X_HOOK before this include gives its own op_x (amg_smooth.glsl: x after
// the smoother's first step, made where it is read, so that one pass takes two steps).
#ifdef WG_AMG_X_HOOK
vec3 op_x(int j, sampler2D x, sampler2D xc, bool prolong);
#else
vec3 op_x(int j, sampler2D x, sampler2D xc, bool prolong) {
    vec3 xj = ld(x, j).xyz;
    if (prolong) xj += op_prolong(j, ld(xc, ldi(rows, j).w).xyz);
    return xj;
}
#endif

// The self-contact pairs' cross terms on this level (wg_amg.h "Cross terms", wg_amg_cross.c):
// pair q's term is c (sum_k e_k u_k)(sum_j e_j u_j)^T, e_k the level's node of slot k's
// particle, u_k its filtered vector (amg_cross_terms.glsl); its k = j parts are A's diagonal
// blocks (the pairs' additions, summed into the coarse levels by the Galerkin passes), the rest,
// c u_k u_j^T for k != j, is summed per setup into 3x3 blocks per pair of nodes
// (amg_cross_blocks.glsl) and added here: a few blocks a node where the slots of an aggregate's
// pairs are hundreds. cross_i per node (first block entry, end, its diagonal cross block or -1,
// n: entry h is block h - n), per block entry (column node, its terms, -); cross_a: block b's
// rows in texels 3 b .. 3 b + 2. u_cross 0: no pairs (nothing read).
uniform isampler2D cross_i;
uniform sampler2D cross_a;
uniform int u_cross;

mat3 op_cross_block(int b) { return blk_rows(ld(cross_a, 3 * b).xyz, ld(cross_a, 3 * b + 1).xyz, ld(cross_a, 3 * b + 2).xyz); }
// Row i of the cross terms times x (x_j + op_prolong(j, xc[agg j]) read with prolong).
vec3 op_cross(int i, sampler2D x, sampler2D xc, bool prolong) {
    vec3 y = vec3(0.0);
    if (u_cross == 0) return y;
    ivec4 r = ldi(cross_i, i);
    for (int h = r.x; h < r.y; ++h) {
        int j = ldi(cross_i, h).x;
        y += op_cross_block(h - r.w) * op_x(j, x, xc, prolong);
    }
    return y;
}
// The cross terms' part of node i's diagonal block (two slots of a pair on node i).
mat3 op_cross_diag(int i) {
    if (u_cross == 0) return mat3(0.0);
    int b = ldi(cross_i, i).z;
    return b < 0 ? mat3(0.0) : op_cross_block(b);
}
// The level's whole diagonal block (the smoother's D, the Rayleigh quotient's).
mat3 op_diag_full(int i) { return op_diag(i) + op_cross_diag(i); }

// Row i of the level's operator times x, x_j + op_prolong(j, xc[agg j]) read with prolong (on the
// finest level x in range(S): above).
vec3 op_row(int i, sampler2D x, sampler2D xc, bool prolong) {
    ivec4 r = ldi(rows, i);
    vec3 y = vec3(0.0);
    for (int k = r.x; k < r.y; ++k) {
        int j = ldi(cols, k).y;
        y += op_mul(k, op_x(j, x, xc, prolong));
    }
    return op_row_end(i, y + op_cross(i, x, xc, prolong));
}
#ifdef WG_AMG_FINE
// Row i of P^ x for any x (the power iterations, from core's unfiltered start vector).
vec3 op_row_any(int i, sampler2D x) {
    ivec4 r = ldi(rows, i);
    vec3 y = vec3(0.0);
    for (int k = r.x; k < r.y; ++k) {
        int j = ldi(cols, k).y;
        y += op_a(k) * filter_apply(ld(S0, j), ld(S1, j), ld(x, j).xyz);
    }
    y += op_cross(i, x, x, false);   /* u_j . x_j = u_j . S_j x_j: u_j is filtered */
    if (!op_filtered(i)) return y;
    mat3 S = op_filter(i);
    vec3 xi = ld(x, i).xyz;
    return S * y + op_scale(op_a(r.z)) * (xi - S * xi);
}
#else
vec3 op_row_any(int i, sampler2D x) { return op_row(i, x, x, false); }
#endif
