// The penalty pairs' off-diagonal blocks in a row's product (wg_pairs.h, core/coupling.h): row i
// of the sum over the active pairs of c w_a w_b n n^T (a != b) times x, added after the pattern's
// product by every pass that multiplies by A in a solve (spmv, spmv_groups, residual,
// jacobi_sweep; an include of theirs, not a pass). Serial over the row's entries, in pair order.
uniform isampler2D pr_rows;  // particles: (first entry, end, -, -)
uniform isampler2D pr_entry; // entries: (pair, the particle's slot in it, the pair's particles, -)
uniform isampler2D pr_p;     // pairs: their particles
uniform sampler2D pr_w;      // pairs: their weights
uniform sampler2D pr_nc;     // pairs: (n, c); c = 0: inactive
uniform int u_pairs;         // 0: no pairs in the system (nothing is read)

vec3 pairs_row(sampler2D xs, int i) {
    vec3 y = vec3(0.0);
    if (u_pairs == 0) return y;
    ivec4 r = ldi(pr_rows, i);
    for (int e = r.x; e < r.y; ++e) {
        ivec4 en = ldi(pr_entry, e);
        vec4 nc = ld(pr_nc, en.x);
        if (!(nc.w > 0.0)) continue;
        ivec4 p = ldi(pr_p, en.x);
        vec4 w = ld(pr_w, en.x);
        float s = 0.0;
        for (int b = 0; b < en.z; ++b)
            if (b != en.y) s += w[b] * dot(nc.xyz, ld(xs, p[b]).xyz);
        y += (nc.w * w[en.y] * s) * nc.xyz;
    }
    return y;
}
