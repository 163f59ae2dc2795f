// Per particle, the line search's first step (core/newton.c): its start w~0 = z + S (-v*) (the
// prescribed part in full, the free particles at x_n: x(-v*) = x_n, bdf2.h's v*; backward Euler:
// v_n) and its direction d = w1 - w~0 towards the first solve's result w1. Outputs: o0 = w~0, o1 = d.
uniform sampler2D v;            // v* (backward Euler: v_n)
uniform sampler2D w1;
uniform sampler2D S0;
uniform sampler2D S1;
uniform sampler2D z;
out vec4 o0;
out vec4 o1;

void main() {
    int i = self_index();
    if (i >= u_n) { o0 = vec4(0.0); o1 = vec4(0.0); return; }
    vec3 w0 = ld(z, i).xyz + filter_apply(ld(S0, i), ld(S1, i), -ld(v, i).xyz);
    o0 = vec4(w0, 0.0);
    o1 = vec4(ld(w1, i).xyz - w0, 0.0);
}
