// Per row of a cross block of one multigrid level (item 3 b + r: row r of block b), once per
// setup, the levels in order (wg_amg_cross.c lists them; amg_level_inputs.glsl reads them). On
// the finest level (u_cross_fine 0) block b (particle i, particle j) sums c u_k u_j^T over its
// terms, the slots k at i and j at j of one pair, k != j (cross_u: per slot (u, c),
// amg_cross_terms.glsl; c 0: the pair is inactive); below, block (I, J) sums the finer level's
// blocks (i, j) with aggregates I and J (cross_fine: their rows), the unsmoothed prolongator's
// Galerkin product. cross_i: the level's u_cross_nodes node heads, then the block entries
// (column, items' first, end, the items' first texel), then the items, 4 a texel: a term's code
// 4 e + m (slot k = e, slot j = 4 q + (k + m) mod 4 of pair q = e / 4) or a finer block.
uniform isampler2D cross_i;
uniform sampler2D cross_u;
uniform sampler2D cross_fine;
uniform int u_cross_nodes;
uniform int u_cross_fine;
out vec4 o0;

void main() {
    int t = self_index();
    if (t >= u_n) { o0 = vec4(0.0); return; }
    int r = t % 3;
    ivec4 h = ldi(cross_i, u_cross_nodes + t / 3);
    vec3 s = vec3(0.0);
    for (int u = h.y; u < h.z; ++u) {
        int code = ldi(cross_i, h.w + (u >> 2))[u & 3];
        if (u_cross_fine != 0) {
            s += ld(cross_fine, 3 * code + r).xyz;
            continue;
        }
        int e = code >> 2, m = code & 3;
        vec4 uk = ld(cross_u, e);
        if (uk.w > 0.0) s += (uk.w * uk[r]) * ld(cross_u, (e & ~3) + (((e & 3) + m) & 3)).xyz;
    }
    o0 = vec4(s, 0.0);
}
