// Per particle: the lumped (row-sum) Jacobian L_i of the air drag over its triangles (core/forces.c
// wc_air_lumped): sum over triangle t of area_t / 3 ((normal - tangent) n n^T + tangent I), TR-BDF2's
// implicit drag (core/bdf2.h "Air drag"). Outputs: o0 = (L00, L01, L02, L11), o1 = (L12, L22, -, -).
uniform sampler2D x;
uniform isampler2D rows;      // (spring start, end, triangle start, end)
uniform isampler2D row_tri;   // per row entry: triangle
uniform isampler2D tri;       // (a, b, c, -)
uniform vec2 u_drag;          // (normal, tangent)
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    o0 = vec4(0.0); o1 = vec4(0.0);
    if (i >= u_n) return;
    ivec4 rr = ldi(rows, i);
    mat3 L = mat3(0.0);
    for (int k = rr.z; k < rr.w; ++k) {
        ivec4 abc = ldi(tri, ldi(row_tri, k).x);
        vec3 xa = ld(x, abc.x).xyz;
        vec3 N = cross(ld(x, abc.y).xyz - xa, ld(x, abc.z).xyz - xa);
        float twice_area = length(N);
        if (!(twice_area > 0.0)) continue;
        vec3 n = N / twice_area;
        float w = 0.5 * twice_area / 3.0;
        L += w * ((u_drag.x - u_drag.y) * outerProduct(n, n) + u_drag.y * mat3(1.0));
    }
    o0 = sym_lo(L);
    o1 = vec4(sym_hi(L), 0.0, 0.0);
}
