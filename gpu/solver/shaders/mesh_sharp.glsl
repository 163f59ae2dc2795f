// A resident body's sharp features at a substep's start (core/mesh_pairs.c sharp_update, in
// float): item e < u_ne is body edge e, its texel (1, ...) when sharp: a boundary or non-manifold
// edge, or a convex one (its second triangle's far vertex behind its first's plane) whose
// triangles' normals at the start turn by more than 30 degrees (cos below 0.866); item
// u_ne + v is vertex v, sharp when one of its edges is. Edges, triangles and vertices are the
// mesh textures' global indices (wg_mesh.h).
uniform sampler2D mesh_vert;   // 3 texels a vertex: start, end, velocity
uniform sampler2D mesh_tri;    // 3 a triangle: vertex indices, normal at start, at end
uniform sampler2D bedge;       // 2 an edge: (r, s, t1, t2 or -1), (non-manifold, -, -, -)
uniform sampler2D btri;        // 1 a triangle: its edges k = (vertex k, vertex k + 1), -
uniform sampler2D bvrow;       // 1 a vertex: (first, end) of its triangles in bvlist
uniform sampler2D bvlist;      // the vertices' triangles
uniform int u_ne;
out vec4 o0;

const float SHARP_COS = 0.866;

bool edge_sharp(int e) {
    vec4 q = ld(bedge, 2 * e);
    if (q.w < 0.0 || ld(bedge, 2 * e + 1).x != 0.0) return true;
    int t1 = int(q.z), t2 = int(q.w), r = int(q.x), s = int(q.y);
    vec3 n1 = ld(mesh_tri, 3 * t1 + 1).xyz, n2 = ld(mesh_tri, 3 * t2 + 1).xyz;
    ivec3 v = ivec3(ld(mesh_tri, 3 * t2).xyz);
    int o = v.x != r && v.x != s ? v.x : v.y != r && v.y != s ? v.y : v.z != r && v.z != s ? v.z : v.x;
    vec3 d = ld(mesh_vert, 3 * o).xyz - ld(mesh_vert, 3 * r).xyz;
    return dot(n1, n2) < SHARP_COS && dot(d, n1) < 0.0;
}

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    if (i < u_ne) { o0 = vec4(edge_sharp(i) ? 1.0 : 0.0, 0.0, 0.0, 0.0); return; }
    int v = i - u_ne;
    vec4 row = ld(bvrow, v);
    float sharp = 0.0;
    for (int j = int(row.x); j < int(row.y) && sharp == 0.0; ++j) {
        int t = int(ld(bvlist, j).x);
        ivec3 tv = ivec3(ld(mesh_tri, 3 * t).xyz);
        vec3 te = ld(btri, t).xyz;
        for (int k = 0; k < 3; ++k)
            if ((tv[k] == v || tv[(k + 1) % 3] == v) && edge_sharp(int(te[k]))) sharp = 1.0;
    }
    o0 = vec4(sharp, 0.0, 0.0, 0.0);
}
