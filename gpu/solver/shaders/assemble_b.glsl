// Per particle i (core/assemble.c by rows): the external force m_i g (+ a third of the air force
// of each incident triangle), the spring forces f_total = f_ext + sum sign f_s, and the right-hand
// side b_i = h (f_total + h sum sign w_s) + m_i mom_i, sign = +1 where i is the spring's end a,
// h the system's step (bdf2.h he) and mom the integrator's momentum term (bdf2.h): none
// (u_mom 0), read (1), or TR-BDF2's stage 1, mom = h f_total / m (2; 0 for a zero mass).
// Outputs: o0 = b, o1 = f_total, o2 = the external force (Newton's line search), o3 = mom (u_mom 2).
uniform sampler2D mass;       // (m, 1/m)
uniform isampler2D rows;      // (spring start, end, triangle start, end)
uniform isampler2D row_entry; // per row entry: (spring, sign, other particle, block)
uniform sampler2D spring_f;   // springs.glsl o0: (f, J00)
uniform sampler2D spring_w;   // springs.glsl o1: (w, J11)
uniform isampler2D row_tri;   // per row entry: triangle
uniform sampler2D tri_air;    // per triangle: its air force (air.glsl)
uniform sampler2D mom;        // per particle: the momentum term (u_mom 1)
uniform int u_mom;
uniform float u_h;
uniform vec3 u_gravity;
uniform int u_use_air;
out vec4 o0;
out vec4 o1;
out vec4 o2;
out vec4 o3;

void main() {
    int i = self_index();
    o3 = vec4(0.0);
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); o2 = vec4(0.0); return; }
    float m = ld(mass, i).x;
    ivec4 rr = ldi(rows, i);
    vec3 f = m * u_gravity;
    if (u_use_air != 0) {
        vec3 acc = vec3(0.0);
        for (int k = rr.z; k < rr.w; ++k) acc += ld(tri_air, ldi(row_tri, k).x).xyz;
        f += acc * (1.0 / 3.0);
    }
    o2 = vec4(f, 0.0);
    vec3 kv = vec3(0.0);
    for (int k = rr.x; k < rr.y; ++k) {
        ivec4 e = ldi(row_entry, k);
        float sg = float(e.y);
        f += sg * ld(spring_f, e.x).xyz;
        kv += sg * ld(spring_w, e.x).xyz;
    }
    vec3 b = u_h * (f + u_h * kv);
    if (u_mom == 1) b += m * ld(mom, i).xyz;
    if (u_mom == 2) {
        vec3 mi = m > 0.0 ? (u_h / m) * f : vec3(0.0);
        o3 = vec4(mi, 0.0);
        b += m * mi;
    }
    o0 = vec4(b, 0.0);
    o1 = vec4(f, 0.0);
}
