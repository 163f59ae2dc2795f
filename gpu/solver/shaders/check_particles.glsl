// Per particle, the step's checks (core/step.c, state.c): (m v.v / 2, -m g.x, the largest
// |coordinate| of x and v (+inf when one is not finite), v.v), reduced as (sum, sum, max, max).
uniform sampler2D x;
uniform sampler2D v;
uniform sampler2D mass; // (m, 1/m)
uniform vec3 u_gravity;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 xi = ld(x, i).xyz, vi = ld(v, i).xyz;
    float m = ld(mass, i).x;
    float big = 0.0;
    if (!finite3(xi) || !finite3(vi)) big = uintBitsToFloat(0x7f800000u);
    else big = max(max(max(abs(xi.x), abs(xi.y)), max(abs(xi.z), abs(vi.x))), max(abs(vi.y), abs(vi.z)));
    float vv = dot(vi, vi);
    o0 = vec4(0.5 * m * vv, -m * dot(u_gravity, xi), big, vv);
}
