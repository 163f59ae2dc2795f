// Per particle, after the solve (core/step.c): v += dv, x = xb + he v (backward Euler: xb = x,
// he = h; BDF2 and TR-BDF2: core/bdf2.h); a fully pinned particle is snapped onto its target
// t1 = from + alpha1 (target - from) with v = (t1 - xb) / he. Outputs: o0 = x, o1 = v.
uniform sampler2D xb;         // the base position (backward Euler: the substep's start)
uniform sampler2D v;
uniform sampler2D dv;
uniform isampler2D pin_map;   // per particle: its pin (-1: none)
uniform sampler2D pin_from;   // per pin: target at the frame start
uniform sampler2D pin_target; // target at the frame end
uniform sampler2D pin_axis;   // free axis (zero: fully pinned)
uniform float u_he;
uniform float u_alpha1;
uniform int u_n_pins;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 x0 = ld(xb, i).xyz;
    vec3 vn = ld(v, i).xyz + ld(dv, i).xyz;
    vec3 xn = x0 + u_he * vn;
    if (u_n_pins > 0) {
        int k = ldi(pin_map, i).x;
        if (k >= 0 && ld(pin_axis, k).xyz == vec3(0.0)) {
            vec3 from = ld(pin_from, k).xyz, to = ld(pin_target, k).xyz;
            vec3 t1v = from + u_alpha1 * (to - from);
            vn = (t1v - x0) / u_he;
            xn = t1v;
        }
    }
    o0 = vec4(xn, 0.0);
    o1 = vec4(vn, 0.0);
}
