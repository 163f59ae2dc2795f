// Per particle, Newton's right-hand side at the iterate w (core/newton.c newton_system; h the
// system's step, bdf2.h he): g = -grad Phi(w) = h f_total(w) - m (w - mom), with h f_total from
// assemble_b.glsl over newton_springs.glsl's forces and mom the integrator's momentum term (0
// for backward Euler), plus kinetic friction's frozen Fb - Fa w (u_friction; newton_friction.glsl),
// minus TR-BDF2's implicit air h L w where its air stays the stage start's (u_air: a contact is
// active in the stage, core/newton.h "Refreshed"; refreshed, f_total holds the air at w itself);
// and the iterate's state x(w) = xb + h (v_n + w), v(w) = v_n + w (the
// energy guard's measure). Outputs: o0 = g, o1 = x(w), o2 = v(w).
uniform sampler2D hf;          // assemble_b.glsl o0: h f_total at w
uniform sampler2D w;
uniform sampler2D mass;        // (m, 1/m)
uniform sampler2D xb;          // the integrator's base position (backward Euler: x_n)
uniform sampler2D mom;
uniform sampler2D v;           // v_n
uniform sampler2D fric_lo;     // friction's Fa (lo, hi) and Fb, read with u_friction
uniform sampler2D fric_hi;
uniform sampler2D fric_b;
uniform sampler2D air_lo;      // TR-BDF2's lumped air Jacobian L (lo, hi), read with u_air
uniform sampler2D air_hi;
uniform float u_h;
uniform int u_friction;
uniform int u_air;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    vec3 wi = ld(w, i).xyz, vi = ld(v, i).xyz + wi;
    vec3 gi = ld(hf, i).xyz - ld(mass, i).x * (wi - ld(mom, i).xyz);
    if (u_friction != 0) gi += ld(fric_b, i).xyz - sym(ld(fric_lo, i), ld(fric_hi, i).xy) * wi;
    if (u_air != 0) gi -= u_h * (sym(ld(air_lo, i), ld(air_hi, i).xy) * wi);
    o0 = vec4(gi, 0.0);
    o1 = vec4(ld(xb, i).xyz + u_h * vi, 0.0);
    o2 = vec4(vi, 0.0);
}
