// Per spring, one Jacobi strain-limiting pass (core/strain_limit.c spring_pass): a stretch spring
// (a, b) longer than L = (1 + limit) rest gets the correction c u (u from a to b) that brings it
// back to L, each end moving in proportion to its inverse mass restricted to its free directions
// (w = inv_mass u^T S u; pinned: 0); skipped when neither end can move along u. Other springs: 0.
// Output: o0 = (c u, -).
uniform sampler2D x;
uniform isampler2D spring;     // (a, b, type, -)
uniform sampler2D spring_rest; // (rest length, stiffness weight w)
uniform sampler2D mass;        // (m, 1/m)
uniform sampler2D S0;
uniform sampler2D S1;
uniform float u_limit;
out vec4 o0;

float eff_w(int i, vec3 u, out float w) {
    vec4 s1 = ld(S1, i);
    w = s1.z == 3.0 ? 0.0 : ld(mass, i).y;
    if (s1.z == 0.0 || w == 0.0) return w;
    return w * dot(u, filter_S(ld(S0, i), s1) * u);
}

void main() {
    int s = self_index();
    o0 = vec4(0.0);
    if (s >= u_n) return;
    ivec4 sp = ldi(spring, s);
    if (sp.z != 0) return;
    float rest = ld(spring_rest, s).r;
    vec3 d = ld(x, sp.y).xyz - ld(x, sp.x).xyz;
    float l = length(d);
    float L = (1.0 + u_limit) * rest;
    if (!(l > L)) return;
    vec3 u = d / l;
    float wa, wb;
    float ea = eff_w(sp.x, u, wa), eb = eff_w(sp.y, u, wb);
    if (wa + wb == 0.0) return;
    float wsum = ea + eb;
    if (!(wsum > 1e-12 * (wa + wb))) return;
    o0 = vec4(u * ((l - L) / wsum), 0.0);
}
