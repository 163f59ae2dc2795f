// Per particle, kinetic friction's frozen terms of Newton's iterations (core/newton.c
// wc_newton_capture and friction_terms): what the contacts' friction pass and its rechecks added
// to A's diagonal block and to b. u_terms = 0 (before the friction pass): the capture,
// o0 / o1 = A_ii (lo, hi), o2 = b; u_terms = 1 (after the rechecks): the terms against the
// capture, o0 / o1 = Fa = A_ii - captured (lo, hi), o2 = Fb = b - captured. A particle friction
// left alone has the terms 0 exactly.
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D b;
uniform sampler2D cap_lo;   // the capture (read with u_terms = 1)
uniform sampler2D cap_hi;
uniform sampler2D cap_b;
uniform int u_terms;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    int dk = ldi(pblocks, i).z;
    vec4 lo = ld(a_lo, dk), bi = vec4(ld(b, i).xyz, 0.0);
    vec4 hi = vec4(ld(a_hi, dk).xy, 0.0, 0.0);
    if (u_terms != 0) {
        lo -= ld(cap_lo, i);
        hi -= ld(cap_hi, i);
        bi -= ld(cap_b, i);
    }
    o0 = lo;
    o1 = hi;
    o2 = bi;
}
