// Per particle: the active penalty pairs' exact terms in a Newton system (pairs_newton.glsl's
// outputs) added to it, in pair order over the particle's entries: o0 = b + sum f_j w_a n,
// o1 / o2 = A_ii + sum c w_a^2 n n^T (lo, hi), which contact_diag then puts into A.
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D b;
uniform isampler2D pr_rows;  // particles: (first entry, end, -, -)
uniform isampler2D pr_entry; // entries: (pair, the particle's slot in it, the pair's particles, -)
uniform sampler2D pw;        // pairs: their weights
uniform sampler2D pnc;       // pairs: (n, c); c = 0: inactive
uniform sampler2D pf;        // pairs: (the force's factor, -, -, -)
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    int d = ldi(pblocks, i).z;
    vec3 db = vec3(0.0);
    mat3 da = mat3(0.0);
    ivec4 r = ldi(pr_rows, i);
    for (int e = r.x; e < r.y; ++e) {
        ivec4 en = ldi(pr_entry, e);
        vec4 nc = ld(pnc, en.x);
        if (!(nc.w > 0.0)) continue;
        float wa = ld(pw, en.x)[en.y];
        db += (ld(pf, en.x).x * wa) * nc.xyz;
        da += outerProduct(nc.xyz, nc.xyz) * (nc.w * wa * wa);
    }
    o0 = ld(b, i) + vec4(db, 0.0);
    o1 = ld(a_lo, d) + sym_lo(da);
    o2 = vec4(ld(a_hi, d).xy + sym_hi(da), 0.0, 0.0);
}
