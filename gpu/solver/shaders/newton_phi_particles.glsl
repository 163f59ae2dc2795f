// Per particle, its part of the change of the incremental potential between the iterates wa and
// wb of a backward-Euler substep (core/newton.c wc_newton_potential, without friction or air
// refresh): 1/2 m (|wb|^2 - |wa|^2) - f_ext . h (wb - wa), since x(w) - x_n = h (v_n + w). The
// difference is summed rather than each potential, so that float keeps its digits.
// Output: o0 = (the change, -, -, -).
uniform sampler2D wa;
uniform sampler2D wb;
uniform sampler2D mass;         // (m, 1/m)
uniform sampler2D fext;         // assemble_b.glsl o2: m g + the air's share, frozen at the start
uniform float u_h;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 a = ld(wa, i).xyz, b = ld(wb, i).xyz;
    float m = ld(mass, i).x;
    o0 = vec4(0.5 * m * dot(b - a, b + a) - u_h * dot(ld(fext, i).xyz, b - a), 0.0, 0.0, 0.0);
}
