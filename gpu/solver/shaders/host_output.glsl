// Per host vertex, in the host's order: its particle's position and normal (welded twins read
// the same particle), in world space or in object space (u_to_object: p' = (R^-1 (p - t)) / scale
// with u_inv = R^-1 / scale, normals by R^-1 renormalised). A host vertex no polygon uses has no
// particle: its rest position moves rigidly with the object (u_object: world = R p + t; in object
// space it is the rest position / scale), with a zero normal.
uniform sampler2D x;
uniform sampler2D normal;    // per particle (normals.glsl)
uniform isampler2D host_map; // per host vertex: its particle (-1: unused)
uniform sampler2D host_rest; // per host vertex: rest position (object space, m)
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
    int p = ldi(host_map, h).x;
    if (p < 0) {
        vec3 r = ld(host_rest, h).xyz;
        o0 = vec4(u_to_object != 0 ? r * u_inv_scale : u_R * r + u_t, 0.0);
        o1 = vec4(0.0);
        return;
    }
    vec3 xh = ld(x, p).xyz, n = ld(normal, p).xyz;
    if (u_to_object != 0) {
        xh = u_inv * (xh - u_t);
        n = u_rinv * n;
        float l = length(n);
        n = l > 0.0 ? n / l : vec3(0.0);
    }
    o0 = vec4(xh, 0.0);
    o1 = vec4(n, 0.0);
}
