// Per block of A: the diagonal block of row i takes the contact passes' A_ii (per particle),
// every other block is copied.
// Outputs: o0 = A lo, o1 = A hi.
uniform isampler2D t0;  // block (row, column, -, -)
uniform sampler2D t1;   // A lo
uniform sampler2D t2;   // A hi
uniform sampler2D t3;   // A_ii lo per particle
uniform sampler2D t4;   // A_ii hi per particle
out vec4 o0;
out vec4 o1;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    ivec4 bl = ldi(t0, k);
    if (bl.x == bl.y) { o0 = ld(t3, bl.x); o1 = ld(t4, bl.x); }
    else { o0 = ld(t1, k); o1 = ld(t2, k); }
}
