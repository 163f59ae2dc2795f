// A body's frame end from a host buffer's floats (raw: float k of the copied range at texel
// (k mod u_rw, k div u_rw)): vertex i - u_v0 of the mesh at global vertices [u_v0, u_v1) is the 3
// floats from float (i - u_v0) u_stride; every other vertex keeps body_to's texel.
uniform sampler2D raw;
uniform sampler2D body_to;
uniform int u_v0, u_v1, u_stride, u_rw;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    if (i < u_v0 || i >= u_v1) { o0 = ld(body_to, i); return; }
    int b = (i - u_v0) * u_stride;
    vec3 p;
    for (int c = 0; c < 3; ++c) p[c] = texelFetch(raw, ivec2((b + c) % u_rw, (b + c) / u_rw), 0).x;
    o0 = vec4(p, 0.0);
}
