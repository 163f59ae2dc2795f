// Per particle: the constraint filter of the pins for a substep (or TR-BDF2 stage) ending at frame
// fraction alpha1 (core/step.c apply_pins): free S = I, z = 0; a pin takes the particle exactly
// to its target, t1 = from + alpha1 (target - from): want = (t1 - base) / he - v, with the
// integrator's base position before the contacts (core/bdf2.c wc_integ_base)
// base = x + u_base_x (x - xp) + u_base_v v (backward Euler: x, he = h); fully pinned:
// S = 0, z = want (ndof 3); a line pin with unit axis d: S = d d^T, z = want - (want.d) d (ndof 2).
// Outputs: o0 = S0, o1 = S1 (s12, s22, ndof, -), o2 = z.
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D xp;         // BDF2's x_{n-1}, TR-BDF2's substep start (stage 2); x where unused
uniform isampler2D pin_map;   // per particle: its pin (-1: none)
uniform sampler2D pin_from;   // per pin: target at the frame start
uniform sampler2D pin_target; // target at the frame end
uniform sampler2D pin_axis;   // free axis (zero: fully pinned)
uniform float u_he;          // the system's step (bdf2.h he)
uniform float u_base_x;      // 1/3 (BDF2), c2 (TR-BDF2's stage 2), else 0
uniform float u_base_v;      // he (TR-BDF2's stage 1), else 0
uniform float u_alpha1;
uniform int u_n_pins;
out vec4 o0;
out vec4 o1;
out vec4 o2;

void main() {
    int i = self_index();
    o0 = vec4(1.0, 0.0, 0.0, 1.0); o1 = vec4(0.0, 1.0, 0.0, 0.0); o2 = vec4(0.0);
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    if (u_n_pins == 0) return;
    int k = ldi(pin_map, i).x;
    if (k < 0) return;
    vec3 from = ld(pin_from, k).xyz, to = ld(pin_target, k).xyz, axis = ld(pin_axis, k).xyz;
    vec3 t1v = from + u_alpha1 * (to - from);
    vec3 xi = ld(x, i).xyz, vi = ld(v, i).xyz;
    vec3 base = xi + u_base_x * (xi - ld(xp, i).xyz) + u_base_v * vi;
    vec3 want = (t1v - base) / u_he - vi;
    if (axis == vec3(0.0)) {
        o0 = vec4(0.0); o1 = vec4(0.0, 0.0, 3.0, 0.0); o2 = vec4(want, 0.0);
    } else {
        mat3 S = outerProduct(axis, axis);
        o0 = sym_lo(S); o1 = vec4(sym_hi(S), 2.0, 0.0);
        o2 = vec4(want - dot(want, axis) * axis, 0.0);
    }
}
