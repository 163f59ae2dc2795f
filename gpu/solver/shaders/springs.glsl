// Per spring: force on end a and the blocks of core/forces.c (Baraff & Witkin; spring_blocks.glsl,
// seams included), for a system of step h (bdf2.h he): J = h kv + h^2 kx and w = kx (v*_a - v*_b)
// with the integrator's v* (core/bdf2.h vstar; backward Euler: v).
// Outputs: o0 = (f, J00), o1 = (w, J11), o2 = (J01, J02, J12, J22).
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D vstar;       // the velocity of the h K v* term
uniform isampler2D spring;     // (a, b, type, -)
uniform sampler2D spring_rest; // (rest length, stiffness weight w)
uniform sampler2D rest;        // rest positions
uniform vec4 u_k;              // stiffness per spring type
uniform vec4 u_d;              // damping per spring type
uniform float u_h;
uniform float u_seam_scale;
uniform int u_compression_drop;
out vec4 o0;
out vec4 o1;
out vec4 o2;
#pragma weft include spring_blocks

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 sp = ldi(spring, s);
    vec3 L = ld(x, sp.x).xyz - ld(x, sp.y).xyz;
    vec3 dv = ld(v, sp.x).xyz - ld(v, sp.y).xyz;
    vec3 R = ld(rest, sp.x).xyz - ld(rest, sp.y).xyz;
    vec3 f;
    mat3 kx, kv;
    spring_blocks(sp.z, ld(spring_rest, s).xy, L, dv, R, u_k[sp.z], u_d[sp.z], u_seam_scale, u_compression_drop != 0,
                  f, kx, kv);
    mat3 J = u_h * kv + (u_h * u_h) * kx;
    o0 = vec4(f, J[0][0]);
    o1 = vec4(kx * (ld(vstar, sp.x).xyz - ld(vstar, sp.y).xyz), J[1][1]);
    o2 = vec4(J[1][0], J[2][0], J[2][1], J[2][2]);
}
