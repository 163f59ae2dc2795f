// Per triangle: wind and drag (core/forces.c air_triangle): with unit normal n, area A and the
// relative air velocity u = wind - mean(v_a, v_b, v_c):
//   f = A (normal_drag (u.n) n + tangent_drag (u - (u.n) n)),  shared equally by the corners.
uniform sampler2D x;
uniform sampler2D v;
uniform isampler2D tri; // (a, b, c, -)
uniform vec3 u_wind;
uniform vec2 u_drag;    // (normal, tangent)
out vec4 o0;

void main() {
    int t = self_index();
    if (t >= u_n) { o0 = vec4(0.0); return; }
    ivec4 abc = ldi(tri, t);
    vec3 xa = ld(x, abc.x).xyz, xb = ld(x, abc.y).xyz, xc = ld(x, abc.z).xyz;
    vec3 N = cross(xb - xa, xc - xa);
    float twice_area = length(N);
    if (!(twice_area > 0.0)) { o0 = vec4(0.0); return; }
    vec3 n = N / twice_area;
    vec3 u = u_wind - (ld(v, abc.x).xyz + ld(v, abc.y).xyz + ld(v, abc.z).xyz) * (1.0 / 3.0);
    float un = dot(u, n), area = 0.5 * twice_area;
    o0 = vec4(area * (u_drag.x * un * n + u_drag.y * (u - un * n)), 0.0);
}
