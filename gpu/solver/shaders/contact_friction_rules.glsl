// Included by contact_friction, contact_recheck and contact_end (#pragma weft include
// contact_friction_rules).
// ---- friction helpers (core/collide.c)
mat3 free_projector(vec3 n0, vec3 n1, int cnt) {
    mat3 S = mat3(1.0) - outerProduct(n0, n0);
    if (cnt == 2) {
        vec3 e;
        ortho(n0, n1, e);
        S -= outerProduct(e, e);
    }
    return S;
}
vec2 contact_impulses(vec3 r, vec3 n0, vec3 n1, int cnt) {
    float r1 = dot(r, n0);
    if (cnt == 1) return vec2(r1, 0.0);
    float r2 = dot(r, n1), c = dot(n0, n1), g = 1.0 - c * c;
    return vec2((r1 - c * r2) / g, (r2 - c * r1) / g);
}
bool holds(float bound, float held) { return bound > 0.0 && held <= bound * (1.0 + 1e-9); }
