// Per particle, its part of the change of the incremental potential between the iterates wa and
// wb of a substep (core/newton.c wc_newton_potential; h the system's step):
// 1/2 m (|wb - mom|^2 - |wa - mom|^2) - f_ext . h (wb - wa), since x(w) - x_n = xb - x_n +
// h (v_n + w); with TR-BDF2's implicit air (u_air) also h/2 (wb.L wb - wa.L wa), and once the air
// was refreshed at wa (u_air_at_wa, core/newton.c refresh_air) f_ext there holds L wa as well;
// with kinetic friction's frozen terms (u_friction) 1/2 (wb.Fa wb - wa.Fa wa) - Fb . (wb - wa). The
// difference is summed rather than each potential, so that float keeps its digits.
// Output: o0 = (the change, -, -, -).
uniform sampler2D wa;
uniform sampler2D wb;
uniform sampler2D mass;         // (m, 1/m)
uniform sampler2D fext;         // assemble_b.glsl o2: m g + the air's share, frozen at the start
uniform sampler2D mom;          // the integrator's momentum term (zeros for backward Euler)
uniform sampler2D air_lo;       // the lumped drag Jacobian L (air_lump.glsl)
uniform sampler2D air_hi;
uniform sampler2D fric_lo;      // friction's Fa (lo, hi) and Fb (newton_friction.glsl)
uniform sampler2D fric_hi;
uniform sampler2D fric_b;
uniform int u_air;
uniform int u_friction;
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
    if (u_friction != 0) {
        mat3 F = sym(ld(fric_lo, i), ld(fric_hi, i).xy);
        change += 0.5 * dot(b - a, F * (b + a)) - dot(ld(fric_b, i).xyz, b - a);
    }
    o0 = vec4(change - u_h * dot(f, b - a), 0.0, 0.0, 0.0);
}
