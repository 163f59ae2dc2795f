// Per host vertex, in the host's order: its particle's position and normal (welded twins read
// the same particle), in world space or in object space (u_to_object: p' = (R^-1 (p - t)) / scale
// with u_inv = R^-1 / scale, normals by R^-1 renormalised). A host vertex no polygon uses has no
// particle: its rest position moves rigidly with the object (u_object: world = R p + t; in object
// space it is the rest position / scale), with a zero normal.
uniform sampler2D t0;   // x (particles)
uniform sampler2D t1;   // particle normals
uniform isampler2D t2;  // particle of each host vertex (-1: unused)
uniform sampler2D t3;   // host rest positions (object space, m)
uniform int u_to_object;
uniform mat3 u_R;       // object rotation (world from object)
uniform vec3 u_t;       // object translation
uniform mat3 u_inv;     // R^-1 / unit_scale
uniform mat3 u_rinv;    // R^-1
uniform float u_inv_scale;
out vec4 o0;
out vec4 o1;

void main() {
    int h = self_index();
    if (h >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    int p = ldi(t2, h).x;
    if (p < 0) {
        vec3 r = ld(t3, h).xyz;
        o0 = vec4(u_to_object != 0 ? r * u_inv_scale : u_R * r + u_t, 0.0);
        o1 = vec4(0.0);
        return;
    }
    vec3 x = ld(t0, p).xyz, n = ld(t1, p).xyz;
    if (u_to_object != 0) {
        x = u_inv * (x - u_t);
        n = u_rinv * n;
        float l = length(n);
        n = l > 0.0 ? n / l : vec3(0.0);
    }
    o0 = vec4(x, 0.0);
    o1 = vec4(n, 0.0);
}
