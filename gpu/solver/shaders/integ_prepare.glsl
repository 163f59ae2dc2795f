// Per particle, the integrator's vectors of a substep (core/bdf2.c wc_integ_prepare) after the
// contacts' correction, from x, v (corrected), xs (BDF2: x_n uncorrected; TR-BDF2's stage 2: x_g
// as stage 1 solved it) and the history xp, vp:
//   u_mode 0 (a BDF2 cloth's backward-Euler substep): xb = x, v* = v, mom = 0;
//   1 (BDF2): back = xs - xp, xb = x + back / 3, v* = v + back / (2 h), mom = (v - vp) / 3;
//   2 (TR-BDF2's stage 1): xb = x + he v, v* = 2 v, mom = 0 (assemble_b.glsl's u_mom 2 fills it);
//   3 (its stage 2): back = c2 (xs - xp), xb = x + back, v* = v + back / he, mom = c2 (v - vp).
// The history moves on (modes 0-2): xp' = x, vp' = v.
// Outputs: o0 = xb, o1 = v*, o2 = mom, o3 = xp', o4 = vp'.
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D xs;
uniform sampler2D xp;
uniform sampler2D vp;
uniform int u_mode;
uniform float u_h;            // the substep's (stage's) length
uniform float u_he;           // the system's step
uniform float u_c2;           // TR-BDF2's c2
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;
out vec4 o4;

void main() {
    int i = self_index();
    o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); o3 = vec4(0.0); o4 = vec4(0.0);
    if (i >= u_n) return;
    vec3 xi = ld(x, i).xyz, vi = ld(v, i).xyz;
    vec3 xb = xi, vs = vi, mom = vec3(0.0);
    if (u_mode == 1) {
        vec3 back = ld(xs, i).xyz - ld(xp, i).xyz;
        xb = xi + back / 3.0;
        vs = vi + back * (1.0 / (2.0 * u_h));
        mom = (vi - ld(vp, i).xyz) / 3.0;
    } else if (u_mode == 2) {
        xb = xi + u_he * vi;
        vs = 2.0 * vi;
    } else if (u_mode == 3) {
        vec3 back = u_c2 * (ld(xs, i).xyz - ld(xp, i).xyz);
        xb = xi + back;
        vs = vi + back / u_he;
        mom = u_c2 * (vi - ld(vp, i).xyz);
    }
    o0 = vec4(xb, 0.0);
    o1 = vec4(vs, 0.0);
    o2 = vec4(mom, 0.0);
    o3 = vec4(xi, 0.0);
    o4 = vec4(vi, 0.0);
}
