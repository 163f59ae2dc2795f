// Per particle (core/strain_limit.c gather): move by the average of the corrections of its
// stretch springs that were too long, times its inverse mass, projected by S; v changes by the
// same amount / h. End a moves along +c u, end b along -c u.
// Outputs: o0 = x, o1 = v.
uniform sampler2D x;
uniform sampler2D v;
uniform isampler2D rows;      // (spring start, end, triangle start, end)
uniform isampler2D row_entry; // per row entry: (spring, sign, other particle, block)
uniform sampler2D corr;       // per spring: its correction (strain_springs.glsl)
uniform sampler2D mass;       // (m, 1/m)
uniform sampler2D S0;
uniform sampler2D S1;
uniform isampler2D spring;    // (a, b, type, -)
uniform float u_h;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 xi = ld(x, i).xyz, vi = ld(v, i).xyz;
    o0 = vec4(xi, 0.0);
    o1 = vec4(vi, 0.0);
    vec4 s1 = ld(S1, i);
    float w = s1.z == 3.0 ? 0.0 : ld(mass, i).y;
    if (w == 0.0) return;
    ivec4 rr = ldi(rows, i);
    vec3 sum = vec3(0.0);
    int cnt = 0;
    for (int k = rr.x; k < rr.y; ++k) {
        ivec4 e = ldi(row_entry, k);
        if (ldi(spring, e.x).z != 0) continue;
        vec3 c = ld(corr, e.x).xyz;
        if (c == vec3(0.0)) continue;
        sum += float(e.y) * c;
        ++cnt;
    }
    if (cnt == 0) return;
    vec3 delta = filter_apply(ld(S0, i), s1, sum * (w / float(cnt)));
    o0 = vec4(xi + delta, 0.0);
    if (u_h > 0.0) o1 = vec4(vi + delta / u_h, 0.0);
}
