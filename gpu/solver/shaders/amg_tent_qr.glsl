// The rotations about the current positions (wg_amg.current): aggregate a's QR of its (3 m) x 6
// near-null rows, core's (core/amg_tent.c: modified Gram-Schmidt, each column orthogonalised twice
// against the earlier live ones, a column whose orthogonal part is at most WC_AMG_DEPENDENT x its
// norm dead), in float. The rows are taken about the aggregate's centre c (the mean of its
// nodes' positions, or of its nodes' centres on a coarse level) rather than core's one centroid
// of every particle: B(c) = B(cg) M, M = [I K; 0 I] upper triangular, so Q is the same and R is
// R(cg) M, without float's cancellation of a far centroid (docs/design/gpu_passes.md). Core's
// dead test is kept: a column's norm is taken about the particles' centroid cg as core's.
// Q's columns are held per member (tq_q) and, for P_tent's blocks, as coefficients on the rows
// (column c of Q = B (ta[c], tb[c]): amg_tent_coef, amg_tent_blocks).
uniform isampler2D tq_range;  // per aggregate: (its first node in tq_list, end)
uniform isampler2D tq_list;   // nodes of this level
uniform sampler2D pos;        // the finest level: the positions
uniform sampler2D cen;        // 1 x 1: the positions' sum
uniform sampler2D nn0;        // a coarse level: a node's near-null rows about its centre (row r,
uniform sampler2D nn1;        // columns 3h..3h + 2 in nn(2r + h).xyz)
uniform sampler2D nn2;
uniform sampler2D nn3;
uniform sampler2D nn4;
uniform sampler2D nn5;
uniform sampler2D nc;         // a coarse level: (its centre, dead bits)
uniform int u_fine;           // this level is the finest (rows from pos)
uniform float u_inv_count;    // 1 / the particles

float tq_R[36];
bool tq_live[6];
vec3 tq_ta[6];
vec3 tq_tb[6];

// K(d): column k is d x e_k (core's rot[r][k] of d)
mat3 tq_skew(vec3 d) { return mat3(0.0, d.z, -d.y, -d.z, 0.0, d.x, d.y, -d.x, 0.0); }

// node j's centre: its position, or its aggregate's centre on the finer level
vec3 tq_centre(int j) { return u_fine != 0 ? ld(pos, j).xyz : ld(nc, j).xyz; }

// node j's rows about the point c: the translations' columns tr and the rotations' ro
void tq_rows(int j, vec3 c, out mat3 tr, out mat3 ro) {
    if (u_fine != 0) {
        tr = mat3(1.0);
        ro = tq_skew(ld(pos, j).xyz - c);
        return;
    }
    vec4 r0 = ld(nn0, j), r1 = ld(nn1, j), r2 = ld(nn2, j), r3 = ld(nn3, j), r4 = ld(nn4, j), r5 = ld(nn5, j);
    tr = transpose(mat3(r0.xyz, r2.xyz, r4.xyz));
    ro = transpose(mat3(r1.xyz, r3.xyz, r5.xyz)) + tr * tq_skew(ld(nc, j).xyz - c);
}


// Aggregate a's QR into tq_R (R about its centre, returned), tq_live and Q's coefficients; its
// columns about its centre in tq_q (member s's rows of column k: tq_q[6 s + k]), core's qr_local
// on them (the host keeps aggregates of at most WG_AMG_TENT_NODES nodes, TQ_CAP here).
#define TQ_CAP 128
vec3 tq_q[6 * TQ_CAP];

vec3 tent_qr(int a) {
    ivec4 m = ldi(tq_range, a);
    const int cnt = m.y - m.x;
    vec3 c = vec3(0.0);
    for (int e = m.x; e < m.y; ++e) c += tq_centre(ldi(tq_list, e).x);
    c /= float(cnt);
    vec3 cg = texelFetch(cen, ivec2(0), 0).xyz * u_inv_count;
    float n0[6];
    for (int k = 0; k < 6; ++k) n0[k] = 0.0;
    mat3 to_cg = tq_skew(c - cg);   // the rotations about cg: + the translations x K(c - cg)
    for (int s = 0; s < cnt; ++s) {
        mat3 tr, ro;
        tq_rows(ldi(tq_list, m.x + s).x, c, tr, ro);
        mat3 rg = ro + tr * to_cg;
        for (int k = 0; k < 3; ++k) {
            tq_q[6 * s + k] = tr[k];
            tq_q[6 * s + 3 + k] = ro[k];
            n0[k] += dot(tr[k], tr[k]);
            n0[3 + k] += dot(rg[k], rg[k]);
        }
    }
    for (int k = 0; k < 36; ++k) tq_R[k] = 0.0;
    for (int k = 0; k < 6; ++k) {
        tq_ta[k] = k < 3 ? vec3(k == 0, k == 1, k == 2) : vec3(0.0);
        tq_tb[k] = k < 3 ? vec3(0.0) : vec3(k == 3, k == 4, k == 5);
    }
    for (int k = 0; k < 6; ++k) {
        float norm0 = sqrt(n0[k]);   // about cg, core's column
        for (int pass = 0; pass < 2; ++pass)
            for (int d = 0; d < k; ++d) {
                if (!tq_live[d]) continue;
                float sum = 0.0;
                for (int s = 0; s < cnt; ++s) sum += dot(tq_q[6 * s + d], tq_q[6 * s + k]);
                for (int s = 0; s < cnt; ++s) tq_q[6 * s + k] -= sum * tq_q[6 * s + d];
                tq_ta[k] -= sum * tq_ta[d];
                tq_tb[k] -= sum * tq_tb[d];
                tq_R[6 * d + k] += sum;
            }
        float norm = 0.0;
        for (int s = 0; s < cnt; ++s) norm += dot(tq_q[6 * s + k], tq_q[6 * s + k]);
        norm = sqrt(norm);
        tq_live[k] = norm > 1e-6 * norm0 && !isinf(norm) && !isnan(norm);
        float scale = tq_live[k] ? 1.0 / norm : 0.0;
        for (int s = 0; s < cnt; ++s) tq_q[6 * s + k] *= scale;
        tq_ta[k] *= scale;
        tq_tb[k] *= scale;
        tq_R[7 * k] = tq_live[k] ? norm : 0.0;
    }
    return c;
}
