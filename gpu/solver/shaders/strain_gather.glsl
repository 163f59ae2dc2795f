// Per particle (core/strain_limit.c gather): move by the average of the corrections of its
// stretch springs that were too long, times its inverse mass, projected by S; v changes by the
// same amount / h. End a moves along +c u, end b along -c u.
// Outputs: o0 = x, o1 = v.
uniform sampler2D t0;   // x
uniform sampler2D t1;   // v
uniform isampler2D t2;  // row ranges (spring_start, spring_end, tri_start, tri_end)
uniform isampler2D t3;  // row spring entries (spring, sign, other, block)
uniform sampler2D t4;   // corrections (strain_springs)
uniform sampler2D t5;   // mass (m, 1/m)
uniform sampler2D t6;   // S0
uniform sampler2D t7;   // S1
uniform isampler2D t8;  // spring (a, b, type, -)
uniform float u_h;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 x = ld(t0, i).xyz, v = ld(t1, i).xyz;
    o0 = vec4(x, 0.0);
    o1 = vec4(v, 0.0);
    vec4 s1 = ld(t7, i);
    float w = s1.z == 3.0 ? 0.0 : ld(t5, i).y;
    if (w == 0.0) return;
    ivec4 rr = ldi(t2, i);
    vec3 sum = vec3(0.0);
    int cnt = 0;
    for (int k = rr.x; k < rr.y; ++k) {
        ivec4 e = ldi(t3, k);
        if (ldi(t8, e.x).z != 0) continue;
        vec3 c = ld(t4, e.x).xyz;
        if (c == vec3(0.0)) continue;
        sum += float(e.y) * c;
        ++cnt;
    }
    if (cnt == 0) return;
    vec3 delta = filter_apply(ld(t6, i), s1, sum * (w / float(cnt)));
    o0 = vec4(x + delta, 0.0);
    if (u_h > 0.0) o1 = vec4(v + delta / u_h, 0.0);
}
