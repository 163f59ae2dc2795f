// A resident body's triangles at a substep: three texels a triangle, its vertices' indices (from
// tri_idx), its unit normal (b - a) x (c - a) at the substep's start and at its end (zero for a
// degenerate one), as core/mesh_collider.c's tri_normals in float.
uniform sampler2D tri_idx;     // (vertex indices, thickness), 1 texel a triangle
uniform sampler2D vert;        // mesh_verts.glsl's output
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    int t = i / 3, c = i - 3 * t;
    vec4 q = ld(tri_idx, t);
    if (c == 0) { o0 = vec4(q.xyz, 0.0); return; }
    ivec3 v = ivec3(q.xyz);
    int e = c - 1;
    vec3 a = ld(vert, 3 * v.x + e).xyz;
    vec3 n = cross(ld(vert, 3 * v.y + e).xyz - a, ld(vert, 3 * v.z + e).xyz - a);
    float l = length(n);
    o0 = vec4(l > 0.0 ? n / l : vec3(0.0), 0.0);
}
