// Per vertex of one mesh (global vertices [u_v0, u_v1); zero elsewhere), a max reduction's input:
// u_mode 0: the speed |velocity| (src: mesh_verts.glsl's output; ref unread); u_mode 1: a bad
// position (src: 1 texel a vertex; NaN, Inf or |coordinate| >= 1e30) as u_v1 - i, so that the
// maximum names the first bad vertex, and in y 1 where src's position differs from ref's (1 texel
// a vertex) in any bit, so that the maximum says whether the mesh moves.
uniform sampler2D src;
uniform sampler2D ref;
uniform int u_mode, u_v0, u_v1;
out vec4 o0;

void main() {
    int i = self_index();
    o0 = vec4(0.0);
    if (i >= u_n || i < u_v0 || i >= u_v1) return;
    if (u_mode == 0) {
        o0.x = length(ld(src, 3 * i + 2).xyz);
    } else {
        vec3 p = ld(src, i).xyz;
        bool bad = any(isnan(p)) || any(isinf(p)) || any(greaterThanEqual(abs(p), vec3(1e30)));
        o0.x = bad ? float(u_v1 - i) : 0.0;
        o0.y = any(notEqual(floatBitsToUint(p), floatBitsToUint(ld(ref, i).xyz))) ? 1.0 : 0.0;
    }
}
