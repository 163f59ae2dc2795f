// Per particle: the area-weighted normal, sum over its triangles of (x_b - x_a) x (x_c - x_a),
// normalised (zero where the sum is zero), as plugin/cloth_output.c computes it.
uniform sampler2D x;
uniform isampler2D rows;    // (spring start, end, triangle start, end)
uniform isampler2D row_tri; // per row entry: triangle
uniform isampler2D tri;     // (a, b, c, -)
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    ivec4 rr = ldi(rows, i);
    vec3 n = vec3(0.0);
    for (int k = rr.z; k < rr.w; ++k) {
        ivec4 abc = ldi(tri, ldi(row_tri, k).x);
        vec3 xa = ld(x, abc.x).xyz;
        n += cross(ld(x, abc.y).xyz - xa, ld(x, abc.z).xyz - xa);
    }
    float l = length(n);
    o0 = vec4(l > 0.0 ? n / l : vec3(0.0), 0.0);
}
