// Per pair and slot (item 4 q + k): slot k's vector of pair q's term in every level of the
// multigrid (wg_amg.h, the cross terms), u = S_p (w_k n) with p the slot's particle (the filter as
// the V-cycle's operator applies it; the unsmoothed prolongator's identity blocks carry u to each
// coarser node unchanged), and the pair's c (0 where it is inactive).
uniform isampler2D pair_p;   // pairs: their particles
uniform sampler2D pair_w;    // pairs: their weights (0 in unused slots)
uniform sampler2D pair_nc;   // pairs: (n, c)
uniform sampler2D S0;
uniform sampler2D S1;
out vec4 o0;

void main() {
    int e = self_index();
    if (e >= u_n) { o0 = vec4(0.0); return; }
    int q = e >> 2, k = e & 3;
    int p = ldi(pair_p, q)[k];
    vec4 nc = ld(pair_nc, q);
    vec3 u = filter_apply(ld(S0, p), ld(S1, p), ld(pair_w, q)[k] * nc.xyz);
    o0 = vec4(u, nc.w > 0.0 ? nc.w : 0.0);
}
