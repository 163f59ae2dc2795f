// Per block of a coarse level: the Galerkin product of unsmoothed aggregation, the sum of the
// finer level's blocks (i, j) with aggregate(i), aggregate(j) its row and column (P = P_tent of
// translations: identity blocks), listed per coarse block when the hierarchy was built.
#pragma weft include amg_blocks
uniform isampler2D t0;  // this level's blocks: (list start, end, -, -)
uniform isampler2D t1;  // list: (finer block, -, -, -)
uniform sampler2D t2;   // finer level's blocks, row 0
uniform sampler2D t3;   // row 1
uniform sampler2D t4;   // row 2
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int k = self_index();
    if (k >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 r = ldi(t0, k);
    vec3 s0 = vec3(0.0), s1 = vec3(0.0), s2 = vec3(0.0);
    for (int e = r.x; e < r.y; ++e) {
        int f = ldi(t1, e).x;
        s0 += ld(t2, f).xyz;
        s1 += ld(t3, f).xyz;
        s2 += ld(t4, f).xyz;
    }
    o0 = vec4(s0, 0.0);
    o1 = vec4(s1, 0.0);
    o2 = vec4(s2, 0.0);
}
