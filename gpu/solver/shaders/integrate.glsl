// Per particle, after the solve (core/step.c): v += dv, x += h v; a fully pinned particle is
// snapped onto its target t1 = from + alpha1 (target - from) with v = (t1 - x0) / h.
// Outputs: o0 = x, o1 = v.
uniform sampler2D t0;   // x0
uniform sampler2D t1;   // v
uniform sampler2D t2;   // dv
uniform isampler2D t3;  // pin of each particle (-1: none)
uniform sampler2D t4;   // pin from
uniform sampler2D t5;   // pin target
uniform sampler2D t6;   // pin free axis
uniform float u_h;
uniform float u_alpha1;
uniform int u_n_pins;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 x0 = ld(t0, i).xyz;
    vec3 v = ld(t1, i).xyz + ld(t2, i).xyz;
    vec3 x = x0 + u_h * v;
    if (u_n_pins > 0) {
        int k = ldi(t3, i).x;
        if (k >= 0 && ld(t6, k).xyz == vec3(0.0)) {
            vec3 from = ld(t4, k).xyz, to = ld(t5, k).xyz;
            vec3 t1v = from + u_alpha1 * (to - from);
            v = (t1v - x0) / u_h;
            x = t1v;
        }
    }
    o0 = vec4(x, 0.0);
    o1 = vec4(v, 0.0);
}
