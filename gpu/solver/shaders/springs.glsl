// Per spring: force on end a and the blocks of core/forces.c (Baraff & Witkin), for a substep
// of length h. Spring s between a and b, L = x_a - x_b, l = |L|, u = L / l, c = 1 - rest / l
// (clamped at 0 under compression when u_compression_drop):
//   f_a = -(k (l - rest) + d (v_a - v_b).u) u
//   kx = -k ((1 - c) u u^T + c I),  kv = -d u u^T,  J = h kv + h^2 kx,  w = kx (v_a - v_b)
// A seam spring (type 3, core/sew.h) has stiffness k w and damping d w (w may be negative), rest
// r = rest x u_seam_scale (the host pairs' ramp) and only pulls: isotropic damping -d w (v_a - v_b);
// f_a -= k w L, kx = -k w I once r = 0; else the spring above with rest r while l > r, no
// stiffness while slack (core/forces.c seam_blocks).
// Outputs: o0 = (f, J00), o1 = (w, J11), o2 = (J01, J02, J12, J22).
uniform sampler2D x;
uniform sampler2D v;
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

// A seam spring's force on a and its blocks kx, kv.
void seam(vec3 L, vec3 dv, float r, float kw, float dw, out vec3 f, out mat3 kx, out mat3 kv) {
    kv = -dw * mat3(1.0);
    f = -dw * dv;
    if (r <= 0.0) {
        f -= kw * L;
        kx = -kw * mat3(1.0);
        return;
    }
    kx = mat3(0.0);
    float l = length(L);
    if (!(l > r)) return;
    vec3 u = L / l;
    float c = 1.0 - r / l;
    f -= kw * (l - r) * u;
    kx = -kw * ((1.0 - c) * outerProduct(u, u) + c * mat3(1.0));
}

void main() {
    int s = self_index();
    if (s >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    ivec4 sp = ldi(spring, s);
    vec2 rw = ld(spring_rest, s).xy;
    float rest_len = rw.x;
    vec3 xa = ld(x, sp.x).xyz, xb = ld(x, sp.y).xyz;
    vec3 dv = ld(v, sp.x).xyz - ld(v, sp.y).xyz;
    vec3 L = xa - xb;
    if (sp.z == 3) {
        vec3 f;
        mat3 kx, kv;
        seam(L, dv, rest_len * u_seam_scale, u_k[3] * rw.y, u_d[3] * rw.y, f, kx, kv);
        mat3 J = u_h * kv + (u_h * u_h) * kx;
        o0 = vec4(f, J[0][0]);
        o1 = vec4(kx * dv, J[1][1]);
        o2 = vec4(J[1][0], J[2][0], J[2][1], J[2][2]);
        return;
    }
    float l = length(L);
    vec3 u = vec3(0.0);
    float c = 0.0;
    if (l > 0.0 && l >= 1e-12 * rest_len) {
        u = L / l;
        c = 1.0 - rest_len / l;
        if (u_compression_drop != 0 && c < 0.0) c = 0.0;
    } else {
        vec3 R = ld(rest, sp.x).xyz - ld(rest, sp.y).xyz;
        float r = length(R);
        if (r > 0.0) u = R / r;
    }
    float k = u_k[sp.z], d = u_d[sp.z];
    float fs = k * (l - rest_len) + d * dot(dv, u);
    vec3 f = -fs * u;
    mat3 uu = outerProduct(u, u);
    mat3 kx = -k * ((1.0 - c) * uu + c * mat3(1.0));
    mat3 J = (u_h * -d) * uu + (u_h * u_h) * kx;
    vec3 w = kx * dv;
    o0 = vec4(f, J[0][0]);
    o1 = vec4(w, J[1][1]);
    o2 = vec4(J[1][0], J[2][0], J[2][1], J[2][2]);
}
