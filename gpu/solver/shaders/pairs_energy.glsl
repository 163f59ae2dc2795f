// Per particle: base plus the penalty pairs' part of the incremental potential's change between
// the iterates wa and wb (core's wc_penalty_pairs_energy, k/2 min(g, 0)^2 a pair, at x(w) =
// xb + h (v + w)), each pair counted at its first particle's entry: with the gap at wa,
// ga = gk.x + h (gk.y + n . sum w_a wa_a), and the change d = h n . sum w_a (wb_a - wa_a),
// gb = ga + d; both negative: k/2 d (ga + gb), so that float keeps the difference's digits.
// Output: o0 = base + (the pairs' change, 0, 0, 0).
uniform isampler2D pr_rows;  // particles: (first entry, end, -, -)
uniform isampler2D pr_entry; // entries: (pair, the particle's slot in it, the pair's particles, -)
uniform isampler2D pp;       // pairs: their particles
uniform sampler2D pw;        // pairs: their weights
uniform sampler2D pnc;       // pairs: (n, c)
uniform sampler2D pgk;       // pairs: (n . sum w xb - off, n . sum w v, k, count)
uniform sampler2D wa;
uniform sampler2D wb;
uniform sampler2D base;      // particles: the potential's other terms (newton_phi_particles.glsl)
uniform float u_h;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    float e = 0.0;
    ivec4 r = ldi(pr_rows, i);
    for (int k = r.x; k < r.y; ++k) {
        ivec4 en = ldi(pr_entry, k);
        if (en.y != 0) continue;
        ivec4 p = ldi(pp, en.x);
        vec4 wt = ld(pw, en.x), gk = ld(pgk, en.x);
        vec3 n = ld(pnc, en.x).xyz;
        float sa = 0.0, sd = 0.0;
        for (int a = 0; a < en.z; ++a) {
            vec3 xa = ld(wa, p[a]).xyz;
            sa += wt[a] * dot(n, xa);
            sd += wt[a] * dot(n, ld(wb, p[a]).xyz - xa);
        }
        float ga = gk.x + u_h * (gk.y + sa), d = u_h * sd, gb = ga + d;
        if (ga < 0.0 && gb < 0.0) e += 0.5 * gk.z * d * (ga + gb);
        else e += 0.5 * gk.z * (min(gb, 0.0) * min(gb, 0.0) - min(ga, 0.0) * min(ga, 0.0));
    }
    o0 = ld(base, i) + vec4(e, 0.0, 0.0, 0.0);
}
