// Per block of A: the diagonal block of row i takes the contact passes' A_ii (per particle),
// every other block is copied.
// Outputs: o0 = A lo, o1 = A hi.
uniform isampler2D block; // (row, column, -, -)
uniform sampler2D a_lo;
uniform sampler2D a_hi;
uniform sampler2D aii_lo; // per particle: its A_ii (lo)
uniform sampler2D aii_hi; // (hi)
out vec4 o0;
out vec4 o1;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    ivec4 bl = ldi(block, k);
    if (bl.x == bl.y) { o0 = ld(aii_lo, bl.x); o1 = ld(aii_hi, bl.x); }
    else { o0 = ld(a_lo, k); o1 = ld(a_hi, k); }
}
