// Per particle: the penalty pairs' terms (wg_pairs.h) added to the system, for the particles in
// [u_lo, u_hi] (the span the host uploaded; the others are copied): o0 = b + db, o1 = f_total +
// df (u_f; else a copy), o2 / o3 = A_ii + dA_ii (lo, hi), which contact_diag then puts into A.
uniform isampler2D pblocks; // (block row start, end, diagonal block, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D b;
uniform sampler2D ftot;
uniform sampler2D db;       // per particle: the additions (xyz)
uniform sampler2D df;
uniform sampler2D da_lo;    // (symmetric block lo, hi)
uniform sampler2D da_hi;
uniform int u_lo;
uniform int u_hi;
uniform int u_f;
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); return; }
    int d = ldi(pblocks, i).z;
    o0 = ld(b, i);
    o1 = ld(ftot, i);
    o2 = ld(a_lo, d);
    o3 = ld(a_hi, d);
    if (i < u_lo || i > u_hi) return;
    o0.xyz += ld(db, i).xyz;
    if (u_f != 0) o1.xyz += ld(df, i).xyz;
    o2 += ld(da_lo, i);
    o3.xy += ld(da_hi, i).xy;
}
