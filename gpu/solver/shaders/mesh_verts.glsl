// A resident body's vertices at a substep (core/mesh_collider.c wc_mesh_collider_substep, in
// float): three texels a vertex, its position at the substep's start (fraction u_a0 of the
// frame), at its end (u_a1; a fraction of 1 lands exactly on the frame's end) and its velocity
// (end - start) / u_h (0 when u_h is 0).
uniform sampler2D body_from;   // the frame's start, 1 texel a vertex
uniform sampler2D body_to;     // the frame's end
uniform float u_a0, u_a1, u_h;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    int v = i / 3, c = i - 3 * v;
    vec3 f = ld(body_from, v).xyz, t = ld(body_to, v).xyz, d = t - f;
    vec3 xa = u_a0 >= 1.0 ? t : f + u_a0 * d;
    vec3 xb = u_a1 >= 1.0 ? t : f + u_a1 * d;
    vec3 r = c == 0 ? xa : c == 1 ? xb : (u_h > 0.0 ? (xb - xa) / u_h : vec3(0.0));
    o0 = vec4(r, 0.0);
}
