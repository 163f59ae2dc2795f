// One spring's force on its end a and its blocks (core/forces.c; an include, not a pass), from
// L = x_a - x_b, dv = v_a - v_b, R = rest_a - rest_b (the direction of (nearly) coincident ends),
// rw = (rest length, stiffness weight w), its type's k and d, the host pairs' ramp seam_scale and
// the compression mode (drop: the compressed spring's negative geometric term clamped at 0):
//   f_a = -(k (l - rest) + d dv.u) u,  kx = -k ((1 - c) u u^T + c I),  kv = -d u u^T,
// u = L / l, c = 1 - rest / l. A seam spring (type 3, core/sew.h) has stiffness k w and damping
// d w (w may be negative), rest r = rest x seam_scale and only pulls: isotropic damping
// -d w dv; f_a -= k w L, kx = -k w I once r = 0; else the spring above with rest r while l > r,
// no stiffness while slack (core/forces.c seam_blocks).
void spring_blocks(int type, vec2 rw, vec3 L, vec3 dv, vec3 R, float k, float d, float seam_scale, bool drop,
                   out vec3 f, out mat3 kx, out mat3 kv) {
    float l = length(L);
    if (type == 3) {
        float r = rw.x * seam_scale, kw = k * rw.y, dw = d * rw.y;
        kv = -dw * mat3(1.0);
        f = -dw * dv;
        if (r <= 0.0) {
            f -= kw * L;
            kx = -kw * mat3(1.0);
            return;
        }
        kx = mat3(0.0);
        if (!(l > r)) return;
        vec3 us = L / l;
        float cs = 1.0 - r / l;
        f -= kw * (l - r) * us;
        kx = -kw * ((1.0 - cs) * outerProduct(us, us) + cs * mat3(1.0));
        return;
    }
    float rest_len = rw.x;
    vec3 u = vec3(0.0);
    float c = 0.0;
    if (l > 0.0 && l >= 1e-12 * rest_len) {
        u = L / l;
        c = 1.0 - rest_len / l;
        if (drop && c < 0.0) c = 0.0;
    } else {
        float r = length(R);
        if (r > 0.0) u = R / r;
    }
    f = -(k * (l - rest_len) + d * dot(dv, u)) * u;
    mat3 uu = outerProduct(u, u);
    kx = -k * ((1.0 - c) * uu + c * mat3(1.0));
    kv = -d * uu;
}
