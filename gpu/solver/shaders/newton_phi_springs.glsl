// Per spring, its part of the change of the incremental potential between the iterates wa and wb
// (core/newton.c wc_newton_potential; h the system's step, x(w) = xb + h (v_n + w)):
// w k/2 (e(x(wb))^2 - e(x(wa))^2) with core's extension e (seams: their ramp, pulling only), and
// the damping's -h/2 (dvb.kv0 dvb - dva.kv0 dva), kv0 the damping block at x_n (frozen) or, in
// TR-BDF2's stages (u_refresh 1), at x(wa), the iterate it was refreshed at, or held at x(wd) (2); dv = v_a - v_b at
// v(w) = v_n + w. Output: o0 = (the change, -, -, -).
uniform sampler2D x;            // x_n
uniform sampler2D v;            // v_n
uniform sampler2D wa;
uniform sampler2D wb;
uniform sampler2D wd;           // the iterate held directions are at (u_refresh 2)
uniform sampler2D xb;           // the integrator's base position (backward Euler: x_n)
uniform isampler2D spring;      // (a, b, type, -)
uniform sampler2D spring_rest;  // (rest length, stiffness weight w)
uniform sampler2D rest;         // rest positions
uniform vec4 u_k;
uniform vec4 u_d;
uniform float u_h;
uniform float u_seam_scale;
uniform int u_refresh;
out vec4 o0;
#pragma weft include spring_blocks

float extension(int type, vec2 rw, float l) {
    if (type != 3) return l - rw.x;
    float r = rw.x * u_seam_scale;
    return l > r ? l - r : 0.0;
}

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); return; }
    ivec4 sp = ldi(spring, s);
    vec2 rw = ld(spring_rest, s).xy;
    vec3 v0 = ld(v, sp.x).xyz - ld(v, sp.y).xyz;
    vec3 dva = v0 + ld(wa, sp.x).xyz - ld(wa, sp.y).xyz, dvb = v0 + ld(wb, sp.x).xyz - ld(wb, sp.y).xyz;
    vec3 L0 = ld(x, sp.x).xyz - ld(x, sp.y).xyz;
    vec3 Lb = ld(xb, sp.x).xyz - ld(xb, sp.y).xyz;
    vec3 R = ld(rest, sp.x).xyz - ld(rest, sp.y).xyz;
    vec3 Ld = L0;
    if (u_refresh == 1) Ld = Lb + u_h * dva;
    else if (u_refresh == 2) Ld = Lb + u_h * (v0 + ld(wd, sp.x).xyz - ld(wd, sp.y).xyz);
    vec3 f;
    mat3 kx0, kv0;
    spring_blocks(sp.z, rw, Ld, vec3(0.0), R, 0.0, u_d[sp.z], u_seam_scale, true, f,
                  kx0, kv0);
    float ea = extension(sp.z, rw, length(Lb + u_h * dva)), eb = extension(sp.z, rw, length(Lb + u_h * dvb));
    float elastic = 0.5 * u_k[sp.z] * rw.y * (eb - ea) * (eb + ea);
    float damping = -0.5 * u_h * (dot(dvb, kv0 * dvb) - dot(dva, kv0 * dva));
    o0 = vec4(elastic + damping, 0.0, 0.0, 0.0);
}
