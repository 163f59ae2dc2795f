// Per particle: the area-weighted normal, sum over its triangles of (x_b - x_a) x (x_c - x_a),
// normalised (zero where the sum is zero), as plugin/cloth_output.c computes it.
uniform sampler2D t0;   // x
uniform isampler2D t1;  // row ranges (spring_start, spring_end, tri_start, tri_end)
uniform isampler2D t2;  // row triangle entries (triangle)
uniform isampler2D t3;  // triangle (a, b, c, -)
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    ivec4 rr = ldi(t1, i);
    vec3 n = vec3(0.0);
    for (int k = rr.z; k < rr.w; ++k) {
        ivec4 tri = ldi(t3, ldi(t2, k).x);
        vec3 xa = ld(t0, tri.x).xyz;
        n += cross(ld(t0, tri.y).xyz - xa, ld(t0, tri.z).xyz - xa);
    }
    float l = length(n);
    o0 = vec4(l > 0.0 ? n / l : vec3(0.0), 0.0);
}
