// Per spring, Newton's system at the iterate w of a substep (core/newton.c newton_system; h the
// system's step, bdf2.h he): the elastic force and stiffness kx at x(w) = xb + h (v_n + w)
// (backward Euler: xb = x_n), the damping at v(w) = v_n + w with the substep start's directions
// (kv0 at x_n, frozen) or, refreshed (u_refresh: TR-BDF2's stages, core/newton.h), with those at
// x(w) (1), or held at x(wd) (2: TR-BDF2's stage 1 past its first system, core/newton.c "Stage 1"),
// so f = f_elastic(x(w)) + kv0 (v_a - v_b), J = h kv0 + h^2 kx(x(w)); the third output's w
// part is 0 (no h^2 kx v* term: Newton's right-hand side is -grad Phi). Same outputs as springs.glsl.
uniform sampler2D x;           // x_n
uniform sampler2D v;           // v_n
uniform sampler2D w;           // the iterate
uniform sampler2D wd;          // the iterate held directions are at (u_refresh 2)
uniform sampler2D xb;          // the integrator's base position (backward Euler: x_n)
uniform isampler2D spring;     // (a, b, type, -)
uniform sampler2D spring_rest; // (rest length, stiffness weight w)
uniform sampler2D rest;        // rest positions
uniform vec4 u_k;
uniform vec4 u_d;
uniform float u_h;
uniform float u_seam_scale;
uniform int u_compression_drop;
uniform int u_refresh;         // the damping's directions at 0: x_n, 1: x(w), 2: x(wd)
out vec4 o0;
out vec4 o1;
out vec4 o2;
#pragma weft include spring_blocks

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 sp = ldi(spring, s);
    vec2 rw = ld(spring_rest, s).xy;
    vec3 va = ld(v, sp.x).xyz + ld(w, sp.x).xyz, vb = ld(v, sp.y).xyz + ld(w, sp.y).xyz;
    vec3 L0 = ld(x, sp.x).xyz - ld(x, sp.y).xyz;
    vec3 L = ld(xb, sp.x).xyz - ld(xb, sp.y).xyz + u_h * (va - vb);
    vec3 R = ld(rest, sp.x).xyz - ld(rest, sp.y).xyz;
    vec3 Ld = L0;
    if (u_refresh == 1) Ld = L;
    else if (u_refresh == 2)
        Ld = ld(xb, sp.x).xyz - ld(xb, sp.y).xyz +
             u_h * (ld(v, sp.x).xyz + ld(wd, sp.x).xyz - ld(v, sp.y).xyz - ld(wd, sp.y).xyz);
    vec3 fd, fe;
    mat3 kx0, kv0, kx, kv;
    // the damping at x_n or x(w) (stiffness 0), the elastic part at x(w) (damping 0)
    spring_blocks(sp.z, rw, Ld, va - vb, R, 0.0, u_d[sp.z], u_seam_scale, u_compression_drop != 0, fd, kx0, kv0);
    spring_blocks(sp.z, rw, L, vec3(0.0), R, u_k[sp.z], 0.0, u_seam_scale, u_compression_drop != 0, fe, kx, kv);
    mat3 J = u_h * kv0 + (u_h * u_h) * kx;
    o0 = vec4(fe + fd, J[0][0]);
    o1 = vec4(0.0, 0.0, 0.0, J[1][1]);
    o2 = vec4(J[1][0], J[2][0], J[2][1], J[2][2]);
}
