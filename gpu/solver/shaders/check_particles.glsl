// Per particle, the step's checks (core/step.c, state.c): (m v.v / 2, -m g.x, the largest
// |coordinate| of x and v (+inf when one is not finite), v.v), reduced as (sum, sum, max, max).
uniform sampler2D t0;   // x
uniform sampler2D t1;   // v
uniform sampler2D t2;   // mass (m, 1/m)
uniform vec3 u_gravity;
out vec4 o0;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); return; }
    vec3 x = ld(t0, i).xyz, v = ld(t1, i).xyz;
    float m = ld(t2, i).x;
    float big = 0.0;
    if (!finite3(x) || !finite3(v)) big = uintBitsToFloat(0x7f800000u);
    else big = max(max(max(abs(x.x), abs(x.y)), max(abs(x.z), abs(v.x))), max(abs(v.y), abs(v.z)));
    float vv = dot(v, v);
    o0 = vec4(0.5 * m * vv, -m * dot(u_gravity, x), big, vv);
}
