// Per particle, its part of the change of the incremental potential between the iterates wa and
// wb of a substep (core/newton.c wc_newton_potential, without friction; h the system's step):
// 1/2 m (|wb - mom|^2 - |wa - mom|^2) - f_ext . h (wb - wa), since x(w) - x_n = xb - x_n +
// h (v_n + w); with TR-BDF2's implicit air (u_air) also h/2 (wb.L wb - wa.L wa), and once the air
// was refreshed at wa (u_air_at_wa, core/newton.c refresh_air) f_ext there holds L wa as well. The
// difference is summed rather than each potential, so that float keeps its digits.
// Output: o0 = (the change, -, -, -).
uniform sampler2D wa;
uniform sampler2D wb;
uniform sampler2D mass;         // (m, 1/m)
uniform sampler2D fext;         // assemble_b.glsl o2: m g + the air's share, frozen at the start
uniform sampler2D mom;          // the integrator's momentum term (zeros for backward Euler)
uniform sampler2D air_lo;       // the lumped drag Jacobian L (air_lump.glsl)
uniform sampler2D air_hi;
uniform int u_air;
uniform int u_air_at_wa;
uniform float u_h;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 a = ld(wa, i).xyz, b = ld(wb, i).xyz;
    float m = ld(mass, i).x;
    vec3 f = ld(fext, i).xyz;
    float change = 0.5 * m * dot(b - a, b + a - 2.0 * ld(mom, i).xyz);
    if (u_air != 0) {
        mat3 L = sym(ld(air_lo, i), ld(air_hi, i).xy);
        if (u_air_at_wa != 0) f += L * a;
        change += 0.5 * u_h * (dot(b, L * b) - dot(a, L * a));
    }
    o0 = vec4(change - u_h * dot(f, b - a), 0.0, 0.0, 0.0);
}
